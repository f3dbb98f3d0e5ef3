"""Headless tests of the Job's motion options (the Robot properties of the poses stage:
Clearance, AllowCollisions, AddHome, MergeTolerance, MaxA2Step, PartPlacement): defaults from the
core's MotionOptions, passed to the motion and the export, the part shown where the motion placed
it (resting on the table, or where the cell puts it), a part below the table reported with the
lowest point, the placement auto choosing the riser, and a Job of an older schema migrated to
the placement it had and the choices of this version."""

import math
import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import FreeCAD  # noqa: E402

import cs_testing  # noqa: E402
from freecad.curvedslicer import api, defaults  # noqa: E402
from freecad.curvedslicer.core import CurvedSlicerError, InvalidInput, native  # noqa: E402
from freecad.curvedslicer.objects import job as job_module  # noqa: E402
from freecad.curvedslicer.stages import poses  # noqa: E402


def _mm(quantity):
    return float(FreeCAD.Units.Quantity(quantity).getValueAs("mm"))


class TestMotionOptions(cs_testing.DocumentTestCase):
    def sunken_box_job(self):
        """A 30 x 20 x 6 mm box whose bottom is 20 mm below the document's z = 0 (the part
        frame): with the default cell's placement its weld points lie inside the table."""
        box = self.box(30, 20, 6)
        box.Placement = FreeCAD.Placement(FreeCAD.Vector(-15, -10, -20), FreeCAD.Rotation())
        self.doc.recompute()
        return api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0,
                            bead_spacing=4.0, point_spacing=2.0, cell_file="")

    def test_defaults_are_the_cores(self):
        core = native.MotionOptions()
        job = api.make_job(self.doc, self.box(), cell_file="")
        self.assertEqual(_mm(job.Clearance), core.clearance)
        self.assertEqual(_mm(job.MergeTolerance), core.merge_tolerance)
        self.assertAlmostEqual(float(job.MaxA2Step.getValueAs("deg")),
                               math.degrees(core.max_a2_step), places=12)
        self.assertEqual(job.AllowCollisions, core.allow_collisions)
        self.assertEqual(job.AddHome, core.add_home)
        self.assertEqual(job.PartPlacement.lower(), core.placement)
        self.assertEqual(defaults.PART_PLACEMENT, "rest")
        # The options the poses stage plans with are the core's defaults (apart from keeping
        # unreachable points for display).
        self.assertEqual(repr(poses.motion_options(job, unreachable="warn")),
                         repr(native.MotionOptions(unreachable="warn")))

    def test_properties_reach_the_motion_options(self):
        job = api.make_job(self.doc, self.box(), cell_file="")
        job.Clearance = 25.0
        job.MergeTolerance = 0.05
        job.MaxA2Step = 3.0
        job.AllowCollisions = True
        job.AddHome = False
        job.PartPlacement = "Cell"
        options = poses.motion_options(job)
        self.assertEqual(options.clearance, 25.0)
        self.assertEqual(options.merge_tolerance, 0.05)
        self.assertAlmostEqual(options.max_a2_step, math.radians(3.0), places=15)
        self.assertTrue(options.allow_collisions)
        self.assertFalse(options.add_home)
        self.assertEqual(options.placement, "cell")
        self.assertEqual(options.unreachable, "throw")

    def test_part_rests_on_the_table_and_is_shown_there(self):
        job = self.sunken_box_job()
        api.run(job, progress=False)
        self.assertTrue(job.PathsStatus.startswith("Planned"), job.PathsStatus)
        motion = api.motion(job)
        t = FreeCAD.Matrix(*[float(v) for row in motion["table_to_part"] for v in row])
        # The box's bottom (z = -20 in the part frame) lies on the table top (table z = 0).
        self.assertAlmostEqual(t.multiply(FreeCAD.Vector(0, 0, -20)).z, 0.0, places=6)
        self.assertAlmostEqual(t.A14, 0.0, places=12)  # the cell's xy kept
        self.assertTrue(any("part placement rest" in n for n in motion["notes"]))
        self.assertTrue(any("part placement rest" in w for w in job.MotionWarnings))
        # The positioner model carries the part at that placement.
        objects = {o.PoseRole: o for o in job.PosesGroup.Group if "PoseRole" in o.PropertiesList}
        part, table = objects["PosePart"], objects["PositionerTable"]
        for index in (0, api.pose_count(job) - 1):
            api.set_pose(job, index)
            in_table = table.Placement.inverse().multiply(part.Placement)
            self.assertAlmostEqual(in_table.Base.z, 20.0, places=6)
            self.assertLess(in_table.Base.x ** 2 + in_table.Base.y ** 2, 1e-12)
        # Exported at the same placement.
        result = api.export(job, None, format="csv")
        self.assertGreater(result["motion_count"], 0)

    def test_part_below_the_table_with_the_cells_placement_names_the_lowest_point(self):
        job = self.sunken_box_job()
        job.PartPlacement = "Cell"
        with self.assertRaises(CurvedSlicerError):
            api.run(job, progress=False)
        self.assertIn("weld points below the table top", job.PathsStatus)
        self.assertIn("mm below the table", job.PathsStatus)
        self.assertIn("PartPlacement Rest", job.PathsStatus)
        self.assertNotIn("--placement", job.PathsStatus)  # the workbench's words, not the CLI's
        with self.assertRaises(InvalidInput) as caught:
            api.export(job, None, format="csv")
        self.assertIn("layer 0 path", str(caught.exception))
        # Resting it on the table plans the poses.
        job.PartPlacement = "Rest"
        api.run(job, progress=False)
        self.assertGreater(api.pose_count(job), 0)

    def test_stale_or_failed_results_are_not_exported(self):
        # The program is what the 3D view shows, or nothing: after a failed run (the earlier
        # plan still stored), after an input changed without a rerun (the view shows the old
        # plan or the old cell's motion), export refuses and says why; after a rerun it writes.
        job = self.sunken_box_job()
        api.run(job, progress=False)
        first = api.export(job, None, format="csv")["files"][0][1]
        cases = (("LayerThickness", 50.0, "its last run failed"),
                 ("BeadSpacing", 3.0, "its path inputs changed since the paths were planned"),
                 ("CellFile", os.path.join(os.environ.get("CURVEDSLICER_SOURCE_DIR", ""),
                                           "resources", "cells",
                                           "kuka_kr16_r1610_2_dkp400.json"),
                  "its cell or robot options changed since its motion was planned"),
                 ("Clearance", 25.0, "its cell or robot options changed"))
        for name, value, reason in cases:
            old = getattr(job, name)
            setattr(job, name, value)
            if name == "LayerThickness":
                with self.assertRaises(CurvedSlicerError):  # thicker than the part
                    api.run(job, progress=False)
            with self.assertRaises(InvalidInput) as caught:
                api.export(job, None, format="csv")
            self.assertIn("%s is not exported: %s" % (job.Label, reason), str(caught.exception))
            self.assertIn("run it again", str(caught.exception))
            setattr(job, name, old)
            api.run(job, progress=False)
            self.assertEqual(api.export(job, None, format="csv")["files"][0][1], first, name)
        # an explicit cell for the export is the caller's choice, not a stale result
        job.CellFile = cases[2][1]
        api.export(job, None, format="csv", cell_file="")

    def test_messages_name_the_workbench_controls_not_command_line_options(self):
        job = self.sunken_box_job()
        api.run(job, progress=False)
        with self.assertRaises(InvalidInput) as caught:
            api.export(job, None, format="krl")  # KUKA's language, the default Yaskawa cell
        text = str(caught.exception)
        self.assertIn("tick \"Write it for another vendor's cell\" in the export dialog", text)
        self.assertNotIn("--allow-foreign-cell", text)
        # each of the core's phrasings is rewritten without a command-line option
        from freecad.curvedslicer import messages
        for core, workbench in messages._OPTIONS:
            self.assertIn("--", core)
            self.assertNotIn("--", messages.for_workbench("text " + core + " text"))

    def test_auto_placement_reaches_the_motion_and_says_what_it_chose(self):
        job = self.sunken_box_job()
        self.assertIn("Auto", job.getEnumerationsOfProperty("PartPlacement"))
        job.PartPlacement = "Auto"
        self.assertEqual(poses.motion_options(job).placement, "auto")
        api.run(job, progress=False)
        motion = api.motion(job)
        # A flat box: the torch clears the table resting on it, no riser needed.
        self.assertEqual(motion["fixture"]["riser_height_mm"], 0.0)
        self.assertGreater(motion["fixture"]["riser_diameter_mm"], 30.0)
        self.assertTrue(any("part placement auto" in n for n in motion["notes"]), motion["notes"])

    def test_the_cells_fixture_carries_the_part_and_is_drawn_on_the_table(self):
        import json

        cell = json.loads(native.default_cell_json())
        cell["positioner"]["fixture"] = {"riser_height_mm": 40, "riser_diameter_mm": 120,
                                         "substrate_thickness_mm": 8, "substrate_size_mm": 100}
        path = cs_testing.tmp_path("fixture_cell.json")
        with open(path, "w") as f:
            json.dump(cell, f)
        job = self.sunken_box_job()
        job.CellFile = path
        api.run(job, progress=False)
        motion = api.motion(job)
        self.assertEqual(motion["fixture"]["riser_height_mm"], 40.0)
        t = FreeCAD.Matrix(*[float(v) for row in motion["table_to_part"] for v in row])
        # The box's bottom (z = -20 in the part frame) lies on the plate's top (table z = 48).
        self.assertAlmostEqual(t.multiply(FreeCAD.Vector(0, 0, -20)).z, 48.0, places=6)
        # The table of the positioner model carries the riser and the plate up to z = 48.
        objects = {o.PoseRole: o for o in job.PosesGroup.Group if "PoseRole" in o.PropertiesList}
        shape = objects["PositionerTable"].Shape.copy()
        shape.Placement = FreeCAD.Placement()  # its own frame: the table frame
        box = shape.BoundBox
        self.assertAlmostEqual(box.ZMax, 48.0, places=6)
        self.assertAlmostEqual(box.ZMin, -30.0, places=6)

    def test_a_job_saved_with_fewer_placements_gets_auto(self):
        job = api.make_job(self.doc, self.box(), cell_file="")
        job.PartPlacement = ["Rest", "Cell"]  # the list a Job of the previous version stored
        job.PartPlacement = "Cell"
        job.Proxy.onDocumentRestored(job)
        self.assertEqual(list(job.getEnumerationsOfProperty("PartPlacement")),
                         job_module.PART_PLACEMENTS)
        self.assertEqual(job.PartPlacement, "Cell")

    def test_older_job_keeps_the_cells_placement(self):
        job = api.make_job(self.doc, self.box(), cell_file="")
        for name in ("Clearance", "AllowCollisions", "AddHome", "MergeTolerance", "MaxA2Step",
                     "PartPlacement"):
            job.removeProperty(name)
        # Before the migration the options fall back to the core's defaults.
        self.assertEqual(poses.motion_options(job).clearance, native.MotionOptions().clearance)
        job.SchemaVersion = 4
        job.Proxy.onDocumentRestored(job)
        self.assertEqual(job.PartPlacement, "Cell")
        self.assertEqual(_mm(job.Clearance), defaults.CLEARANCE)
        self.assertEqual(job.SchemaVersion, job_module.SCHEMA_VERSION)


cs_testing.main(__name__)
