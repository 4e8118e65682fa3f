#!/usr/bin/env python3
"""The layers of docs/architecture.md as a test: reads every #include "..." of the library's
sources and fails on an edge the architecture does not allow, naming file, line and rule.

    check_layers.py SOURCE_DIR [KNOWN]
    check_layers.py --expect-new N SOURCE_DIR   (its own test: exactly N edges must be found)

KNOWN (tests/layers/known_edges.txt) lists the edges that break a rule today, one
"file -> include" a line, each to be removed by moving code (issue 27): an edge not in it fails,
and so does a listed edge that no longer exists, so the list only shrinks.
"""
import pathlib
import re
import sys

# Families every other family may use: the port types (scene/), the rasterizer and model
# (splat/), the capture readers (ingest/).
SHARED_FAMILIES = {"scene", "splat", "ingest"}
# Files of a family that adapt its algorithms to the runtime (ports, params, commands): they may
# also include runtime/ and graph/. Everything else in nodes/ is an algorithm over plain data.
ADAPTER = re.compile(r"^(register|.*_nodes|.*_command|segment_session)\.(hpp|cpp)$")

# Top-level layers, lowest first: each may include itself and the layers listed.
LAYERS = {
    "base": {"base"},
    "param": {"base", "param"},
    "graph": {"base", "param", "graph"},
    "runtime": {"base", "param", "graph", "runtime"},
    "report": {"base", "param", "graph", "runtime", "report"},
    "cli": {"base", "param", "graph", "runtime", "report", "cli"},
    # gslift view: above the node families it shows (a program main() adds, as segment is)
    "viewer": {"base", "param", "runtime", "nodes", "viewer"},
}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def allowed(path: pathlib.PurePosixPath, target: str):
    """None when `path` may include `target`, else the rule it breaks."""
    parts = path.parts
    top = target.split("/")[0]
    if parts[0] in LAYERS:
        if top in LAYERS[parts[0]]:
            return None
        return f"{parts[0]}/ may include only {', '.join(sorted(LAYERS[parts[0]]))}"
    if parts[0] == "nodes":
        if len(parts) == 2:  # nodes/builtin.*: the catalogue of every family
            return None if top in ("base", "param", "graph", "runtime", "nodes") else \
                "nodes/builtin may include base, param, graph, runtime and the families"
        family = parts[1]
        adapter = bool(ADAPTER.match(parts[-1]))
        if top in ("base", "param"):
            return None
        if top in ("runtime", "graph"):
            return None if adapter else \
                f"an algorithm ({family}/) may not include {top}/: only register.* and *_nodes.* adapt to it"
        if top == "nodes":
            other = target.split("/")[1]
            if other == family or other in SHARED_FAMILIES:
                return None
            return f"nodes/{family}/ may not include another family ({other}/) but scene/, splat/, ingest/"
        return f"nodes/ may not include {top}/"
    return None  # app/, tests/, bench/, fuzz/: the composition roots and tools


def main(src: pathlib.Path, known_file) -> int:
    known = set()
    if known_file:
        for line in pathlib.Path(known_file).read_text().splitlines():
            if line.strip() and not line.startswith("#"):
                known.add(line.strip())
    broken = []
    seen = set()
    checked = 0
    for top in list(LAYERS) + ["nodes"]:
        root = src / top
        if not root.is_dir():
            continue
        for f in sorted(root.rglob("*")):
            if f.suffix not in (".hpp", ".cpp", ".h"):
                continue
            rel = pathlib.PurePosixPath(f.relative_to(src).as_posix())
            for n, line in enumerate(f.read_text(errors="replace").splitlines(), 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                checked += 1
                why = allowed(rel, m.group(1))
                if not why:
                    continue
                edge = f"{rel} -> {m.group(1)}"
                seen.add(edge)
                if edge not in known:
                    broken.append(f"{rel}:{n}: includes \"{m.group(1)}\": {why}")
    stale = sorted(known - seen)
    for b in broken:
        print(b)
    for e in stale:
        print(f"{e}: listed in {known_file} but gone: remove the line")
    print(f"layers: {checked} includes checked, {len(seen)} against the rules "
          f"({len(seen) - len(broken)} known), {len(broken)} new, {len(stale)} stale")
    return 1 if broken or stale else 0


if __name__ == "__main__":
    args = sys.argv[1:]
    if args[0] == "--expect-new":
        expected = int(args[1])
        import contextlib
        import io
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            main(pathlib.Path(args[2]), None)
        found = [l for l in out.getvalue().splitlines() if not l.startswith("layers:")]
        print(out.getvalue(), end="")
        sys.exit(0 if len(found) == expected else 1)
    sys.exit(main(pathlib.Path(args[0]), args[1] if len(args) > 1 else None))
