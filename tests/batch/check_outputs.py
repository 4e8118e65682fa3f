#!/usr/bin/env python3
"""Checks that a gslift output folder holds only complete files (issue 16's fault tests).

    check_outputs.py run DIR      the results folder of `gslift run`
    check_outputs.py batch ROOT   the results root of `gslift batch`

Complete means: every file is either absent or fully written. JSON parses; a PNG has its
signature, every chunk's CRC and an IEND; a PLY's header parses and the file holds exactly the
bytes its header declares. Files named like write_atomically's temporaries
(<stem>.tmp-<pid>-<n><ext>) are unfinished writes that nothing reads: they may remain after a
kill -9 and are reported, not judged. A batch root additionally: every capture folder (a name
without a leading '.') holds exactly one marker, _DONE or _FAILED.json, and a _DONE capture has a
run.json whose status is "ok"; unfinished captures live only in hidden .<name>.partial folders.
Exit status 0 when complete, 1 with one line per problem otherwise.
"""
import json
import os
import re
import struct
import sys
import zlib

TEMP = re.compile(r"\.tmp-\d+-\d+")
PLY_SIZES = {"char": 1, "uchar": 1, "int8": 1, "uint8": 1, "short": 2, "ushort": 2,
             "int16": 2, "uint16": 2, "int": 4, "uint": 4, "int32": 4, "uint32": 4,
             "float": 4, "float32": 4, "double": 8, "float64": 8}


def check_png(data):
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return "no PNG signature"
    at = 8
    while at + 12 <= len(data):
        (length,) = struct.unpack(">I", data[at:at + 4])
        kind = data[at + 4:at + 8]
        end = at + 12 + length
        if end > len(data):
            return "chunk %r runs past the end" % kind
        (crc,) = struct.unpack(">I", data[end - 4:end])
        if zlib.crc32(data[at + 4:end - 4]) & 0xffffffff != crc:
            return "chunk %r has a bad CRC" % kind
        if kind == b"IEND":
            return None if end == len(data) else "bytes after IEND"
        at = end
    return "no IEND chunk"


def check_ply(data):
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        return "no PLY header"
    size, count, row = end + len(b"end_header\n"), None, 0
    for line in data[:end].decode("ascii", "replace").splitlines():
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            count = int(words[2])
        elif words[:1] == ["element"]:
            return "unexpected element %s" % words[1]
        elif words[:1] == ["property"]:
            row += PLY_SIZES[words[1]]
    if "binary" not in data[:end].decode("ascii", "replace"):
        return None
    if count is None or size + count * row != len(data):
        return "holds %d bytes, its header declares %s" % (
            len(data), "no vertices" if count is None else size + count * row)
    return None


def check_file(path):
    with open(path, "rb") as f:
        data = f.read()
    try:
        if path.endswith(".json") or os.path.basename(path) == "_DONE":
            json.loads(data)
            return None
    except ValueError as e:
        return "not JSON: %s" % e
    if path.endswith(".png"):
        return check_png(data)
    if path.endswith(".ply"):
        return check_ply(data)
    return None


def check_tree(top, problems, temps):
    files = 0
    for folder, _, names in os.walk(top):
        for name in names:
            path = os.path.join(folder, name)
            if TEMP.search(name):
                temps.append(path)
                continue
            files += 1
            why = check_file(path)
            if why:
                problems.append("%s: %s" % (path, why))
    return files


def main():
    mode, top = sys.argv[1], sys.argv[2]
    problems, temps = [], []
    if not os.path.isdir(top):
        print("complete: %s does not exist yet" % top)
        return 0
    if mode == "run":
        files = check_tree(top, problems, temps)
    else:
        files = 0
        for name in sorted(os.listdir(top)):
            path = os.path.join(top, name)
            if name.startswith("."):
                continue  # .<name>.partial (unfinished, redone by a rerun), .summary.lock
            if not os.path.isdir(path):
                if TEMP.search(name):
                    temps.append(path)
                    continue
                files += 1
                why = check_file(path)
                if why:
                    problems.append("%s: %s" % (path, why))
                continue
            markers = [m for m in ("_DONE", "_FAILED.json") if os.path.exists(os.path.join(path, m))]
            if len(markers) != 1:
                problems.append("%s: %d markers (%s)" % (path, len(markers), ", ".join(markers)))
            inner = []
            files += check_tree(path, problems, inner)
            problems += ["%s: a temporary file in a finished capture" % t for t in inner]
            if markers == ["_DONE"]:
                try:
                    with open(os.path.join(path, "run.json")) as f:
                        if json.load(f)["run"].get("status") != "ok":
                            problems.append("%s: _DONE but run.json status is not ok" % path)
                except (OSError, ValueError, KeyError) as e:
                    problems.append("%s: _DONE but no readable run.json (%s)" % (path, e))
    for p in problems:
        print("INCOMPLETE " + p)
    print("%s: %d files complete, %d unfinished temporaries, %d problems" %
          (top, files, len(temps), len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
