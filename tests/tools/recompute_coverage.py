#!/usr/bin/env python3
"""Independent check of the plan's bead coverage: plans a model with the command line,
then recomputes every layer's void share from the layer surface (its PLY file) and the plan's
points by Monte-Carlo sampling with brute-force distances, and compares with plan.json.

Nothing of the core's coverage code is reused: surface points are drawn uniformly by area with a
seeded generator (not the core's sub-triangle centroids), and every sample is tested against every
bead segment of its layer (no grid). A sample is void when no segment has it within half the
bead's width there (width interpolated along the segment, closing segment of a closed path
included); overlap when two different paths cover it or one path at two points more than a bead
width apart along the path (the definitions in cpp/include/curvedslicer/paths/coverage.hpp).

Tolerance, stated: per layer |recomputed - plan| <= 4 standard errors of the Monte-Carlo estimate
(sqrt(p(1-p)/n), p the plan's share, at least 1/n) + 0.01 (the plan's own discretisation: its
samples stand for sub-triangles up to s/10 across); over all layers together (area-weighted) the
same with the pooled sample count. Exit 0 when every comparison holds, 1 otherwise.

Usage: recompute_coverage.py --cli PATH --model FILE --work DIR [--samples N] -- PLAN ARGS...
       recompute_coverage.py --self-test   (the checker on a synthetic layer with a known answer)
"""

import argparse
import json
import os
import shutil
import struct
import subprocess
import sys

import numpy as np


def read_ply(path):
    """Vertices (n, 3) and triangles (m, 3) of a binary little-endian PLY as CurvedSlicer writes
    it (double x y z; uchar-int vertex lists; optional int face_id per face)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in header:
        raise ValueError("%s: not a binary little-endian PLY" % path)
    counts, face_props = {}, []
    element = None
    for line in header:
        words = line.split()
        if words[:1] == ["element"]:
            element = words[1]
            counts[element] = int(words[2])
        elif words[:1] == ["property"] and element == "face":
            face_props.append(words[-1])
    nv, nf = counts.get("vertex", 0), counts.get("face", 0)
    vertices = np.frombuffer(data, dtype="<f8", count=3 * nv, offset=end).reshape(nv, 3)
    offset = end + 24 * nv
    record = 1 + 12 + (4 if "face_id" in face_props else 0)
    triangles = np.empty((nf, 3), dtype=np.int64)
    for i in range(nf):
        if data[offset] != 3:
            raise ValueError("%s: face %d is not a triangle" % (path, i))
        triangles[i] = struct.unpack_from("<3i", data, offset + 1)
        offset += record
    return vertices, triangles


def sample_surface(vertices, triangles, n, rng):
    """n points uniformly by area, and the surface area."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    areas = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    total = areas.sum()
    chosen = rng.choice(len(areas), size=n, p=areas / total)
    u, v = rng.random(n), rng.random(n)
    flip = u + v > 1.0
    u[flip], v[flip] = 1.0 - u[flip], 1.0 - v[flip]
    points = a[chosen] + u[:, None] * (b[chosen] - a[chosen]) + v[:, None] * (c[chosen] - a[chosen])
    return points, total


def bead_segments(paths, bead_spacing):
    """Arrays over all segments: start, end, widths at both ends, path id, arc at both ends, and
    per path (length, closed)."""
    rows, info = [], []
    for k, path in enumerate(paths):
        pts = np.array(path["points"], dtype=float)
        xyz = pts[:, :3]
        w = pts[:, 9] if pts.shape[1] > 9 else np.full(len(pts), bead_spacing)
        w = np.where(w > 0, w, bead_spacing)
        closed = bool(path["closed"]) and len(pts) >= 3
        order = list(range(len(pts))) + ([0] if closed else [])
        if len(pts) == 1:
            order = [0, 0]
        arc = 0.0
        for i, j in zip(order[:-1], order[1:]):
            step = float(np.linalg.norm(xyz[j] - xyz[i]))
            rows.append((xyz[i], xyz[j], w[i], w[j], k, arc, arc + step))
            arc += step
        info.append((arc, closed))
    return rows, info


def classify(points, rows, info, chunk=512):
    """(void, overlap) boolean arrays over the samples, by brute force over every segment."""
    n = len(points)
    void, overlap = np.ones(n, bool), np.zeros(n, bool)
    if not rows:
        return void, overlap
    a = np.array([r[0] for r in rows])
    b = np.array([r[1] for r in rows])
    wa, wb = np.array([r[2] for r in rows]), np.array([r[3] for r in rows])
    path = np.array([r[4] for r in rows])
    arca, arcb = np.array([r[5] for r in rows]), np.array([r[6] for r in rows])
    length = np.array([i[0] for i in info])
    closed = np.array([i[1] for i in info])
    ab = b - a
    len2 = (ab * ab).sum(axis=1)
    for s in range(0, n, chunk):
        p = points[s:s + chunk]
        ap = p[:, None, :] - a[None, :, :]
        t = np.where(len2 > 0, (ap * ab[None]).sum(axis=2) / np.maximum(len2, 1e-300), 0.0)
        t = np.clip(t, 0.0, 1.0)
        d = np.linalg.norm(ap - t[:, :, None] * ab[None], axis=2)
        w = wa[None] + t * (wb - wa)[None]
        hit = d <= 0.5 * w
        void[s:s + chunk] = ~hit.any(axis=1)
        arc = arca[None] + t * (arcb - arca)[None]
        for i in np.nonzero(hit.sum(axis=1) >= 2)[0]:
            hits = np.nonzero(hit[i])[0]
            paths_hit, arcs, widths = path[hits], arc[i, hits], w[i, hits]
            if len(set(paths_hit.tolist())) > 1:
                overlap[s + i] = True
                continue
            k = paths_hit[0]
            diff = np.abs(arcs[:, None] - arcs[None, :])
            if closed[k]:
                diff = np.minimum(diff, length[k] - diff)
            overlap[s + i] = bool((diff > np.maximum(widths[:, None], widths[None, :])).any())
    return void, overlap


