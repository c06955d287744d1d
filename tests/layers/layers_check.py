#!/usr/bin/env python3
"""Holds every layer folder to the layers its CMake library links.

Usage: layers_check.py LAYERS_TABLE SOURCE_ROOT

LAYERS_TABLE has one line per layer folder, "folder: lower layers it links" (the build writes it to
build/layers.txt from cmake/dslam_layer.cmake). A file in a layer folder may include headers of its own
folder and of the layers below it, directly or through others; an include of any other layer folder is
reported with the file and line, and the check exits 1.
"""
import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/')


def read_table(path):
    table = {}
    for number, line in enumerate(pathlib.Path(path).read_text().splitlines(), 1):
        if not line.strip():
            continue
        folder, sep, below = line.partition(":")
        if not sep:
            sys.exit(f"{path}:{number}: expected 'folder: layers', got {line!r}")
        table[folder.strip()] = below.split()
    return table


def below(table, folder, seen=None):
    seen = set() if seen is None else seen
    for layer in table.get(folder, []):
        if layer not in seen:
            seen.add(layer)
            below(table, layer, seen)
    return seen


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    table = read_table(sys.argv[1])
    root = pathlib.Path(sys.argv[2])
    violations = 0
    for folder in sorted(table):
        allowed = below(table, folder) | {folder}
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in (".h", ".cpp"):
                continue
            for number, line in enumerate(path.read_text().splitlines(), 1):
                match = INCLUDE.match(line)
                if match and match.group(1) in table and match.group(1) not in allowed:
                    print(f"{path.relative_to(root)}:{number}: layer '{folder}' includes "
                          f"'{match.group(1)}/', which is not below it (it links: "
                          f"{', '.join(sorted(allowed - {folder})) or 'no layer'})")
                    violations += 1
    if violations:
        sys.exit(1)
    print(f"layers: {len(table)} folders, every include within its layers")


if __name__ == "__main__":
    main()
