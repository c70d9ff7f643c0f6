#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The include graph of lib/ runs one way: every #include of lib/src and lib/include/okid goes to
the includer's own folder or to a lower one (docs/design.md, "Layers"), names its folder
("numerics/dense.h", "okid/modal.h"), and the graph has no cycle. Exit status 1 with one line per
offending include, 0 when the graph is clean.

    python3 tests/check_include_layers.py [path/to/lib]

Layers, lowest first; a folder may include the folders listed for it and the base headers:
  numerics                       nothing else
  model                          numerics
  pipeline                       numerics
  quality                        numerics, pipeline
  identifier                     numerics, pipeline, quality
  analysis                       numerics, pipeline, quality, identifier
A public header belongs to the folder that implements it (PUBLIC below; a new one must be added
there); src/status.c, at the top of src/, may include only the base headers.
"""
import os
import re
import sys

LOWER = {
    "base": set(),
    "numerics": {"base"},
    "model": {"base", "numerics"},
    "pipeline": {"base", "numerics"},
    "quality": {"base", "numerics", "pipeline"},
    "identifier": {"base", "numerics", "pipeline", "quality"},
    "analysis": {"base", "numerics", "pipeline", "quality", "identifier"},
    "status": {"base"},
    "top": {"base", "model", "pipeline", "quality", "identifier", "analysis"},
}
# Public headers: the layer they belong to.
PUBLIC = {
    "okid_build_config.h": "base",  # generated from okid_build_config.h.in
    "limits.h": "base",
    "types.h": "base",
    "sizes.h": "base",
    "status.h": "base",
    "model.h": "model",
    "random.h": "model",
    "modal.h": "pipeline",
    "lifting.h": "pipeline",
    "ring_storage.h": "pipeline",
    "correlation_storage.h": "pipeline",
    "modal_indicators.h": "quality",
    "identifier.h": "identifier",
    "identifier_storage.h": "identifier",
    "refine.h": "analysis",
    "refine_storage.h": "analysis",
    "stabilization.h": "analysis",
    "mode_selection.h": "analysis",
    "ambient.h": "analysis",
    "ambient_storage.h": "analysis",
    "okid.h": "top",
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def main(lib):
    src, inc = os.path.join(lib, "src"), os.path.join(lib, "include", "okid")
    nodes = {}  # node name -> (layer, path)
    for name in sorted(os.listdir(inc)):
        if name.endswith(".h.in"):
            name = name[:-3]
        elif not name.endswith(".h"):
            continue
        nodes["okid/" + name] = (PUBLIC.get(name), os.path.join(inc, name))
    for folder, _, files in os.walk(src):
        for f in sorted(files):
            if f.endswith((".c", ".h", ".cpp")):
                rel = os.path.relpath(os.path.join(folder, f), src).replace(os.sep, "/")
                layer = rel.split("/")[0] if "/" in rel else "status"
                nodes[rel] = (layer, os.path.join(folder, f))
    errors, edges = [], {}
    for node, (layer, path) in sorted(nodes.items()):
        if layer is None:
            errors.append(f"{node}: a public header without a layer: add it to PUBLIC in {__file__}")
            continue
        if layer not in LOWER:
            errors.append(f"{node}: folder {layer}/ is not a layer: add it to LOWER in {__file__}")
            continue
        if not os.path.exists(path):  # okid_build_config.h: generated, includes nothing
            continue
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
        edges[node] = []
        for target in INCLUDE.findall(text):
            if target not in nodes:
                errors.append(f"{node}: #include \"{target}\" names no folder of lib/src or okid/ "
                              f"(write \"folder/{os.path.basename(target)}\")")
                continue
            if node.startswith("okid/") and not target.startswith("okid/"):
                errors.append(f"{node}: a public header includes the private \"{target}\"")
                continue
            tlayer = nodes[target][0]
            if tlayer != layer and tlayer not in LOWER[layer]:
                errors.append(f"{node}: #include \"{target}\" runs up from {layer} to {tlayer}")
            edges[node].append(target)
    # no cycle (an include guard hides one from the compiler, not from the reader)
    state = {}

    def visit(n, stack):
        state[n] = 1
        for t in edges.get(n, []):
            if state.get(t) == 1:
                errors.append("include cycle: " + " -> ".join(stack[stack.index(t):] + [t]))
            elif t not in state:
                visit(t, stack + [t])
        state[n] = 2

    for n in sorted(edges):
        if n not in state:
            visit(n, [n])
    for e in errors:
        print(e)
    print(f"{len(nodes)} files, {sum(len(v) for v in edges.values())} includes: "
          + (f"{len(errors)} problems" if errors else "every include runs down"))
    return 1 if errors else 0


if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "lib")))
