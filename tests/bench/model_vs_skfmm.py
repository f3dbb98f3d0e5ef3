#!/usr/bin/python3
"""Geodesic field on real models: our exact default against scikit-fmm (second order).

Runs on Debian's python3-scikit-fmm (use /usr/bin/python3). Steps:
  1. `model_field_bench --export WORK --json MODEL...` voxelizes each model as the pipeline does,
     computes our exact field from the build plate and writes the inside mask, the signed seed band
     and our field as .npy files (see model_field_bench.cpp, common/npy_export.hpp).
  2. For each repetition and model: times skfmm.distance(phi, dx=L, order=2) on the masked grid
     exactly as field_vs_skfmm.py does (same phi, mask and seed handling: run_skfmm there) and runs
     `model_field_bench --json MODEL` once, alternating which goes first.
  3. Prints medians: wall and CPU seconds of each, the paired speed ratio exact/skfmm (skfmm time
     over ours, >= 1 means ours is at least as fast) and skfmm's mean / max |skfmm - exact| in L.

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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from field_vs_skfmm import run_skfmm  # noqa: E402  (same skfmm set-up as the analytic cases)

import numpy as np  # noqa: E402


def load(directory):
    with open(os.path.join(directory, "meta.json")) as f:
        meta = json.load(f)
    arrays = {name: np.load(os.path.join(directory, name + ".npy"))
              for name in ("inside", "phi_band", "exact")}
    return meta, arrays


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
