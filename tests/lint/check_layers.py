#!/usr/bin/env python3
"""Fails when a file under sim/ or render/ includes a file of a higher layer.

Usage: check_layers.py ROOT LAYERS
ROOT is the repository root, LAYERS the layer list (tests/lint/layers.txt, which says how
paths are assigned to layers). Every violation is reported as FILE:LINE with both layers;
the exit status is 1 if there is any, 2 for a bad layer list.
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*"((?:sim|render)/[^"]+)"')
SOURCE_DIRS = ("sim", "render")
SUFFIXES = (".h", ".cpp")


def read_layers(path):
    """Returns (names in order, {folder: rank}, {stem: rank})."""
    names, folders, stems = [], {}, {}
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            name, sep, paths = line.partition(":")
            if not sep or not paths.split():
                sys.exit(f"{path}:{number}: expected 'layer: path ...', got '{line}'")
            rank = len(names)
            names.append(name.strip())
            for p in paths.split():
                table = folders if p.endswith("/") else stems
                if p in table:
                    sys.exit(f"{path}:{number}: '{p}' is already in layer {names[table[p]]}")
                table[p] = rank
    return names, folders, stems


def layer_of(path, folders, stems):
    """The rank of a repository-relative path, or None when no line claims it."""
    stem = os.path.splitext(path)[0]
    if stem in stems:
        return stems[stem]
    best = None
    for folder, rank in folders.items():
        if path.startswith(folder) and (best is None or len(folder) > len(best[0])):
            best = (folder, rank)
    return best[1] if best else None


def sources(root):
    for top in SOURCE_DIRS:
        for folder, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if name.endswith(SUFFIXES):
                    full = os.path.join(folder, name)
                    yield os.path.relpath(full, root).replace(os.sep, "/"), full


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    root, layers_path = sys.argv[1], sys.argv[2]
    names, folders, stems = read_layers(layers_path)
    problems, checked = [], 0
    for rel, full in sources(root):
        own = layer_of(rel, folders, stems)
        if own is None:
            problems.append(f"{rel}: no layer in {layers_path} holds it")
            continue
        checked += 1
        with open(full, encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                target = m.group(1)
                other = layer_of(target, folders, stems)
                if other is not None and other > own:
                    problems.append(
                        f"{rel}:{number}: includes {target}: layer '{names[own]}' may not "
                        f"include layer '{names[other]}', which is above it")
    if checked == 0:
        problems.append(f"no sources found under {root}/{{{','.join(SOURCE_DIRS)}}}")
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} layer problem(s); the layer order is in {layers_path}")
        return 1
    print(f"{checked} files obey the {len(names)} layers of {layers_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
