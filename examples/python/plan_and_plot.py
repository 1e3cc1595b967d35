"""Plans a part from Python, prints its GD&T and what the plan measures of each toleranced
face, and plots the coverage as the views are taken in sequence.

    PYTHONPATH=build/release/python python3 examples/python/plan_and_plot.py \
        examples/parts/nist_ctc_01_asme1_ap242-e1.stp --spec examples/specs/ctc01.yaml \
        -o coverage.png
"""

import argparse

import matplotlib

matplotlib.use("Agg")  # files only, no window
import matplotlib.pyplot as plt
import numpy as np

import scanplan


def print_tolerances(part, plan):
    """Each geometric tolerance with the share of its faces' samples the plan measures."""
    faces, measured = plan.sample_faces, plan.measured
    print(f"{'tolerance':<22} {'value':>7}  {'datums':<8} {'samples':>7} {'measured':>9}")
    for t in part.tolerances:
        on = np.isin(faces, t["faces"])
        share = f"{measured[on].mean():.0%}" if on.any() else "-"
        print(f"{t['type']:<22} {t['value']:>7.3f}  {','.join(t['datums']):<8} "
              f"{on.sum():>7} {share:>9}")


def coverage_curve(plan):
    """The share of samples measured after each view of the sequence (view ids from
    plan.json's measured_by lists)."""
    doc = plan.to_json()
    order = plan.sequence or plan.view_ids
    seen = np.zeros(len(doc["samples"]), dtype=bool)
    curve = []
    for view in order:
        for i, sample in enumerate(doc["samples"]):
            if view in sample["measured_by"]:
                seen[i] = True
        curve.append(seen.mean())
    return np.array(curve)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("part")
    parser.add_argument("--spec", help="inspection spec (YAML); default: one global task")
    parser.add_argument("-o", "--out", default="coverage.png", help="the figure (PNG)")
    args = parser.parse_args()

    part = scanplan.import_part(args.part)
    spec = scanplan.load_spec(args.spec) if args.spec else None
    plan = scanplan.plan(part, spec,
                         progress=lambda stage, fraction: print(
                             f"\r{stage:<52} {fraction:4.0%}", end="", flush=True))
    print(f"\r{plan!r:<60}")
    if part.tolerances:
        print_tolerances(part, plan)

    curve = coverage_curve(plan)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(np.arange(1, len(curve) + 1), 100 * curve, marker=".")
    ax.set_xlabel("views taken, in sequence order")
    ax.set_ylabel("samples measured (%)")
    ax.set_ylim(0, 100)
    ax.set_title(f"{part.file.split('/')[-1]}: {len(curve)} views")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"figure     {args.out}")


if __name__ == "__main__":
    main()
