"""Writes every output of the turbine example that a refactoring must not change: the plans of
the base (thin wall) and the blades (curved layers) as plan JSON, and the combined program in
every export format. Run with freecadcmd, FREECAD_USER_HOME's Mod holding the workbench of the
build under test (scripts/compare_outputs.sh does that); output folder: CURVEDSLICER_OUT.
Uses only the public macro API (api.make_job via the example, api.run, api.plan_json,
api.export), so the same script runs against an older build.
"""

import os
import sys
import traceback

import FreeCAD


def main():
    source = os.environ["CURVEDSLICER_SOURCE_DIR"]
    sys.path.insert(0, os.path.join(source, "resources", "examples"))
    import turbine
    from freecad.curvedslicer import api

    out = os.environ["CURVEDSLICER_OUT"]
    os.makedirs(out, exist_ok=True)
    doc = FreeCAD.newDocument("Turbine")
    _, base, blades = turbine.make_turbine_jobs(doc, float(os.environ.get("CURVEDSLICER_VOXEL",
                                                                          "1.0")))
    api.run(base)
    api.run(blades)
    for name, job in (("base", base), ("blades", blades)):
        with open(os.path.join(out, "plan_%s.json" % name), "w") as f:
            f.write(api.plan_json(job))
    for fmt, extension in api.export_formats():
        folder = os.path.join(out, "export_" + fmt)
        os.makedirs(folder, exist_ok=True)
        api.export([base, blades], os.path.join(folder, "TURBINE" + extension), format=fmt,
                   program_name="TURBINE", warn_unreachable=True)
    FreeCAD.closeDocument(doc.Name)
    print("turbine outputs written to %s" % out)
    return 0


try:
    code = main()
except Exception:
    traceback.print_exc()
    code = 1
sys.stdout.flush()
os._exit(code)
