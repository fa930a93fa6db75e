#!/usr/bin/env python3
"""Checks that every #include between vpm's source folders points down the layers.

    core < config < io < scene < transport < photon < render < analysis < tools

A file in lib/<folder>/ (or tools/, bench/, fuzz/) may include headers of its own folder and of
folders below it, never above. Because the order is strict, a folder-level cycle is impossible
once no arrow points up. Prints the folder-level include graph with --graph.

usage: python3 scripts/check_layers.py [--graph] [ROOT]      (exit 1 on an upward include)
"""
import pathlib
import re
import sys

LAYERS = ["core", "config", "io", "scene", "transport", "photon", "render", "analysis", "tools"]
RANK = {name: i for i, name in enumerate(LAYERS)}
# Front ends outside lib/ sit on top of everything.
TOP_FOLDERS = {"tools": "tools", "bench": "tools", "fuzz": "tools"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/[^"]+"', re.MULTILINE)


def folder_of(root: pathlib.Path, path: pathlib.Path) -> str:
    rel = path.relative_to(root).parts
    if rel[0] == "lib":
        return rel[1]
    return TOP_FOLDERS[rel[0]]


def main(argv):
    show_graph = "--graph" in argv
    args = [a for a in argv if not a.startswith("--")]
    root = pathlib.Path(args[0] if args else pathlib.Path(__file__).resolve().parent.parent)
    sources = [p for top in ["lib", *TOP_FOLDERS] for p in (root / top).rglob("*")
               if p.suffix in (".h", ".cpp") and p.is_file()]
    if not sources:
        print(f"check_layers: no sources under {root}", file=sys.stderr)
        return 2
    edges = {}
    errors = []
    for path in sorted(sources):
        src = folder_of(root, path)
        if src not in RANK:
            errors.append(f"{path.relative_to(root)}: folder '{src}' is not a known layer ({', '.join(LAYERS)})")
            continue
        for match in INCLUDE.finditer(path.read_text(errors="replace")):
            dst = match.group(1)
            if dst not in RANK:
                continue   # a third-party header such as "nanoflann.hpp" has no folder
            if dst != src:
                edges.setdefault((src, dst), 0)
                edges[(src, dst)] += 1
            if RANK[dst] > RANK[src]:
                line = path.read_text(errors="replace")[: match.start()].count("\n") + 1
                errors.append(f"{path.relative_to(root)}:{line}: {src}/ includes {match.group(0).split()[-1]} "
                              f"from {dst}/, a layer above it")
    if show_graph:
        for (src, dst), n in sorted(edges.items(), key=lambda e: (RANK[e[0][0]], RANK[e[0][1]])):
            print(f"{src:>9} -> {dst:<9} {n} include(s)")
    for e in errors:
        print(e, file=sys.stderr)
    print(f"check_layers: {len(sources)} files, {sum(edges.values())} includes across folders, "
          f"{len(errors)} upward" + ("" if errors else " (order: " + " < ".join(LAYERS) + ")"))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