def tolerance(share, n):
    p = min(max(share, 1.0 / n), 1.0 - 1.0 / n)
    return 4.0 * np.sqrt(p * (1.0 - p) / n) + 0.01


def check_plan(out_dir, samples, seed=1):
    with open(os.path.join(out_dir, "plan.json")) as f:
        plan = json.load(f)
    s = plan["parameters"]["bead_spacing_mm"]
    rng = np.random.default_rng(seed)
    failures, measured = [], 0
    total = {"area": 0.0, "void_plan": 0.0, "void_mc": 0.0, "over_plan": 0.0, "over_mc": 0.0}
    for layer in plan["layers"]:
        cov = layer.get("coverage")
        if cov is None or not layer["surface"]:
            continue
        vertices, triangles = read_ply(os.path.join(out_dir, layer["surface"]))
        points, area = sample_surface(vertices, triangles, samples, rng)
        rows, info = bead_segments(layer["paths"], s)
        void, overlap = classify(points, rows, info)
        mc_void, mc_over = void.mean(), overlap.mean()
        measured += 1
        if abs(area - cov["area_mm2"]) > 1e-6 * max(area, 1.0):
            failures.append("layer %d: area %.6g mm2 from the PLY, %.6g in the plan"
                            % (layer["index"], area, cov["area_mm2"]))
        if abs(mc_void - cov["void_share"]) > tolerance(cov["void_share"], samples):
            failures.append("layer %d: void share %.4f recomputed, %.4f in the plan (tolerance "
                            "%.4f)" % (layer["index"], mc_void, cov["void_share"],
                                       tolerance(cov["void_share"], samples)))
        total["area"] += area
        total["void_plan"] += cov["void_share"] * area
        total["void_mc"] += mc_void * area
        total["over_plan"] += cov["overlap_share"] * area
        total["over_mc"] += mc_over * area
    if measured == 0:
        failures.append("no layer with a measured coverage in %s" % out_dir)
        return failures, total
    pooled = samples * measured
    for key in ("void", "over"):
        plan_share = total[key + "_plan"] / total["area"]
        mc_share = total[key + "_mc"] / total["area"]
        print("%s share: plan %.4f, recomputed %.4f (%d layers, %d samples each)"
              % ({"void": "void", "over": "overlap"}[key], plan_share, mc_share, measured,
                 samples))
        if abs(plan_share - mc_share) > tolerance(plan_share, pooled):
            failures.append("total %s share %.4f recomputed, %.4f in the plan" % (
                key, mc_share, plan_share))
    return failures, total


def self_test():
    """A 40 x 40 plate with one square ring of width 4 at 2 mm from the edge: void share =
    (32^2 + 4 r^2 (1 - pi/4)) / 1600, r = 2 (the closed form the C++ test uses)."""
    rng = np.random.default_rng(7)
    vertices = np.array([[0, 0, 0], [40, 0, 0], [40, 40, 0], [0, 40, 0]], float)
    triangles = np.array([[0, 1, 2], [0, 2, 3]])
    points, area = sample_surface(vertices, triangles, 20000, rng)
    ring = {"closed": True, "points": [[2, 2, 0] + [0] * 6 + [4], [38, 2, 0] + [0] * 6 + [4],
                                       [38, 38, 0] + [0] * 6 + [4], [2, 38, 0] + [0] * 6 + [4]]}
    rows, info = bead_segments([ring], 4.0)
    void, overlap = classify(points, rows, info)
    expected = (32.0 ** 2 + 4 * 4.0 * (1 - np.pi / 4)) / 1600.0
    ok = abs(area - 1600.0) < 1e-9 and abs(void.mean() - expected) < tolerance(expected, 20000)
    ok = ok and not overlap.any()
    print("self-test: void %.4f, expected %.4f: %s" % (void.mean(), expected,
                                                        "ok" if ok else "FAILED"))
    return 0 if ok else 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--self-test", action="store_true")
    parser.add_argument("--cli")
    parser.add_argument("--model")
    parser.add_argument("--work")
    parser.add_argument("--samples", type=int, default=3000)
    parser.add_argument("plan_args", nargs="*")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    out = os.path.join(args.work, "out")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(args.work, exist_ok=True)
    cmd = [args.cli, "plan", args.model] + args.plan_args + ["-o", out, "-q"]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        print("plan failed (%d): %s\n%s" % (run.returncode, " ".join(cmd), run.stderr))
        return 1
    failures, _ = check_plan(out, args.samples)
    for failure in failures:
        print("FAIL: " + failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
