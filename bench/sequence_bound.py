#!/usr/bin/env python3
"""The motion of a plan's sequence against a lower bound on any sequence of its views
(docs/benchmarks.md, "Sequence against a lower bound").

The bound is Held and Karp's: 1-trees over the views and a free end node, raised by
subgradient steps on node weights. It is taken over the straight moves' times (the camera's
travel plus its rotation times 200 mm, one trapezoid at the generic positioning's speed and
acceleration), which no move of the planner, over the part or not, undercuts, and it ignores
the registration rule: no order of the views, whatever it keeps, moves in less time.

    bench/sequence_bound.py PLAN.json [SPEED mm/s] [ACCELERATION mm/s²] [--free]
    bench/sequence_bound.py --check

Prints the plan's motion, the bound and the gap between them, for a plan of one placement
without a cell (summary.cycle.model generic). With --free, also the motion of the plan's
order improved by 2-opt and or-opt moves without the registration rule (this script's own
search, not the planner's): how much of the gap the rule takes. --check compares the bound
with the shortest open path by brute force on 20 random instances of 8 points in a plane.
"""
import json
import math
import sys

import numpy as np


def trapezoid(distance, speed, acceleration):
    """Seconds over `distance` from rest to rest (arrays)."""
    triangle = distance <= speed * speed / acceleration
    return np.where(triangle, 2 * np.sqrt(distance / acceleration),
                    distance / speed + speed / acceleration)


def move_times(plan, speed, acceleration, arm=200.0):
    poses = [np.array(v["camera_to_world"], dtype=float).reshape(4, 4) for v in plan["views"]]
    centres = np.array([m[:3, 3] for m in poses])
    rotations = np.array([m[:3, :3] for m in poses])
    travel = np.linalg.norm(centres[:, None, :] - centres[None, :, :], axis=2)
    # The angle between two orientations from the trace of R_i^T R_j.
    trace = np.einsum("iab,jab->ij", rotations, rotations)
    angle = np.arccos(np.clip((trace - 1) / 2, -1, 1))
    times = trapezoid(travel + arm * angle, speed, acceleration)
    np.fill_diagonal(times, 0)
    return times


def one_tree(cost):
    """Weight and node degrees of the minimum 1-tree: a spanning tree over nodes 1..n-1
    (Prim) and the two cheapest edges of node 0."""
    n = len(cost)
    inside = np.zeros(n, bool)
    inside[0] = True
    inside[1] = True
    best = cost[1].copy()
    parent = np.full(n, 1)
    degree = np.zeros(n, int)
    weight = 0.0
    for _ in range(n - 2):
        candidates = np.where(inside, np.inf, best)
        j = int(np.argmin(candidates))
        weight += best[j]
        degree[j] += 1
        degree[parent[j]] += 1
        inside[j] = True
        closer = cost[j] < best
        best = np.where(closer, cost[j], best)
        parent = np.where(closer, j, parent)
    two = np.argsort(cost[0, 1:])[:2] + 1
    weight += cost[0, two].sum()
    degree[0] += 2
    degree[two] += 1
    return weight, degree


def held_karp(times, upper, iterations=600):
    """A lower bound on the shortest open path through every node of `times`: a cycle
    through a free end node (node 0, at no cost from every view)."""
    n = len(times) + 1
    cost = np.zeros((n, n))
    cost[1:, 1:] = times
    np.fill_diagonal(cost, np.inf)
    weights = np.zeros(n)
    bound, step, since = -math.inf, 2.0, 0
    for _ in range(iterations):
        tree, degree = one_tree(cost + weights[:, None] + weights[None, :])
        value = tree - 2 * weights.sum()
        if value > bound + 1e-9:
            bound, since = value, 0
        else:
            since += 1
            if since >= 20:
                step, since = step / 2, 0
        slack = degree - 2
        if not slack.any() or step < 1e-6:
            break
        weights += step * (upper - value) / float(slack @ slack) * slack
    return bound


