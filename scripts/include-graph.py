#!/usr/bin/env python3
"""Lists the include arrows between the folders under src/ and fails on a cycle.

An arrow A -> B means that a file in src/A includes a header of src/B ("B/name.hpp"). The
public headers (src/include/fdmsurf/) are the API every folder may include; they are not a
folder of the engine and are left out. A folder's includes of itself are not arrows.

Usage: scripts/include-graph.py [--dot] [SRC_DIR]
  prints one line per arrow, "from -> to  (N includes: first file)", then the folders in an
  order where each comes after every folder it includes (bottom first); exit 1 with the
  folders of each cycle named when there is one (CI runs this: docs/architecture.md).
  --dot prints the graph in Graphviz's format instead.
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def arrows(src):
    folders = sorted(d for d in os.listdir(src)
                     if os.path.isdir(os.path.join(src, d)) and d != "include")
    found = {}  # (from, to) -> [count, first file]
    for folder in folders:
        for root, _, files in os.walk(os.path.join(src, folder)):
            for name in sorted(files):
                if not name.endswith((".cpp", ".hpp", ".h", ".inl")):
                    continue
                path = os.path.join(root, name)
                with open(path, encoding="utf-8", errors="replace") as f:
                    text = f.read()
                for target in INCLUDE.findall(text):
                    head = target.split("/", 1)[0]
                    if "/" in target and head in folders and head != folder:
                        entry = found.setdefault((folder, head), [0, os.path.relpath(path, src)])
                        entry[0] += 1
    return folders, found


def cycles(folders, found):
    """Strongly connected components of more than one folder (Tarjan)."""
    graph = {f: sorted(t for (s, t) in found if s == f) for f in folders}
    index, low, on_stack, stack, result = {}, {}, set(), [], []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
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
                result.append(sorted(component))

    for f in folders:
        if f not in index:
            visit(f)
    return result, graph


def layers(folders, graph):
    """Each folder's height: 0 for one that includes no other folder."""
    height = {}

    def h(v):
        if v not in height:
            height[v] = 0
            height[v] = 1 + max((h(w) for w in graph[v]), default=-1)
        return height[v]

    for f in folders:
        h(f)
    return height


def main(argv):
    dot = "--dot" in argv
    rest = [a for a in argv if a != "--dot"]
    src = rest[0] if rest else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")
    folders, found = arrows(src)
    cyc, graph = cycles(folders, found)
    if dot:
        print("digraph src {")
        for (s, t), (n, _) in sorted(found.items()):
            print(f'  "{s}" -> "{t}" [label={n}];')
        print("}")
    else:
        for (s, t), (n, first) in sorted(found.items()):
            print(f"{s} -> {t}  ({n} include{'s' if n != 1 else ''}: {first})")
        if not cyc:
            height = layers(folders, graph)
            print("layers, bottom first:")
            for level in range(max(height.values(), default=0) + 1):
                print(f"  {level}: " + " ".join(f for f in folders if height[f] == level))
    if cyc:
        for component in cyc:
            inside = [f"{s} -> {t}" for (s, t) in sorted(found) if s in component and t in component]
            print("include-graph: cycle between " + ", ".join(component) + ": " + "; ".join(inside),
                  file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
