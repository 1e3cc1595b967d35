#!/usr/bin/env python3
"""The library's layering rule (docs/design.md, "Parts and layers").

Every file of src/ and include/scanplan/ lies in a part folder, src/<part>/ beside
include/scanplan/<part>/ (an umbrella header include/scanplan/<part>.h belongs to its part).
The parts stand on rungs, from the bottom up. A file includes files of its own part and of
parts on lower rungs only: never a part above it, nor another part of its own rung.

usage: check-layers.py [REPO]   prints each violation; exit 1 when there is one
"""
import pathlib
import re
import sys

RUNGS = (
    ("core",),
    ("solve",),
    ("cad",),
    ("scanner",),
    ("sampling", "registration", "robot"),
    ("plan",),
    ("spec",),
    ("io",),
    ("planning",),
    ("report", "editor"),
)
RUNG_OF = {part: rung for rung, parts in enumerate(RUNGS) for part in parts}
INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*([<"])([^>"]+)[>"]', re.M)
SOURCES = (".h", ".hpp", ".cpp", ".cc")


def part_of(repo, path):
    """The part a library file belongs to, or None when it lies in no part folder."""
    rel = path.relative_to(repo).parts
    inside = rel[1:] if rel[0] == "src" else rel[2:]
    if len(inside) > 1:
        return inside[0] if inside[0] in RUNG_OF else None
    stem = pathlib.Path(inside[0]).stem
    return stem if rel[0] == "include" and stem in RUNG_OF else None


def included(repo, source, quote, name):
    """The library file an include names, or None for a system or third-party header."""
    candidates = []
    if quote == "<":
        if name.startswith("scanplan/"):
            candidates.append(repo / "include" / name)
    else:
        candidates += [source.parent / name, repo / "src" / name, repo / "include" / name]
    for candidate in candidates:
        if candidate.is_file():
            return candidate.resolve()
    return None


def violations(repo):
    repo = pathlib.Path(repo).resolve()
    found = []
    files = [p for root in (repo / "src", repo / "include" / "scanplan") if root.is_dir()
             for p in sorted(root.rglob("*")) if p.suffix in SOURCES and p.is_file()]
    for path in files:
        mine = part_of(repo, path)
        rel = path.relative_to(repo)
        if mine is None:
            found.append(f"{rel}: in no part folder")
            continue
        for quote, name in INCLUDE.findall(path.read_text(errors="replace")):
            target = included(repo, path, quote, name)
            if target is None:
                continue
            theirs = part_of(repo, target)
            if theirs is None or theirs == mine:
                continue
            if RUNG_OF[theirs] >= RUNG_OF[mine]:
                where = "above it" if RUNG_OF[theirs] > RUNG_OF[mine] else "on its rung"
                found.append(f"{rel} ({mine}) includes {target.relative_to(repo)} "
                             f"({theirs}, {where})")
    return found


def main(argv):
    found = violations(argv[1] if len(argv) > 1 else ".")
    for line in found:
        print(line)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
