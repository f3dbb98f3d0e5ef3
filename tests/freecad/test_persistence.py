"""Persistence: save -> reopen in a new freecadcmd process -> Job, layers and report intact
without a recompute; a recompute after reopening does not rerun the layers; a Job saved by an
older workbench (missing properties, schema 0) is migrated on load."""

import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import cs_testing  # noqa: E402
from freecad.curvedslicer import SCHEMA_VERSION, api  # noqa: E402

CHECK = r'''
import FreeCAD
from freecad.curvedslicer import api
doc = FreeCAD.openDocument(PATH)
job = doc.getObject("Job")
layers = api.layers(job)
out = {
    "is_job": api.is_job(job),
    "touched": [o.Name for o in doc.Objects if "Touched" in o.State],
    "layer_count": job.LayerCount,
    "layers": [[o.Name, float(o.Height), o.Mesh.CountFacets, round(float(o.Area), 6)]
               for o in layers],
    "report_layers": len(api.report(job)["layers"]),
    "digest": job.InputsDigest,
    "run_count": job.RunCount,
    "schema": job.SchemaVersion,
    "has_point_spacing": "PointSpacing" in job.PropertiesList,
    "status": job.Status,
    "narrow_strips": getattr(job, "NarrowStrips", None),
    "deposition_direction": getattr(job, "DepositionDirection", None),
    "corner_angle": (FreeCAD.Units.Quantity(job.CornerAngle).getValueAs("deg").Value
                     if "CornerAngle" in job.PropertiesList else None),
    "path_count": job.PathCount,
    "simplify_layers": getattr(job, "SimplifyLayers", None),
}
plan_before = job.PlanJson
doc.recompute()
out["run_count_after_recompute"] = job.RunCount
out["plan_unchanged_by_recompute"] = job.PlanJson == plan_before
print("RESULT " + json.dumps(out))
'''


class TestPersistence(cs_testing.DocumentTestCase):
    def test_saved_job_reopens_intact_without_recompute(self):
        box = self.box(12, 10, 9)
        job = api.make_job(self.doc, box, start=(box, ["Face5"]), layer_thickness=2.0,
                           voxel_size=0.5)
        api.run(job, progress=False)
        expected = [[o.Name, float(o.Height), o.Mesh.CountFacets, round(float(o.Area), 6)]
                    for o in api.layers(job)]
        path = cs_testing.tmp_path("persist.FCStd")
        self.doc.saveAs(path)
        out = cs_testing.run_in_new_process(CHECK.replace("PATH", repr(path)))
        self.assertNotIn("error", out, out)
        self.assertTrue(out["is_job"])
        self.assertEqual(out["touched"], [])
        self.assertEqual(out["layer_count"], 4)
        self.assertEqual(out["layers"], expected)
        self.assertEqual(out["report_layers"], 4)
        self.assertEqual(out["digest"], job.InputsDigest)
        self.assertEqual(out["run_count"], 1)
        self.assertEqual(out["run_count_after_recompute"], 1)
        self.assertEqual(out["simplify_layers"], job.SimplifyLayers)

    def test_job_of_an_older_schema_is_migrated_on_load(self):
        box = self.box(10, 10, 5)
        # Planned as a Job of the time did: narrow strips overlapping and the paper's deposition
        # direction everywhere (the options did not exist).
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0,
                           narrow_strips="Overlap", deposition_direction="Nearest")
        api.run(job, progress=False)
        paths = job.PathCount
        self.assertGreater(paths, 0)
        job.removeProperty("PointSpacing")
        job.removeProperty("NarrowStrips")
        job.removeProperty("CornerAngle")
        job.removeProperty("DepositionDirection")
        job.SchemaVersion = 0
        path = cs_testing.tmp_path("old_schema.FCStd")
        self.doc.saveAs(path)
        out = cs_testing.run_in_new_process(CHECK.replace("PATH", repr(path)))
        self.assertNotIn("error", out, out)
        self.assertTrue(out["has_point_spacing"])
        self.assertEqual(out["schema"], SCHEMA_VERSION)
        self.assertEqual(out["layer_count"], 2)
        self.assertEqual(out["run_count_after_recompute"], 1)
        # The new option arrives as Overlap, so the saved plan stays what it was: no replan.
        self.assertEqual(out["narrow_strips"], "Overlap")
        self.assertEqual(out["deposition_direction"], "Nearest")
        # The corner angle arrives as 30°, the value the fit used before it was a property.
        self.assertEqual(out["corner_angle"], 30.0)
        self.assertEqual(out["path_count"], paths)
        self.assertTrue(out["plan_unchanged_by_recompute"])

    def test_job_of_schema_7_keeps_its_full_resolution_layers(self):
        box = self.box(10, 10, 5)
        # Sliced as a Job of the time did: full-resolution layers (simplification was opt-in).
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0,
                           simplify_layers=False)
        api.run(job, progress=False)
        expected = [[o.Name, float(o.Height), o.Mesh.CountFacets, round(float(o.Area), 6)]
                    for o in api.layers(job)]
        job.removeProperty("SimplifyLayers")
        job.SchemaVersion = 7
        path = cs_testing.tmp_path("schema_7.FCStd")
        self.doc.saveAs(path)
        out = cs_testing.run_in_new_process(CHECK.replace("PATH", repr(path)))
        self.assertNotIn("error", out, out)
        self.assertEqual(out["schema"], SCHEMA_VERSION)
        self.assertIs(out["simplify_layers"], False)
        self.assertEqual(out["digest"], job.InputsDigest)  # same inputs: the layers stay
        self.assertEqual(out["layers"], expected)
        self.assertEqual(out["run_count_after_recompute"], 1)
        self.assertTrue(out["plan_unchanged_by_recompute"])


cs_testing.main(__name__)
