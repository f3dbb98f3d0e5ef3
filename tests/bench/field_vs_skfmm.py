#!/usr/bin/python3
"""Geodesic field: our methods against scikit-fmm (second order) on the closed-form cases.

Runs on Debian's python3-scikit-fmm (use /usr/bin/python3). Steps:
  1. `field_bench --export WORK` writes each case's inside mask, exact seed distances, closed-form
     distances and our default field as .npy files (see field_bench.cpp).
  2. Checks that this script's error metric reproduces measureFieldError (C++) on our default field
     (mean and max within 1e-6 L); exits non-zero otherwise.
  3. For each repetition and case: times skfmm.distance(phi, dx=L, order=2) on the masked grid
     (mask = outside the solid) and runs `field_bench --benchmark_filter=^field/<case>/<cells>/`
     once (both C++ methods), alternating which goes first, so peers share the machine's state.
  4. Prints medians over the repetitions: inside voxels per wall second, process CPU seconds,
     mean / max |error| in L, the paired speed ratios default/skfmm (median of per-repetition
     ratios, by wall time and by CPU time), and the targets.

skfmm input (phi_band.npy from field_bench): phi is the signed distance to the start surface in
the seed band (sqrt(3)·L): +d on the seed voxels (the inside voxels and exact distances the C++
methods seed with) and -d on the cells behind the start surface (outside the solid, closest source
point the foot of the perpendicular), and +BIG on the other inside voxels (only the sign matters
there: every sign change lies between two band cells). The mask hides every other cell, i.e. the
outside of the solid apart from that thin band behind the start surface. The result is skfmm's
distance on the inside voxels, with the seed voxels set to their exact distances as in the C++
methods. Timing covers the skfmm.distance call only (the seeds, computed in C++, are not timed,
while the C++ methods' times include their seeding).

Usage:
  field_vs_skfmm.py --bench BUILD/tests/bench/field_bench [--work DIR] [--cells 128 256]
                    [--cases slab shell lshape ubend] [--repeat 5] [--json OUT.json]
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

BIG = 1e6  # mm, phi on inside voxels beyond the seed band (any positive value)
CASES = ["slab", "shell", "lshape", "ubend"]


def load_case(directory):
    with open(os.path.join(directory, "meta.json")) as f:
        meta = json.load(f)
    arrays = {name: np.load(os.path.join(directory, name + ".npy"))
              for name in ("inside", "phi_band", "exact", "anyangle")}
    return meta, arrays


def field_error(field, inside, exact, L):
    """Mean / max |field - exact| / L over reached inside voxels (measureFieldError's metric)."""
    reached = inside & np.isfinite(field)
    diff = np.abs(field[reached].astype(np.float64) - exact[reached]) / L
    return {"mean": float(diff.mean()), "max": float(diff.max()),
            "unreached": int(inside.sum() - reached.sum())}


def check_metric(meta, arrays):
    inside = arrays["inside"].astype(bool)
    got = field_error(arrays["anyangle"], inside, arrays["exact"], meta["voxel_size_mm"])
    want = meta["anyangle_error"]
    for key in ("mean", "max"):
        if abs(got[key] - want[key]) > 1e-6:
            sys.exit(f"metric mismatch on {meta['case']}_{meta['cells']}: {key} {got[key]} here, "
                     f"{want[key]} from measureFieldError; fix the script before trusting it")


def run_skfmm(meta, arrays):
    L = meta["voxel_size_mm"]
    inside = arrays["inside"].astype(bool)
    band = arrays["phi_band"]
    in_band = np.isfinite(band)
    is_seed = in_band & inside
    phi = np.where(in_band, band, BIG)
    phi = np.ma.MaskedArray(phi, mask=~(inside | in_band))
    t0, cpu0 = time.perf_counter(), time.process_time()
    dist = skfmm.distance(phi, dx=L, order=2)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - cpu0
    field = np.full(inside.shape, np.inf)
    values = np.ma.filled(dist, np.inf)
    field[inside] = values[inside]
    field[is_seed] = band[is_seed]
    err = field_error(field, inside, arrays["exact"], L)
    return {"seconds": seconds, "cpu_s": cpu, "voxels_per_s": int(inside.sum()) / seconds, **err}


def run_cpp(bench, case, cells):
    cmd = [bench, f"--cases={case}", f"--cells={cells}", "--benchmark_format=json",
           f"--benchmark_filter=^field/{case}/{cells}/"]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    results = {}
    for b in json.loads(out)["benchmarks"]:
        method = b["run_name"].split("/")[3]
        results[method] = {"seconds": b["real_time"] / 1e3, "cpu_s": b["cpu_s"],
                           "voxels_per_s": b["voxels_per_s"],
                           "mean": b["mean_err_L"], "max": b["max_err_L"],
                           "unreached": int(b["unreached"])}
    return results


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bench", required=True, help="path to the field_bench executable")
    ap.add_argument("--work", default="/tmp/curvedslicer-field-bench")
    ap.add_argument("--cells", type=int, nargs="+", default=[128, 256])
    ap.add_argument("--cases", nargs="+", default=CASES, choices=CASES)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", help="write all per-repetition results here")
    args = ap.parse_args()

    subprocess.run([args.bench, f"--export={args.work}", "--cells=" + ",".join(map(str, args.cells)),
                    "--cases=" + ",".join(args.cases)], check=True)

    runs = {}  # (case, cells) -> {method: [result per repetition]}
    metas = {}
    for rep in range(args.repeat):
        for case in args.cases:
            for cells in args.cells:
                meta, arrays = load_case(os.path.join(args.work, f"{case}_{cells}"))
                if rep == 0:
                    check_metric(meta, arrays)
                metas[(case, cells)] = meta
                slot = runs.setdefault((case, cells), {})
                if rep % 2 == 0:
                    sk = run_skfmm(meta, arrays)
                    cpp = run_cpp(args.bench, case, cells)
                else:
                    cpp = run_cpp(args.bench, case, cells)
                    sk = run_skfmm(meta, arrays)
                del arrays
                slot.setdefault("skfmm", []).append(sk)
                for method, r in cpp.items():
                    slot.setdefault(method, []).append(r)
                print(f"rep {rep + 1}/{args.repeat} {case} {cells}: " + ", ".join(
                    f"{m} {r[-1]['voxels_per_s'] / 1e6:.2f} M/s" for m, r in slot.items()),
                    file=sys.stderr, flush=True)

    if args.json:
        with open(args.json, "w") as f:
            json.dump({f"{c}_{n}": v for (c, n), v in runs.items()}, f, indent=1)

    load = os.getloadavg()
    print(f"{time.strftime('%Y-%m-%d')}, {os.cpu_count()} CPUs, load average at the end "
          f"{load[0]:.2f} {load[1]:.2f} {load[2]:.2f}, {args.repeat} repetitions (medians)")
    print()
    print("| case | cells | inside voxels | method | M voxels/s (wall) | CPU s | mean err (L) | "
          "max err (L) |")
    print("|---|---|---|---|---|---|---|---|")
    targets = []
    for (case, cells), slot in runs.items():
        meta = metas[(case, cells)]
        for method in ("paper", "anyangle", "skfmm"):
            r = slot[method]
            med = lambda key: statistics.median(x[key] for x in r)
            label = {"anyangle": "default (anyangle)", "skfmm": "skfmm order 2"}.get(method, method)
            print(f"| {meta['name']} | {cells} | {meta['inside']} | {label} | "
                  f"{med('voxels_per_s') / 1e6:.3f} | {med('cpu_s'):.2f} | {med('mean'):.4f} | "
                  f"{med('max'):.3f} |")
        paired = lambda f: statistics.median(f(a, b) for a, b in zip(slot["anyangle"], slot["skfmm"]))
        ratio = paired(lambda a, b: a["voxels_per_s"] / b["voxels_per_s"])
        cpu_ratio = paired(lambda a, b: b["cpu_s"] / a["cpu_s"])
        max_any = statistics.median(x["max"] for x in slot["anyangle"])
        max_sk = statistics.median(x["max"] for x in slot["skfmm"])
        targets.append((meta["name"], cells, ratio, cpu_ratio, max_any, max_sk,
                        case in ("lshape", "ubend")))
    print()
    print("| case | cells | speed default/skfmm (wall) | same by CPU time | speed target (>= 1) | "
          "max err default/skfmm | accuracy target (<= 0.2, L-shape and U-bend) |")
    print("|---|---|---|---|---|---|---|")
    for name, cells, ratio, cpu_ratio, max_any, max_sk, scored in targets:
        err_ratio = max_any / max_sk if max_sk > 0 else float("inf")
        acc = ("pass" if err_ratio <= 0.2 else "FAIL") if scored else "(not a target)"
        print(f"| {name} | {cells} | {ratio:.2f} | {cpu_ratio:.2f} | "
              f"{'pass' if ratio >= 1 else 'FAIL'} | {err_ratio:.3f} | {acc} |")


if __name__ == "__main__":
    main()
