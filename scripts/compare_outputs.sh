#!/usr/bin/env bash
# Shows that a change leaves the product's outputs as they were: builds BASE_REV (a commit, tag or
# branch; default origin/main or main) in a temporary worktree, runs the same cases with that
# build and with this tree's build, and compares every output file byte for byte.
#
# Cases (all at their README settings):
#   curved   the curved example: custom_base_geom_to_slice.obj on custom_base_surface.obj,
#            h 1.5, L 0.5, s 3.7, --cap-holes
#   bunny    bunny_closed_low_res.stl, h 1.5, L 1, s 3.7
#   wall     the curved example's base surface planned as a thin wall, s 1.65
#   turbine  the turbine example in FreeCAD (tests/regression/turbine_outputs.py): both plans
# Each CLI case writes the plan folder (layer files, voxel_sets.ply, plan.json, plan.csv,
# report.json) and exports plan.json in every format with the default cell; the turbine case
# writes both plans and the combined program in every format.
# report.json is compared without its timings, peak memory and version (they differ run to run);
# everything else must be identical. Differences are listed; exit 1 if there are any.
#
# Usage: scripts/compare_outputs.sh [BASE_REV] [CASE...]
# Environment: CURVEDSLICER_BUILD_DIR (this tree's build, default build/), COMPARE_WORK (scratch,
# default /tmp/curvedslicer-compare). Needs scripts/setup.sh's packages; about 10 min on 2 cores
# plus the base build.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
base_rev="${1:-}"
[[ $# -gt 0 ]] && shift
if [[ -z "$base_rev" ]]; then
  base_rev="$(git -C "$repo" rev-parse --verify -q origin/main >/dev/null && echo origin/main || echo main)"
fi
cases=("$@")
((${#cases[@]})) || cases=(curved bunny wall turbine)
work="${COMPARE_WORK:-/tmp/curvedslicer-compare}"
head_build="${CURVEDSLICER_BUILD_DIR:-$repo/build}"
jobs="$(nproc 2>/dev/null || echo 2)"
launcher=()
command -v ccache >/dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

build_tree() {  # build_tree SOURCE BUILD
  if [[ ! -f "$2/build.ninja" ]]; then
    cmake -S "$1" -B "$2" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCURVEDSLICER_BUILD_BENCH=OFF \
      "${launcher[@]}" >"$work/cmake-$(basename "$2").log"
  fi
  cmake --build "$2" -j "$jobs" --target curvedslicer curvedslicer_workbench \
    >>"$work/cmake-$(basename "$2").log"
}

run_cli_case() {  # run_cli_case CLI OUT CASE
  local cli="$1" out="$2/$3" models="$repo/resources/models"
  rm -rf "$out"
  case "$3" in
    curved) "$cli" plan "$models/custom_base_geom_to_slice.obj" \
              --start "mesh:$models/custom_base_surface.obj" --cap-holes \
              --layer-thickness 1.5 --voxel 0.5 --bead-spacing 3.7 -o "$out" -q ;;
    bunny)  "$cli" plan "$models/bunny_closed_low_res.stl" --layer-thickness 1.5 --voxel 1 \
              --bead-spacing 3.7 -o "$out" -q ;;
    wall)   "$cli" plan "$models/custom_base_surface.obj" --thin-wall lowest --bead-spacing 1.65 \
              -o "$out" -q ;;
  esac
  local fmt
  for fmt in jbi krl rapid ls gcode csv json; do
    # A refused export is an output too: its message is compared instead of the files.
    mkdir -p "$out/export_$fmt"
    "$cli" export "$out/plan.json" --format "$fmt" -o "$out/export_$fmt/PART.$fmt" \
      --name PART --allow-unreachable -q 2>"$out/export_$fmt/stderr.txt" || echo "exit $?" >>"$out/export_$fmt/stderr.txt"
  done
}

run_turbine_case() {  # run_turbine_case BUILD OUT
  local home="$work/home-$(basename "$1")"
  rm -rf "$home" "$2/turbine"
  mkdir -p "$home"
  ln -sfn "$1/freecad-home/Mod" "$home/Mod"
  FREECAD_USER_HOME="$home" CURVEDSLICER_OUT="$2/turbine" CURVEDSLICER_SOURCE_DIR="$repo" \
    freecadcmd "$repo/tests/regression/turbine_outputs.py" >"$2/turbine.log" 2>&1 || true
  if grep -q Traceback "$2/turbine.log" || [[ ! -f "$2/turbine/plan_blades.json" ]]; then
    echo "compare_outputs.sh: the turbine case failed with $1 (log: $2/turbine.log)" >&2
    return 1
  fi
}

run_cases() {  # run_cases BUILD OUT
  mkdir -p "$2"
  local c
  for c in "${cases[@]}"; do
    echo "compare_outputs.sh: case $c with $1"
    if [[ "$c" == turbine ]]; then run_turbine_case "$1" "$2"; else run_cli_case "$1/cpp/curvedslicer" "$2" "$c"; fi
  done
}

mkdir -p "$work"
base_src="$work/base-src"
base_build="$work/base-build"
if [[ "$(git -C "$base_src" rev-parse HEAD 2>/dev/null)" != "$(git -C "$repo" rev-parse "$base_rev")" ]]; then
  git -C "$repo" worktree remove --force "$base_src" 2>/dev/null || rm -rf "$base_src"
  git -C "$repo" worktree prune
  git -C "$repo" worktree add --detach "$base_src" "$base_rev" >/dev/null
  rm -rf "$base_build"
fi
echo "compare_outputs.sh: base $base_rev ($(git -C "$base_src" rev-parse --short HEAD)), head: this tree"
build_tree "$base_src" "$base_build"
build_tree "$repo" "$head_build"
run_cases "$base_build" "$work/out-base"
run_cases "$head_build" "$work/out-head"

/usr/bin/python3 - "$work/out-base" "$work/out-head" "${cases[@]}" <<'EOF'
import filecmp, json, os, sys

base, head, cases = sys.argv[1], sys.argv[2], sys.argv[3:]
VOLATILE = ("seconds", "peak_memory_bytes", "peak_bytes", "version", "total_seconds",
            "bytes_per_cell", "threads")

def strip(value):
    if isinstance(value, dict):
        return {k: strip(v) for k, v in value.items()
                if not any(word in k for word in VOLATILE)}
    if isinstance(value, list):
        return [strip(v) for v in value]
    return value

def paths_differing(a, b, prefix=""):
    """Key paths where two JSON values differ (added, removed or changed)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in list(a) + [k for k in b if k not in a]:
            if k not in a or k not in b:
                out.append("%s/%s (%s)" % (prefix, k, "added" if k in b else "removed"))
            else:
                out += paths_differing(a[k], b[k], "%s/%s" % (prefix, k))
        return out
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        out = []
        for i, (x, y) in enumerate(zip(a, b)):
            out += paths_differing(x, y, "%s/%d" % (prefix, i))
        return out
    return [] if a == b else ["%s (changed)" % (prefix or "/")]

def files(root):
    out = set()
    for folder, _, names in os.walk(root):
        out.update(os.path.relpath(os.path.join(folder, n), root) for n in names)
    return out

differ = []
count = 0
for case in cases:
    a, b = os.path.join(base, case), os.path.join(head, case)
    fa, fb = files(a), files(b)
    for name in sorted(fa ^ fb):
        differ.append("%s/%s: only in %s" % (case, name, "base" if name in fa else "head"))
    for name in sorted(fa & fb):
        count += 1
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        if os.path.basename(name) == "report.json":
            keys = paths_differing(strip(json.load(open(pa))), strip(json.load(open(pb))))
            if keys:
                shown = sorted(set(keys))
                differ.append("%s/%s: differs beyond timings at %s%s" % (
                    case, name, ", ".join(shown[:8]), " …" if len(shown) > 8 else ""))
        elif not filecmp.cmp(pa, pb, shallow=False):
            differ.append("%s/%s: differs" % (case, name))
print("compare_outputs.sh: %d files compared in %s" % (count, ", ".join(cases)))
for line in differ:
    print("  " + line)
if differ:
    print("compare_outputs.sh: outputs DIFFER")
    sys.exit(1)
print("compare_outputs.sh: outputs identical")
EOF
