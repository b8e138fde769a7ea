#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The rules of docs/ARCHITECTURE.md that the include roots alone do not enforce.

usage: check_architecture.py SOURCE_DIR BUILD_DIR

- No loops between the files of a module: the call graph between the object files of
  each static library (from `nm`: who defines a symbol, who uses it) has no cycle.
- File names are unique in src/, preprocess/ and shaders/.
- GL calls (gl[A-Z]...) only in src/render/.
- No relative includes that climb out of a folder ("../").
- Binding points only from src/render/bindings.h: no layout(binding = <number>) in a
  shader, no bare number as the binding/unit argument of a glBind* call in C.
Prints every violation; exit 1 if there is any.
"""
import collections
import os
import re
import subprocess
import sys

if len(sys.argv) != 3:
    sys.exit("usage: check_architecture.py SOURCE_DIR BUILD_DIR (the build's object files "
             "are read for the loop check, e.g. . build/release)")
src_dir, build_dir = sys.argv[1], sys.argv[2]
problems = []


def object_graph(library):
    out = subprocess.run(["nm", "-A", library], capture_output=True, text=True, check=True).stdout
    defined, used = {}, collections.defaultdict(set)
    for line in out.splitlines():
        parts = line.split()
        if len(parts) < 2:
            continue
        obj = parts[0].split(":")[1]
        kind, symbol = parts[-2], parts[-1]
        if kind in "TDBRC":
            defined[symbol] = obj
        elif kind == "U":
            used[obj].add(symbol)
    graph = collections.defaultdict(set)
    for obj, symbols in used.items():
        for symbol in symbols:
            if symbol in defined and defined[symbol] != obj:
                graph[obj].add(defined[symbol])
    return graph


def cycles(graph):
    """Strongly connected components with more than one file (Tarjan)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(set(graph) | {w for ws in graph.values() for w in ws}):
        if v not in index:
            visit(v)
    return found


libraries = []
for root, _, files in os.walk(build_dir):
    libraries += [os.path.join(root, f) for f in files
                  if f.startswith("libsta_") and f.endswith(".a") and "test" not in f]
if not libraries:
    problems.append(f"no libsta_*.a under {build_dir}: build first")
for library in sorted(libraries):
    for component in cycles(object_graph(library)):
        problems.append(f"{os.path.basename(library)}: files call each other in a loop: "
                        + " <-> ".join(component))

names = collections.defaultdict(list)
code_files = []
for top in ("src", "preprocess", "shaders"):
    for root, _, files in os.walk(os.path.join(src_dir, top)):
        for f in files:
            path = os.path.relpath(os.path.join(root, f), src_dir)
            if f.endswith((".c", ".h", ".comp", ".vert", ".frag", ".glsl")):
                names[f].append(path)
                code_files.append(path)
for name, paths in sorted(names.items()):
    if len(paths) > 1:
        problems.append(f"file name {name} is not unique: {', '.join(sorted(paths))}")

gl_call = re.compile(r"\bgl[A-Z]\w*\s*\(")
climbing_include = re.compile(r'#\s*include\s*"\.\./')
shader_binding = re.compile(r"binding\s*=\s*\d")
c_binding = re.compile(r"\bglBind(?:ImageTexture|TextureUnit|BufferBase|BufferRange)\s*\(\s*"
                       r"(?:GL_[A-Z_]+\s*,\s*)?\d")
comment = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)
for path in sorted(code_files):
    with open(os.path.join(src_dir, path), encoding="utf-8") as f:
        text = comment.sub("", f.read())
    is_c = path.endswith((".c", ".h"))
    if is_c and not path.startswith("src/render/"):
        for m in gl_call.finditer(text):
            problems.append(f"{path}: GL call outside src/render/: {m.group(0)}")
    if climbing_include.search(text):
        problems.append(f"{path}: include climbs out of its folder (../)")
    if not is_c:
        for m in shader_binding.finditer(text):
            problems.append(f"{path}: bare binding number: {m.group(0)}")
    if is_c:
        for m in c_binding.finditer(text):
            problems.append(f"{path}: bare binding number: {m.group(0)}")

for p in problems:
    print(p)
print(f"{len(problems)} architecture problem(s) in {len(code_files)} files, "
      f"{len(libraries)} libraries")
sys.exit(1 if problems else 0)
