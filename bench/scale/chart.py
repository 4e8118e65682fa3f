"""bench/scale/run.sh's results: held-out PSNR against steps per capture.

    chart.py RESULTS_CSV OUT_PREFIX VERSION [MACHINE]   -> OUT_PREFIX.{json,csv,svg}
"""
import csv
import json
import sys

rows_in, prefix, version = sys.argv[1], sys.argv[2], sys.argv[3]
machine = sys.argv[4] if len(sys.argv) > 4 else ""
rows = []
for r in csv.DictReader(open(rows_in)):
    def num(key):
        return float(r[key]) if r.get(key) not in (None, "") else None
    # The set's paths are relative to bench/sets; the shared scenes are named as ../shared/data has them.
    rows.append({"capture": r["input"].replace("bench/sets/../../../shared/data/", ""), "steps": int(float(r["recon.iterations"])),
                 "status": r["status"], "error": r.get("error", ""),
                 "gaussians": num("recon.gaussians"), "scene_extent": num("recon.scene_extent"),
                 "train_psnr": num("recon.train_psnr"), "test_psnr": num("recon.test_psnr"),
                 "test_psnr_covered": num("recon.test_psnr_covered"), "seconds": num("total_s")})
captures = list(dict.fromkeys(r["capture"] for r in rows))
steps = sorted({r["steps"] for r in rows})
checks = {}
for c in captures:
    series = sorted((r for r in rows if r["capture"] == c), key=lambda r: r["steps"])
    ok = all(r["status"] == "ok" and (r["gaussians"] or 0) > 0 for r in series)
    psnr = [r["test_psnr"] for r in series]
    # "does not fall": each longer run within 0.1 dB of the best shorter one, or above it.
    rising = ok and all(psnr[i] >= max(psnr[:i]) - 0.1 for i in range(1, len(psnr)))
    checks[c] = {"non_empty": ok, "held_out_psnr_does_not_fall": rising}
json.dump({"benchmark": "scale (issue 29)", "graph": "graphs/examples/reconstruct.yaml",
           "binary": version, "machine": machine, "runs": rows, "checks": checks}, open(prefix + ".json", "w"),
          indent=2)
with open(prefix + ".csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)

# SVG: held-out PSNR (dB) against steps (log axis), one line per capture.
W, H, L, R, T, B = 640, 360, 60, 230, 30, 50
lo = min(r["test_psnr"] for r in rows if r["test_psnr"] is not None) - 1
hi = max(r["test_psnr"] for r in rows if r["test_psnr"] is not None) + 1
import math
def x(s):
    return L + (math.log(s) - math.log(steps[0])) / (math.log(steps[-1]) - math.log(steps[0])) * (W - L - R)
def y(v):
    return T + (hi - v) / (hi - lo) * (H - T - B)
colours = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"]
svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
       f'<text x="{L}" y="18">Held-out PSNR against steps, graphs/examples/reconstruct.yaml ({version})</text>',
       f'<line x1="{L}" y1="{H-B}" x2="{W-R}" y2="{H-B}" stroke="black"/>',
       f'<line x1="{L}" y1="{T}" x2="{L}" y2="{H-B}" stroke="black"/>']
for s in steps:
    svg.append(f'<text x="{x(s):.1f}" y="{H-B+16}" text-anchor="middle">{s}</text>')
svg.append(f'<text x="{(L+W-R)/2:.1f}" y="{H-12}" text-anchor="middle">steps</text>')
for v in range(int(math.ceil(lo)), int(hi) + 1, 2):
    svg.append(f'<text x="{L-6}" y="{y(v)+4:.1f}" text-anchor="end">{v}</text>')
    svg.append(f'<line x1="{L}" y1="{y(v):.1f}" x2="{W-R}" y2="{y(v):.1f}" stroke="#ddd"/>')
svg.append(f'<text x="14" y="{(T+H-B)/2:.1f}" transform="rotate(-90 14 {(T+H-B)/2:.1f})" text-anchor="middle">held-out PSNR (dB)</text>')
for i, c in enumerate(captures):
    col = colours[i % len(colours)]
    pts = [(x(r["steps"]), y(r["test_psnr"])) for r in sorted(rows, key=lambda r: r["steps"])
           if r["capture"] == c and r["test_psnr"] is not None]
    svg.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>' %
               (col, " ".join(f"{a:.1f},{b:.1f}" for a, b in pts)))
    for a, b in pts:
        svg.append(f'<circle cx="{a:.1f}" cy="{b:.1f}" r="3" fill="{col}"/>')
    label = c
    svg.append(f'<rect x="{W-R+12}" y="{T+i*18}" width="10" height="10" fill="{col}"/>')
    svg.append(f'<text x="{W-R+26}" y="{T+i*18+9}">{label}</text>')
svg.append("</svg>")
open(prefix + ".svg", "w").write("\n".join(svg) + "\n")
for c in captures:
    series = [r for r in rows if r["capture"] == c]
    print(c, " ".join(f'{r["steps"]}: {r["test_psnr"]:.2f} dB ({r["gaussians"]:.0f} G, {r["seconds"]:.0f} s)'
                      for r in sorted(series, key=lambda r: r["steps"]) if r["test_psnr"] is not None),
          checks[c])
