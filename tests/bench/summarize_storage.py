#!/usr/bin/python3
"""Summarises a voxel_storage_bench JSON file (--benchmark_out) as the README's markdown table.

For each voxel set and structure it takes the median over repetitions of the time per search (CPU
time of the benchmark thread, the `per_search` counter) and prints the ratios the paper's Table 1
is about: map/dense, kd/dense, kd/map (the paper claims the map is ~70 % faster than a kd-tree,
i.e. kd/map ~ 1.7).

Usage: summarize_storage.py RESULT.json
"""
import json
import statistics
import sys
from collections import defaultdict


def main(path):
    with open(path) as f:
        doc = json.load(f)
    per_search = defaultdict(list)  # (set, structure) -> [seconds per search]
    bytes_per_voxel = {}
    for b in doc["benchmarks"]:
        if b.get("run_type") != "iteration":
            continue
        _, shape, structure = b["run_name"].split("/")[:3]
        per_search[(shape, structure)].append(b["per_search"])
        bytes_per_voxel[(shape, structure)] = b["bytes_per_voxel"]
    ctx = doc["context"]
    print(f"date {ctx['date']}, {ctx['num_cpus']} CPUs, load average "
          f"{', '.join(f'{x:.2f}' for x in ctx.get('load_avg', []))}")
    print()
    print("| voxel set | structure | time per search (median) | min – max | runs | "
          "heap bytes per voxel |")
    print("|---|---|---|---|---|---|")
    med = {}
    order = ["map", "map_rows", "kd_radius", "kd_knn27", "dense"]
    for key in sorted(per_search, key=lambda k: (k[0] != "block", order.index(k[1]))):
        values = per_search[key]
        med[key] = statistics.median(values)
        print(f"| {key[0]} | {key[1]} | {fmt(med[key])} | {fmt(min(values))} – {fmt(max(values))} "
              f"| {len(values)} | {bytes_per_voxel[key]:.1f} |")
    print()
    print("| voxel set | map/dense | map_rows/dense | kd_radius/dense | kd_radius/map | "
          "kd_knn27/map |")
    print("|---|---|---|---|---|---|")
    for shape in dict.fromkeys(s for s, _ in med):
        m = lambda name: med[(shape, name)]
        print(f"| {shape} | {m('map') / m('dense'):.1f} | {m('map_rows') / m('dense'):.1f} | "
              f"{m('kd_radius') / m('dense'):.1f} | {m('kd_radius') / m('map'):.2f} | "
              f"{m('kd_knn27') / m('map'):.2f} |")


def fmt(seconds):
    if seconds >= 1e-6:
        return f"{seconds * 1e6:.2f} µs"
    return f"{seconds * 1e9:.0f} ns"


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
