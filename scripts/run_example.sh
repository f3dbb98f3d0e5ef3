#!/usr/bin/env bash
# The main job: the paper's turbine (§4.2) planned in FreeCAD, headless.
#
# resources/examples/turbine_job.py builds the parametric turbine and plans it as the paper does:
# the base as a thin wall of beads 1.65 mm apart from its lower edge (paper: 54 paths), the blades
# as 1.5 mm curved layers grown from the base's outer surface with 3.7 mm bead spacing (paper: 20
# layers); positioner motion in the paper's cell (Motoman HP20D + tilt-rotate positioner).
# resources/examples/turbine_render.py then renders the 3D view (xvfb-run + freecad).
# Output: out/example/ — turbine.FCStd (layers, paths, poses, plan), TURBINE.JBI (+ sub-jobs),
# summary.json, turbine.png (layers and paths), turbine_pose.png (the blades on the positioner
# table at a pose, the torch at the motion point, the deposit up to it), turbine_cell.png (the
# same with the robot).
# Run scripts/setup.sh first (it installs the dependencies and builds build/).
# Environment: CURVEDSLICER_BUILD_DIR (default build/), CURVEDSLICER_VOXEL (blade layers' voxel
# size, mm, default 1.0).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${CURVEDSLICER_BUILD_DIR:-$repo/build}"
jobs="$(nproc 2>/dev/null || echo 2)"

if [[ ! -f "$build/build.ninja" ]]; then
  cmake -S "$repo" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" -j "$jobs" --target curvedslicer_workbench

out="$repo/out/example"
mkdir -p "$out"
# An isolated FreeCAD user folder whose Mod is the build-tree workbench (never the real one).
home="$build/freecad-example-home"
mkdir -p "$home"
ln -sfn "$build/freecad-home/Mod" "$home/Mod"
export FREECAD_USER_HOME="$home" QTWEBENGINE_DISABLE_SANDBOX=1 CURVEDSLICER_OUT="$out"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-$jobs}"

# Drops FreeCAD's "( 42 %)" progress clutter; fails on a Traceback (FreeCAD may exit 0 anyway).
filter_log() {
  tr '\r' '\n' | sed -E 's/\(\s*[0-9]+\s*%\)//g' | grep -v -E '^\s*$' | tee "$1" |
    grep -v -E '^( *#|FreeCAD (0|is|wouldn)|Recompute|Postprocessing)' || true
  ! grep -q Traceback "$1"
}

echo "run_example.sh: planning the turbine (base thin wall + curved blade layers) in FreeCAD"
start_time=$(date +%s)
# Outputs of an earlier run (and of the older command-line example that wrote here) go first, so
# out/example/ holds exactly this run's files.
rm -f "$out"/summary.json "$out"/*.JBI "$out"/*.png "$out"/turbine.FCStd "$out"/layer_*.ply \
  "$out"/voxel_sets.ply "$out"/report.json
freecadcmd "$repo/resources/examples/turbine_job.py" 2>&1 | filter_log "$out/plan.log"
[[ -f "$out/summary.json" ]] || { echo "run_example.sh: the plan failed (see $out/plan.log)" >&2; exit 1; }
plan_time=$(date +%s)

echo "run_example.sh: rendering the 3D view"
CURVEDSLICER_DOCUMENT="$out/turbine.FCStd" \
  xvfb-run -a -s "-screen 0 1280x1024x24" freecad "$repo/resources/examples/turbine_render.py" \
  2>&1 | filter_log "$out/render.log"
[[ -s "$out/turbine.png" ]] || { echo "run_example.sh: no render (see $out/render.log)" >&2; exit 1; }
end_time=$(date +%s)

/usr/bin/python3 - "$out/summary.json" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
print()
print("Summary")
print("  base:        %d paths 1.65 mm apart (paper: %d; profile %.1f mm)"
      % (s["base_paths"], s["paper_base_paths"], s["base_profile_length_mm"]))
print("  blades:      %d curved layers of 1.5 mm (paper: %d), %d paths at 3.7 mm"
      % (s["blade_layers"], s["paper_blade_layers"], s["blade_paths"]))
print("  coverage:    blades %.2f %% void, %.2f %% overlap, %d arc starts (target: "
      "void <= 1.5 %%)" % (s["blade_void_percent"], s["blade_overlap_percent"],
                           s["blade_arc_starts"]))
print("  clearance:   %d collisions; largest torch angle off gravity %.1f deg, largest gravity "
      "deviation %.1f deg; risers: base %.1f mm, blades %.1f mm"
      % (s["collisions"], s["max_torch_angle_deg"], s["max_gravity_deviation_deg"],
         s["riser_height_mm"]["base"], s["riser_height_mm"]["blades"]))
print("  program:     %s (%d files, %d motions)"
      % (s["program"], len(s["program_files"]), s["program_motions"]))
print("  document:    %s (layers, paths, poses, plan JSON)" % s["document"])
EOF
echo "  renders:     $out/turbine.png, $out/turbine_pose.png, $out/turbine_cell.png"
echo "  wall time:   $((plan_time - start_time)) s plan + $((end_time - plan_time)) s render"
