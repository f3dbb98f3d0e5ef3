#!/usr/bin/python3
"""Geodesic field on real models: our exact default against scikit-fmm (second order).

Runs on Debian's python3-scikit-fmm (use /usr/bin/python3). Steps:
  1. `model_field_bench --export WORK --json MODEL...` voxelizes each model as the pipeline does,
     computes our exact field from the build plate and writes the inside mask, the signed seed band
     and our field as .npy files (see model_field_bench.cpp, common/npy_export.hpp).
  2. For each repetition and model: times skfmm.distance(phi, dx=L, order=2) on the grid masked
     to the inside voxels and runs `model_field_bench --json MODEL` once, alternating which goes
     first.
  3. Prints medians: wall and CPU seconds of each, the paired speed ratio exact/skfmm (skfmm time
     over ours, >= 1 means ours is at least as fast) and skfmm's mean / max |skfmm - exact| in L.

skfmm input. The bundled models stand on a build plate that reaches beyond them, so the set-up of
field_vs_skfmm.py (negative cells behind the start surface) does not apply: outside cells beside
the part near the plate would either carry the zero level set onto the part's walls or let the
front leak around the outside. Instead the front starts inside the seed band: with c = sqrt(3)·L
(the band) and d the straight distance to the start surface, phi = d - c on the inside voxels
with d <= 3c (negative exactly on the seeds), +BIG on the other inside voxels, everything outside
masked; the field is c + skfmm's distance, and the seeds get their exact d back, as in the C++
methods. Timing covers the skfmm.distance call only.

Usage:
  model_vs_skfmm.py --bench BUILD/tests/bench/model_field_bench [--voxel 0.5] [--repeat 3]
                    [--work DIR] MODEL...
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

import time

import numpy as np
import skfmm

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from field_vs_skfmm import BIG, field_error  # noqa: E402  (the analytic cases' metric)


def load(directory):
    with open(os.path.join(directory, "meta.json")) as f:
        meta = json.load(f)
    arrays = {name: np.load(os.path.join(directory, name + ".npy"))
              for name in ("inside", "source_distance", "exact")}
    return meta, arrays


def run_skfmm(meta, arrays):
    L = meta["voxel_size_mm"]
    c = np.sqrt(3.0) * L
    inside = arrays["inside"].astype(bool)
    d = arrays["source_distance"]
    near = np.isfinite(d)
    is_seed = near & (d <= c)
    phi = np.ma.MaskedArray(np.where(near, d - c, BIG), mask=~inside)
    t0, cpu0 = time.perf_counter(), time.process_time()
    dist = skfmm.distance(phi, dx=L, order=2)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - cpu0
    field = np.full(inside.shape, np.inf)
    values = np.ma.filled(dist, np.inf) + c
    field[inside] = values[inside]
    field[is_seed] = d[is_seed]
    err = field_error(field, inside, arrays["exact"], L)
    return {"seconds": seconds, "cpu_s": cpu, "voxels_per_s": int(inside.sum()) / seconds, **err}


def run_ours(bench, model, voxel):
    out = subprocess.run([bench, "--json", "--voxel", str(voxel), model], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bench", required=True, help="path to the model_field_bench executable")
    ap.add_argument("--work", default="/tmp/curvedslicer-model-field")
    ap.add_argument("--voxel", type=float, default=0.5)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("models", nargs="+")
    args = ap.parse_args()

    subprocess.run([args.bench, "--export", args.work, "--json", "--voxel", str(args.voxel)]
                   + args.models, check=True, capture_output=True)
    print("| model | L (mm) | inside voxels | exact s (wall) | skfmm s (wall) | exact / skfmm CPU s "
          "| speed exact/skfmm (wall) | by CPU | skfmm vs exact mean / max (L) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for model in args.models:
        stem = os.path.splitext(os.path.basename(model))[0]
        meta, arrays = load(os.path.join(args.work, stem))
        ours, peer = [], []
        for rep in range(args.repeat):
            if rep % 2 == 0:
                peer.append(run_skfmm(meta, arrays))
                ours.append(run_ours(args.bench, model, args.voxel))
            else:
                ours.append(run_ours(args.bench, model, args.voxel))
                peer.append(run_skfmm(meta, arrays))
        med = statistics.median
        wall = med(p["seconds"] / o["exact_seconds"] for o, p in zip(ours, peer))
        cpu = med(p["cpu_s"] / o["exact_cpu_s"] for o, p in zip(ours, peer))
        print(f"| {meta['model']} | {meta['voxel_size_mm']:g} | {meta['inside']} | "
              f"{med(o['exact_seconds'] for o in ours):.2f} | {med(p['seconds'] for p in peer):.2f} | "
              f"{med(o['exact_cpu_s'] for o in ours):.2f} / {med(p['cpu_s'] for p in peer):.2f} | "
              f"{wall:.2f} | {cpu:.2f} | {peer[0]['mean']:.3f} / {peer[0]['max']:.3f} |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