def length(times, order):
    return float(times[order[:-1], order[1:]].sum())


def two_opt(times, order):
    """Segment reversals that shorten the open path (the start stays), until none does."""
    order = np.array(order)
    n = len(order)
    improved = True
    while improved:
        improved = False
        for i in range(1, n - 1):
            j = np.arange(i + 1, n)
            delta = times[order[i - 1], order[j]] - times[order[i - 1], order[i]]
            inner = j + 1 < n
            delta[inner] += (times[order[i], order[j[inner] + 1]] -
                             times[order[j[inner]], order[j[inner] + 1]])
            k = int(np.argmin(delta))
            if delta[k] < -1e-9:
                order[i:j[k] + 1] = order[i:j[k] + 1][::-1].copy()
                improved = True
    return list(order)


def or_opt(times, order):
    """Runs of 1 to 3 nodes moved, either way round, where they shorten the path most."""
    improved = True
    while improved:
        improved = False
        for size in (1, 2, 3):
            i = 1
            while i + size <= len(order):
                run, rest = order[i:i + size], order[:i] + order[i + size:]
                removed = times[order[i - 1], run[0]]
                if i + size < len(order):
                    removed += times[run[-1], order[i + size]] - times[order[i - 1], order[i + size]]
                a = np.array(rest)
                b = np.append(a[1:], -1)
                best, where = -1e-9, None
                for turned in (run, run[::-1]):
                    add = times[a, turned[0]] + np.where(b >= 0, times[turned[-1], b] - times[a, b], 0)
                    add += length(times, turned) - length(times, run)
                    k = int(np.argmin(add - removed))
                    if add[k] - removed < best:
                        best, where = add[k] - removed, (k, turned)
                if where:
                    k, turned = where
                    order = rest[:k + 1] + list(turned) + rest[k + 1:]
                    improved = True
                i += 1
    return order


def free_search(times, order):
    """`order` improved by 2-opt and or-opt in turn, without the registration rule."""
    best = length(times, order)
    while True:
        order = or_opt(times, two_opt(times, order))
        if length(times, order) > best - 1e-9:
            return order
        best = length(times, order)


def check():
    """The bound against brute force: it must never exceed the shortest open path."""
    import itertools
    random = np.random.default_rng(3)
    gaps = []
    for _ in range(20):
        points = random.uniform(0, 1000, (8, 2))
        times = np.linalg.norm(points[:, None] - points[None], axis=2)
        shortest = min(length(times, list(order)) for order in itertools.permutations(range(8)))
        bound = held_karp(times, 1.1 * shortest)
        if bound > shortest + 1e-6:
            sys.exit(f"the bound {bound} exceeds the shortest path {shortest}")
        gaps.append(shortest / bound - 1)
    print(f"20 instances of 8 points: the shortest path at most {100 * max(gaps):.3f} % "
          f"above the bound")


def main():
    if "--check" in sys.argv:
        return check()
    args = [a for a in sys.argv[1:] if a != "--free"]
    plan = json.load(open(args[0]))
    speed = float(args[1]) if len(args) > 1 else 250.0
    acceleration = float(args[2]) if len(args) > 2 else 500.0
    cycle = plan["summary"]["cycle"]
    if cycle["model"] != "generic":
        sys.exit(f"{args[0]}: the bound is for the generic positioning, not a cell")
    motion = cycle["motion"]
    times = move_times(plan, speed, acceleration)
    bound = held_karp(times, motion)
    line = (f"views {len(plan['views'])}  motion {motion:.1f} s  bound {bound:.1f} s  "
            f"gap {100 * (motion / bound - 1):.1f} %")
    if "--free" in sys.argv:
        index = {view["id"]: k for k, view in enumerate(plan["views"])}
        free = length(times, free_search(times, [index[i] for i in plan["sequence"]]))
        line += f"  free {free:.1f} s ({100 * (free / bound - 1):.1f} % above)"
    print(line)


if __name__ == "__main__":
    main()
