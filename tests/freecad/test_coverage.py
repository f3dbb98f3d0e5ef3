"""Headless tests of the Job's bead-coverage options and results: MinFeatureWidth,
BeadWidthMin / BeadWidthMax, ConnectInsets and MeasureCoverage default to the core's
PlannerOptions and reach the plan; the plan's coverage shows on the Job (VoidShare, OverlapShare,
ArcStarts, CoverageReport) and on each path layer; bad values are refused naming the property;
a Job of schema 5 is migrated (ConnectInsets off, as it planned then)."""

import json
import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import FreeCAD  # noqa: E402

import cs_testing  # noqa: E402
from freecad.curvedslicer import api, defaults  # noqa: E402
from freecad.curvedslicer.core import InvalidInput, native  # noqa: E402
from freecad.curvedslicer.objects import job as job_module  # noqa: E402
from freecad.curvedslicer.stages import paths  # noqa: E402

NEW_PROPERTIES = ("MinFeatureWidth", "BeadWidthMin", "BeadWidthMax", "ConnectInsets",
                  "MeasureCoverage", "VoidShare", "OverlapShare", "ArcStarts", "CoverageReport")


def _mm(quantity):
    return float(FreeCAD.Units.Quantity(quantity).getValueAs("mm"))


class TestCoverage(cs_testing.DocumentTestCase):
    def job(self, **kwargs):
        return api.make_job(self.doc, self.box(30, 20, 6), layer_thickness=2.0, voxel_size=1.0,
                            bead_spacing=4.0, point_spacing=2.0, cell_file="", **kwargs)

    def test_defaults_are_the_cores(self):
        core = native.PlannerOptions()
        job = api.make_job(self.doc, self.box(), cell_file="")
        self.assertEqual(_mm(job.MinFeatureWidth), 0.5 * core.bead_spacing)
        self.assertEqual(job.BeadWidthMin, core.width_min)
        self.assertEqual(job.BeadWidthMax, core.width_max)
        self.assertEqual(job.ConnectInsets, core.connect_insets)
        self.assertEqual(job.FillGaps, core.fill_gaps)
        self.assertTrue(job.FillGaps)
        self.assertEqual(job.MeasureCoverage, core.measure_coverage)
        self.assertEqual(defaults.MIN_FEATURE_WIDTH, 0.5 * core.bead_spacing)

    def test_plan_records_options_and_coverage(self):
        job = self.job(min_feature_width=1.5, bead_width_range=(0.8, 1.2), connect_insets=False,
                       fill_gaps=False)
        api.run(job, progress=False)
        summary = native.plan_summary(job.PlanJson)
        self.assertEqual(summary["parameters"]["min_feature_width_mm"], 1.5)
        self.assertEqual(tuple(summary["parameters"]["bead_width_range"]), (0.8, 1.2))
        self.assertFalse(summary["parameters"]["connect_insets"])
        self.assertFalse(summary["parameters"]["fill_gaps"])
        totals = summary["coverage"]
        self.assertEqual(totals["measured_layers"], summary["layers"])
        self.assertAlmostEqual(job.VoidShare, 100.0 * totals["void_share"], places=9)
        self.assertAlmostEqual(job.OverlapShare, 100.0 * totals["overlap_share"], places=9)
        self.assertTrue(0.0 <= job.VoidShare < 100.0)
        self.assertEqual(job.ArcStarts, job.PathCount)
        report = json.loads(job.CoverageReport)
        self.assertEqual(len(report["layers"]), summary["layers"])
        features = paths.path_objects(job)
        self.assertEqual(len(features), summary["layers"])
        for feature, layer in zip(features, summary["per_layer"]):
            self.assertTrue(feature.CoverageMeasured)
            self.assertAlmostEqual(feature.VoidShare, 100.0 * layer["coverage"]["void_share"])
            self.assertEqual(feature.ArcStarts, layer["paths"])
            self.assertEqual(len(feature.Voids), len(layer["coverage"]["voids"]))
        # Widths come with the paths: adaptive here, within 0.8·s … 1.2·s (s = 4 mm); dwell only
        # on spots (two points).
        for path in native.plan_paths(job.PlanJson, with_widths=True):
            self.assertTrue(((path[6] >= 3.2 - 1e-9) & (path[6] <= 4.8 + 1e-9)).all())
            self.assertTrue(path[7] == 0.0 or len(path[6]) == 2)
        # Coverage off: replanned, nothing measured.
        job.MeasureCoverage = False
        api.run(job, progress=False)
        self.assertEqual(native.plan_summary(job.PlanJson)["coverage"]["measured_layers"], 0)
        self.assertFalse(any(f.CoverageMeasured for f in paths.path_objects(job)))

    def test_bad_values_name_the_property(self):
        job = self.job()
        api.run(job, progress=False)
        job.BeadWidthMin = 1.1
        with self.assertRaises(InvalidInput) as caught:
            api.run(job, progress=False)
        self.assertIn("BeadWidthMin", str(caught.exception))
        self.assertIn("excludes the bead spacing", str(caught.exception))
        job.BeadWidthMin = 0.7
        job.BeadWidthMax = 0.9
        with self.assertRaises(InvalidInput) as caught:
            api.run(job, progress=False)
        self.assertIn("BeadWidthMax", str(caught.exception))
        job.BeadWidthMax = 1.3
        job.MinFeatureWidth = 0.0
        with self.assertRaises(InvalidInput) as caught:
            api.run(job, progress=False)
        self.assertIn("MinFeatureWidth must be a positive length: 0 mm", str(caught.exception))
        # The core refuses the same for every front end (the Python module's options).
        with self.assertRaises(InvalidInput) as caught:
            native.plan_layers([], options=native.PlanJobOptions(
                layer_job=native.LayerJobOptions(layer_thickness=2.0, voxel_size=1.0),
                planner=native.PlannerOptions(width_min=1.2, width_max=1.5)))
        self.assertIn("excludes the bead spacing", str(caught.exception))

    def test_schema_5_job_is_migrated(self):
        job = self.job()
        for name in NEW_PROPERTIES:
            job.removeProperty(name)
        job.removeProperty("FillGaps")
        job.SchemaVersion = 5
        job.Proxy.onDocumentRestored(job)
        self.assertFalse(job.ConnectInsets)  # as it planned before the option existed
        self.assertFalse(job.FillGaps)  # likewise
        self.assertEqual(_mm(job.MinFeatureWidth), 2.0)  # half its bead spacing
        self.assertEqual((job.BeadWidthMin, job.BeadWidthMax), (1.0, 1.0))
        self.assertTrue(job.MeasureCoverage)
        self.assertEqual(job.SchemaVersion, job_module.SCHEMA_VERSION)
        self.assertEqual(job_module.SCHEMA_VERSION, 11)

    def test_schema_6_job_keeps_its_plan_without_gap_fill(self):
        job = self.job()
        job.removeProperty("FillGaps")
        job.SchemaVersion = 6
        job.Proxy.onDocumentRestored(job)
        self.assertFalse(job.FillGaps)  # planned before gap fill existed
        self.assertEqual(job.SchemaVersion, job_module.SCHEMA_VERSION)
        api.run(job, progress=False)
        self.assertFalse(native.plan_summary(job.PlanJson)["parameters"]["fill_gaps"])

    def test_schema_7_job_keeps_its_plan_without_corner_fill(self):
        job = self.job()
        self.assertTrue(job.CornerFill)  # the default
        self.assertAlmostEqual(job.MinGapArea, 16.0)  # its bead spacing squared
        job.removeProperty("CornerFill")
        job.removeProperty("MinGapArea")
        job.SchemaVersion = 7
        job.Proxy.onDocumentRestored(job)
        self.assertFalse(job.CornerFill)  # planned before corner fill existed
        self.assertAlmostEqual(job.MinGapArea, 16.0)  # what gap fill used before the option
        self.assertEqual(job.SchemaVersion, job_module.SCHEMA_VERSION)
        api.run(job, progress=False)
        params = native.plan_summary(job.PlanJson)["parameters"]
        self.assertAlmostEqual(params["min_gap_area_mm2"], 16.0)
        self.assertLess(params["corner_overdeposit_mm"], 0.0)  # off
        self.assertNotIn("corner_fill_angle_deg", params)


cs_testing.main(__name__)
