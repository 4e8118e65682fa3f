#!/usr/bin/env python3
"""Writes inria_degree1.ply the way the reference 3DGS code (GaussianModel.save_ply with plyfile)
does: properties x y z nx ny nz f_dc_0..2 f_rest_0..8 opacity scale_0..2 rot_0..3, float32,
binary little endian, one 'vertex' element. Property p of vertex i holds 100 i + p, so the test can
check that every field lands where the INRIA layout says. Only the standard library is used."""
import struct
from pathlib import Path

names = ["x", "y", "z", "nx", "ny", "nz"] + [f"f_dc_{i}" for i in range(3)] + \
        [f"f_rest_{i}" for i in range(9)] + ["opacity"] + [f"scale_{i}" for i in range(3)] + \
        [f"rot_{i}" for i in range(4)]
header = "ply\nformat binary_little_endian 1.0\nelement vertex 2\n" + \
         "".join(f"property float {n}\n" for n in names) + "end_header\n"
body = b"".join(struct.pack("<f", 100.0 * i + p) for i in range(2) for p in range(len(names)))
Path(__file__).with_name("inria_degree1.ply").write_bytes(header.encode("ascii") + body)
