#!/usr/bin/env python3
"""Report import cycles between the top-level modules of each crate.

A module `m` of a crate depends on module `n` when any file under `src/m` (or `src/m.rs`)
names `crate::n` (in a `use` or a path), or, inside `src/m/`, a sibling reaches `super::n`
from `src/m/mod.rs`'s children is *not* counted (that stays inside `m`). Files inside one
module directory are checked the same way one level down, so `collision::world::state`
reaching `collision::world::sink` and back is a cycle too.

Usage: tools/lint/module_cycles.py [crates/...]; exits 1 and lists each cycle if any.
"""
import os
import re
import sys
from collections import defaultdict

START = re.compile(r"\b(crate|super)::")


def paths(text):
    """Every `crate::…` / `super::…` path as (kind, rest), rest starting with `::`; a brace
    group is kept whole (nested groups included)."""
    out = []
    for m in START.finditer(text):
        i = m.end()
        if i < len(text) and text[i] == "{":
            depth, j = 0, i
            while j < len(text):
                depth += {"{": 1, "}": -1}.get(text[j], 0)
                j += 1
                if depth == 0:
                    break
            out.append((m.group(1), "::" + text[i:j]))
        else:
            word = re.match(r"[A-Za-z_][A-Za-z0-9_]*(?:::[A-Za-z_][A-Za-z0-9_]*)*", text[i:])
            if word:
                out.append((m.group(1), "::" + word.group(0)))
    return out


def split_top(inner):
    parts, depth, cur = [], 0, ""
    for ch in inner:
        if ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
            continue
        depth += {"{": 1, "}": -1}.get(ch, 0)
        cur += ch
    parts.append(cur)
    return [p.strip() for p in parts if p.strip()]


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return "\n".join(line.split("//")[0] for line in text.splitlines())


def scc(graph):
    index, low, stack, on, out, n = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = n[0]
        n[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def names_in(group):
    """`{a, b::c, d}` → [a, b, d]; `::a::b` → [a]."""
    if group.startswith("::{"):
        return [p.split("::")[0].split(" ")[0] for p in split_top(group[3:-1])]
    return [group.split("::")[1]]


def module_graph(directory):
    """Edges between the children (files/dirs) of one module directory."""
    children = {}
    for entry in os.listdir(directory):
        full = os.path.join(directory, entry)
        if entry in ("lib.rs", "main.rs", "mod.rs"):
            continue
        if entry.endswith(".rs"):
            children[entry[:-3]] = [full]
        elif os.path.isdir(full):
            files = []
            for root, _, fs in os.walk(full):
                files += [os.path.join(root, f) for f in fs if f.endswith(".rs")]
            children[entry] = files
    return children


def edges(children, prefix_kind, crate_root):
    graph = defaultdict(set)
    for name, files in children.items():
        graph[name]
        for f in files:
            text = strip_comments(open(f).read())
            depth = os.path.relpath(f, crate_root).count(os.sep)
            for kind, rest in paths(text):
                if prefix_kind == "crate" and kind == "crate":
                    targets = names_in(rest)
                elif prefix_kind == "super" and kind == "super":
                    # `super::x` from a direct child file of this directory
                    if os.path.dirname(f) != os.path.dirname(files[0]) or name not in children:
                        continue
                    if f.endswith("mod.rs"):
                        continue
                    targets = names_in(rest)
                elif prefix_kind != "crate" and kind == "crate":
                    parts = rest.split("::")[1:]
                    if parts[: len(prefix_kind)] != prefix_kind or len(parts) <= len(prefix_kind):
                        continue
                    tail = "::" + "::".join(parts[len(prefix_kind):])
                    targets = names_in(tail) if tail.startswith("::{") else [parts[len(prefix_kind)]]
                else:
                    continue
                for t in targets:
                    if t in children and t != name:
                        graph[name].add(t)
    return graph


def main():
    roots = sys.argv[1:] or sorted(
        os.path.join("crates", c) for c in os.listdir("crates") if os.path.isdir(os.path.join("crates", c, "src"))
    ) + ["python"]
    found = []
    for crate in roots:
        src = os.path.join(crate, "src")
        if not os.path.isdir(src):
            continue
        top = module_graph(src)
        for comp in scc(edges(top, "crate", src)):
            found.append(f"{crate}: {' <-> '.join(comp)}")
        for name, files in top.items():
            sub = os.path.join(src, name)
            if os.path.isdir(sub):
                kids = module_graph(sub)
                g = edges(kids, [name], src)
                g2 = edges(kids, "super", src)
                for k, v in g2.items():
                    g[k] |= v
                for comp in scc(g):
                    found.append(f"{crate}: {name}::{{{', '.join(comp)}}}")
    for line in found:
        print(line)
    sys.exit(1 if found else 0)


if __name__ == "__main__":
    main()
