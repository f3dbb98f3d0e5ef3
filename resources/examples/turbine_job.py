"""Headless turbine example (paper §4.2): builds the turbine (turbine.py), makes a CurvedSlicer
Job for the blades grown from the base's outer surface with 1.5 mm layers (bead spacing 3.7 mm,
stored for path planning), runs it and saves an .FCStd.

    freecadcmd resources/examples/turbine_job.py

Environment: CURVEDSLICER_OUT (output folder, default out/turbine under the current folder),
CURVEDSLICER_VOXEL (voxel size, mm, default 1.0). Writes turbine.FCStd and summary.json and
exits non-zero on failure. Paths, poses, the JBI program and the PNG render arrive with the path
planner and exporters (next version of the workbench).
"""

import json
import os
import sys
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)) if "__file__" in globals()
                else os.path.join(os.getcwd(), "resources", "examples"))

import FreeCAD  # noqa: E402


def main():
    import turbine
    from freecad.curvedslicer import api

    out = os.path.abspath(os.environ.get("CURVEDSLICER_OUT", os.path.join("out", "turbine")))
    voxel = float(os.environ.get("CURVEDSLICER_VOXEL", "1.0"))
    os.makedirs(out, exist_ok=True)
    doc = FreeCAD.newDocument("Turbine")
    parts = turbine.build_turbine(doc)
    job = api.make_job(doc, parts["Blades"], start=parts["BaseOuterSurface"],
                       layer_thickness=1.5, voxel_size=voxel, bead_spacing=3.7,
                       name="BladesJob")
    last = [-1]

    def progress(stage, fraction):
        percent = int(100 * fraction)
        if percent >= last[0] + 10:
            last[0] = percent
            print("  %3d %%  %s" % (percent, stage))
            sys.stdout.flush()
        return True

    start = time.time()
    api.run(job, progress=progress)
    path = os.path.join(out, "turbine.FCStd")
    doc.saveAs(path)
    summary = {
        "document": path,
        "blade_layers": job.LayerCount,
        "paper_blade_layers": 20,
        "layer_heights_mm": list(job.LayerHeights),
        "base_profile_length_mm": round(turbine.profile_length(), 3),
        "base_paths_expected": int(turbine.profile_length() // 1.65),
        "paper_base_paths": 54,
        "voxel_size_mm": voxel,
        "grid": job.GridDims,
        "max_geodesic_distance_mm": round(job.MaxDistance, 3),
        "seconds": round(time.time() - start, 2),
        "paths": job.PathsStatus,
    }
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print("turbine: %d blade layers (paper: 20), saved %s" % (job.LayerCount, path))
    return 0 if abs(job.LayerCount - 20) <= 1 else 1


try:
    code = main()
except Exception:
    traceback.print_exc()
    code = 1
sys.stdout.flush()
sys.exit(code)
