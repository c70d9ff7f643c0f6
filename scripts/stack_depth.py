#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Worst-case stack depth of library entry points from GCC's -fcallgraph-info=su call graphs.

Usage: stack_depth.py BUILD_DIR ENTRY [ENTRY ...]
Reads every .ci (call graph, frame sizes) and .su file under BUILD_DIR. Fails when a frame is
not static (a VLA or alloca), when the graph recurses, or on an indirect call. Calls out of the
graph (newlib's libm and string functions) are listed: their frames are not in the sum, which the
run-time measurement of bench/firmware/cost_report.c covers.
"""
import pathlib
import re
import sys

NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
FRAME = re.compile(r'\\n(\d+) bytes \((static|dynamic[^)]*)\)')


def load(build_dir):
    frames, calls, not_static = {}, {}, []
    for ci in pathlib.Path(build_dir).rglob("*.ci"):
        for line in ci.read_text().splitlines():
            m = NODE.search(line)
            if m:
                f = FRAME.search(m.group(2))
                if f:
                    frames[m.group(1)] = int(f.group(1))
                    if f.group(2) != "static":
                        not_static.append(m.group(1))
                continue
            m = EDGE.search(line)
            if m:
                calls.setdefault(m.group(1), set()).add(m.group(2))
    for su in pathlib.Path(build_dir).rglob("*.su"):
        for line in su.read_text().splitlines():
            if line.strip() and not line.rstrip().endswith("\tstatic"):
                not_static.append(line)
    return frames, calls, not_static


def resolve(name, frames):
    """A call names a file-local function as 'file:name' in its own file, others by plain name."""
    return name if name in frames else None


def worst(entry, frames, calls, outside, path=()):
    if entry in path:
        raise SystemExit("stack_depth: recursion through " + " -> ".join(path + (entry,)))
    best, best_chain = 0, []
    for callee in sorted(calls.get(entry, ())):
        if callee == "__indirect_call":
            raise SystemExit(f"stack_depth: indirect call in {entry}: depth not bounded by the graph")
        target = resolve(callee, frames)
        if target is None:
            outside.add(callee)
            continue
        depth, chain = worst(target, frames, calls, outside, path + (entry,))
        if depth > best:
            best, best_chain = depth, chain
    return frames[entry] + best, [entry] + best_chain


def main():
    build_dir, entries = sys.argv[1], sys.argv[2:]
    frames, calls, not_static = load(build_dir)
    if not frames:
        raise SystemExit(f"stack_depth: no .ci files under {build_dir}")
    if not_static:
        raise SystemExit("stack_depth: frames that are not static:\n  " + "\n  ".join(not_static))
    print(f"stack: {len(frames)} functions, every frame static (no VLA, no alloca)")
    for entry in entries:
        outside = set()
        depth, chain = worst(entry, frames, calls, outside)
        short = [c.rsplit(":", 1)[-1] for c in chain]
        print(f"stack.{entry} {depth} bytes: " + " > ".join(f"{s} ({frames[c]})" for s, c in zip(short, chain)))
        if outside:
            print(f"  calls out of the library (frames not summed): {', '.join(sorted(outside))}")


if __name__ == "__main__":
    main()
