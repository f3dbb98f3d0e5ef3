"""The turbine main job (paper §4.2), headless: builds the turbine (turbine.py) and plans it as the
paper does —

 - the base as a thin wall: equidistant paths 1.65 mm apart along its outer surface from its lower
   edge (PlanKind ThinWall; the paper: 54 paths);
 - the blades as 1.5 mm curved layers grown from the base's outer surface with 3.7 mm bead
   spacing (the paper: 20 layers);

then plans the positioner motion in the default cell (the paper's Motoman HP20D with a tilt-rotate
positioner), exports one JBI program (base first, then the blades) and saves the .FCStd with
layers, paths and poses.

    freecadcmd resources/examples/turbine_job.py

Environment: CURVEDSLICER_OUT (output folder, default out/example under the current folder),
CURVEDSLICER_VOXEL (voxel size of the blades' layers, mm, default 1.0), CURVEDSLICER_FORMAT
(program format, default jbi). Writes turbine.FCStd, the program (TURBINE.JBI and its sub-jobs)
and summary.json; exits non-zero on failure or when the counts leave the acceptance ranges
(base paths 54 ± 2, blade layers 20 ± 1).
"""

import json
import math
import os
import sys
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)) if "__file__" in globals()
                else os.path.join(os.getcwd(), "resources", "examples"))

import FreeCAD  # noqa: E402

PAPER_BASE_PATHS = 54
PAPER_BLADE_LAYERS = 20


def _progress(name):
    last = [-1]

    def progress(stage, fraction):
        percent = int(100 * fraction)
        if percent >= last[0] + 10:
            last[0] = percent
            print("  %-6s %3d %%  %s" % (name, percent, stage))
            sys.stdout.flush()
        return True

    return progress


def main():
    import turbine
    from freecad.curvedslicer import api

    out = os.path.abspath(os.environ.get("CURVEDSLICER_OUT", os.path.join("out", "example")))
    voxel = float(os.environ.get("CURVEDSLICER_VOXEL", "1.0"))
    fmt = os.environ.get("CURVEDSLICER_FORMAT", "jbi")
    os.makedirs(out, exist_ok=True)
    doc = FreeCAD.newDocument("Turbine")
    parts, base, blades = turbine.make_turbine_jobs(doc, voxel)
    start = time.time()
    api.run(base, progress=_progress("base"))
    api.run(blades, progress=_progress("blades"))
    plan_seconds = time.time() - start
    extension = dict(api.export_formats())[fmt]
    program = os.path.join(out, "TURBINE" + extension)
    exported = api.export([base, blades], program, format=fmt, program_name="TURBINE",
                          warn_unreachable=True)
    # Show a pose in the middle of the blades on the saved document: the middle welded point,
    # so the torch is on a bead with the deposit up to it.
    welded = [i for i, on in enumerate(api.motion(blades)["arc_on"]) if on]
    api.set_pose(blades, welded[len(welded) // 2] if welded else api.pose_count(blades) // 2)
    path = os.path.join(out, "turbine.FCStd")
    doc.saveAs(path)
    motions = [api.motion(base), api.motion(blades)]
    summary = {
        "document": path,
        "program": program,
        "program_files": [name for (name, _, _) in exported["files"]],
        "program_motions": exported["motion_count"],
        "program_warnings": exported["warnings"],
        "base_paths": base.PathCount,
        "paper_base_paths": PAPER_BASE_PATHS,
        "base_profile_length_mm": round(turbine.profile_length(), 3),
        "blade_layers": blades.LayerCount,
        "paper_blade_layers": PAPER_BLADE_LAYERS,
        "blade_paths": blades.PathCount,
        "blade_layers_with_paths": blades.PlanLayerCount,
        # The plan's bead coverage of the blade layers, area-weighted, percent.
        "blade_void_percent": round(blades.VoidShare, 2),
        "blade_overlap_percent": round(blades.OverlapShare, 2),
        "blade_arc_starts": blades.ArcStarts,
        "layer_heights_mm": list(blades.LayerHeights),
        "voxel_size_mm": voxel,
        "grid": blades.GridDims,
        "max_geodesic_distance_mm": round(blades.MaxDistance, 3),
        "motion_warnings": list(base.MotionWarnings) + list(blades.MotionWarnings),
        # what the program still hits (0: every move clears table, riser and deposit), the largest
        # torch angle off gravity used to clear, the largest gravity deviation of the deposit, and
        # the riser each Job stands on (placement Auto)
        "collisions": sum(len(m["collisions"]) for m in motions),
        "max_torch_angle_deg": round(max(math.degrees(m["total"]["max_torch_angle"])
                                         for m in motions), 2),
        "max_gravity_deviation_deg": round(max(math.degrees(m["total"]["max_gravity_deviation"])
                                               for m in motions), 2),
        "riser_height_mm": {"base": round(motions[0]["fixture"]["riser_height_mm"], 1),
                            "blades": round(motions[1]["fixture"]["riser_height_mm"], 1)},
        "pose": {"point": blades.PosePoint, "a1_deg": blades.PoseA1, "a2_deg": blades.PoseA2},
        "plan_seconds": round(plan_seconds, 2),
    }
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print("turbine: base %d paths (paper: %d), blades %d layers (paper: %d) with %d paths; "
          "program %s (%d files); saved %s"
          % (base.PathCount, PAPER_BASE_PATHS, blades.LayerCount, PAPER_BLADE_LAYERS,
             blades.PathCount, program, len(exported["files"]), path))
    print("turbine: collisions %d; largest torch angle off gravity %.1f deg, largest gravity "
          "deviation of the deposit %.1f deg; risers: base %.1f mm, blades %.1f mm"
          % (summary["collisions"], summary["max_torch_angle_deg"],
             summary["max_gravity_deviation_deg"], summary["riser_height_mm"]["base"],
             summary["riser_height_mm"]["blades"]))
    ok = abs(base.PathCount - PAPER_BASE_PATHS) <= 2 and \
        abs(blades.LayerCount - PAPER_BLADE_LAYERS) <= 1
    return 0 if ok else 1


try:
    code = main()
except Exception:
    traceback.print_exc()
    code = 1
sys.stdout.flush()
# freecadcmd 1.1 crashes at exit (in FreeCAD's Mesh module) while a document holding Mesh features
# is open; the document is saved already.
for name in list(FreeCAD.listDocuments()):
    FreeCAD.closeDocument(name)
sys.exit(code)
