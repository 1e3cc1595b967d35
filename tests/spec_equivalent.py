"""Whether two inspection specs say the same: their YAML documents are equal, but for the
control points' file, whose points must be the same (within 1e-6 mm; a normal only where
both files give one).

    python3 tests/spec_equivalent.py A.yaml B.yaml

Exits 0 when they are equivalent, 1 with the differences otherwise."""

import csv
import os
import sys

import yaml


def points(spec_path, name):
    """The control points of a points task's file, relative to its spec."""
    with open(os.path.join(os.path.dirname(spec_path), name), newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].lstrip().startswith("#")]
    if rows and not rows[0][0].lstrip("-").replace(".", "").isdigit():
        rows = rows[1:]  # the header
    return [[float(x) for x in r] for r in rows]


def document(path):
    with open(path) as f:
        spec = yaml.safe_load(f)
    for task in spec.get("tasks", []):
        if task.get("type") == "points":
            task["file"] = points(path, task["file"])
    return spec


def same_points(a, b):
    return len(a) == len(b) and all(
        all(abs(x - y) <= 1e-6 for x, y in zip(p[: min(len(p), len(q))], q)) for p, q in zip(a, b)
    )


def differences(a, b, where="spec"):
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b), key=str):
            if key not in a or key not in b:
                yield f"{where}.{key}: only in {'the first' if key in a else 'the second'}"
            else:
                yield from differences(a[key], b[key], f"{where}.{key}")
    elif where.endswith(".file") and isinstance(a, list):
        if not same_points(a, b):
            yield f"{where}: the control points differ: {a} and {b}"
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            yield from differences(x, y, f"{where}[{i}]")
    elif a != b:
        yield f"{where}: {a!r} and {b!r}"


def main():
    first, second = sys.argv[1:3]
    found = list(differences(document(first), document(second)))
    for line in found:
        print(f"FAIL {line}")
    if not found:
        print(f"ok   {second} says what {first} says")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
