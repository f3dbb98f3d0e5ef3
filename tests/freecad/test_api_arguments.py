"""Every macro-API argument is checked with the core's message before anything is stored or
computed: a negative length is reported as given (a length property would store it as
0), a name string instead of the solid says what to pass, a bad enumeration lists the choices,
export's date cannot inject a header line, and path='' gets a message of its own."""

import os
import sys
import time

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import cs_testing  # noqa: E402
import FreeCAD  # noqa: E402
from freecad.curvedslicer import api  # noqa: E402
from freecad.curvedslicer.core import InvalidInput, ResourceLimit  # noqa: E402
from freecad.curvedslicer.stages import layers as layer_stage  # noqa: E402


class TestApiArguments(cs_testing.DocumentTestCase):
    def refused(self, **kwargs):
        """The message of the InvalidInput make_job raises for the box with `kwargs`; no Job
        is left in the document."""
        box = self.doc.getObject("Box") or self.box(10, 10, 10)
        before = len(self.doc.Objects)
        with self.assertRaises(InvalidInput) as caught:
            api.make_job(self.doc, box, **kwargs)
        self.assertEqual(len(self.doc.Objects), before)
        return str(caught.exception)

    def test_negative_and_non_finite_numbers_are_reported_as_given(self):
        self.assertEqual(self.refused(layer_thickness=-1.5),
                         "layer thickness must be a positive number of millimetres: -1.5; pass a "
                         "value such as 1.5")
        self.assertEqual(self.refused(voxel_size=-0.25),
                         "voxel size must be a positive number of millimetres: -0.25; pass a "
                         "value such as 0.5")
        self.assertIn("voxel size must be a positive number of millimetres: nan",
                      self.refused(voxel_size=float("nan")))
        self.assertIn("layer thickness must be a positive number of millimetres: '1.5'",
                      self.refused(layer_thickness="1.5"))
        self.assertEqual(self.refused(bead_spacing=-3.7),
                         "bead spacing must be a positive number of mm: -3.7; pass a value such "
                         "as 3.7")
        self.assertIn("point spacing must be a positive number of mm: 0;",
                      self.refused(point_spacing=0))
        self.assertIn("fit tolerance must be a positive number of mm: -0.05;",
                      self.refused(fit_tolerance=-0.05))
        self.assertIn("corner angle must be in (0, 180] degrees: 200;",
                      self.refused(corner_angle=200))
        self.assertIn("memory budget must be 0 (automatic) or a positive number of MB: -5;",
                      self.refused(memory_budget_mb=-5))
        self.assertIn("deflection must be 0 (automatic) or a positive number of millimetres: -1;",
                      self.refused(deflection=-1))
        self.assertIn("wall_axis must be 3 finite numbers", self.refused(wall_axis=(0, 1)))

    def test_a_name_instead_of_the_solid_says_what_to_pass(self):
        self.box(10, 10, 10)
        with self.assertRaises(InvalidInput) as caught:
            api.make_job(self.doc, "Box")
        message = str(caught.exception)
        self.assertIn("solid must be a FreeCAD object: 'Box' of type str", message)
        self.assertIn("doc.getObject('Box')", message)
        with self.assertRaises(InvalidInput) as caught:
            api.make_job(self.doc, 42)
        self.assertIn("solid must be a FreeCAD object: 42 of type int", str(caught.exception))

    def test_unknown_choices_list_the_valid_ones(self):
        self.assertEqual(self.refused(method="fast"),
                         "unknown method: 'fast'; use one of AnyAngle, Paper")
        self.assertIn("unknown grid_alignment: 'obb'; use one of PCA, Model",
                      self.refused(grid_alignment="obb"))
        self.assertIn("unknown narrow_strips: 'x'", self.refused(narrow_strips="x"))

    def test_a_point_spacing_that_explodes_the_plan_is_a_resource_limit(self):
        box = self.box(20, 16, 6)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0, bead_spacing=4.0,
                           point_spacing=1e-6, memory_budget_mb=64, cell_file="")
        begin = time.monotonic()
        with self.assertRaises(ResourceLimit) as caught:
            api.run(job, progress=False)
        self.assertLess(time.monotonic() - begin, 5.0)
        message = str(caught.exception)
        self.assertIn("the plan would hold about ", message)
        self.assertIn("over the memory budget of 67.1 MB", message)
        self.assertIn("use a point spacing of at least ", message)

    def test_overlapping_solids_are_sliced_as_their_union_with_a_warning(self):
        a = self.box(20, 30, 20, name="A")
        b = self.box(20, 30, 20, name="B")
        b.Placement.Base = FreeCAD.Vector(5, 0, 0)
        both = self.doc.addObject("Part::Compound", "Both")
        both.Links = [a, b]
        self.doc.recompute()
        job = api.make_job(self.doc, both, layer_thickness=4.0, voxel_size=1.0,
                           grid_alignment="Model")
        # The union is the point here: only the layer stage runs.
        layer_stage.update_layers(job)
        report = api.report(job)
        self.assertEqual(report["grid"]["fill_rule"], "nonzero")
        self.assertEqual(report["grid"]["inside_voxels"], 15000)
        self.assertEqual(len(report["warnings"]), 1)
        self.assertIn("9000 voxels lie inside two or more shells of the model", report["warnings"][0])
        self.assertIn("around x 5.5..19.5, y 0.5..29.5, z 0.5..19.5 mm", report["warnings"][0])

    def test_export_date_and_empty_path(self):
        box = self.box(20, 16, 6)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0, bead_spacing=4.0,
                           point_spacing=2.0, cell_file="")
        api.run(job, progress=False)
        with self.assertRaises(InvalidInput) as caught:
            api.export(job, None, format="jbi", date="2026/11/22 07:00\r\nMOVJ VJ=100.00")
        self.assertEqual(str(caught.exception),
                         "date must look like \"YYYY/MM/DD HH:MM\": '2026/11/22 07:00\\r\\nMOVJ "
                         "VJ=100.00'; e.g. \"2026/11/22 07:00\"")
        with self.assertRaises(InvalidInput):
            api.export(job, None, format="jbi", date="2026")
        with self.assertRaises(InvalidInput) as caught:
            api.export(job, None, format="jbi", date=20261122)
        self.assertIn("date must be a string", str(caught.exception))
        with self.assertRaises(InvalidInput) as caught:
            api.export(job, "", format="jbi")
        self.assertEqual(str(caught.exception),
                         "output path is empty: ''; pass a file path such as 'PART.JBI'")
        result = api.export(job, None, format="jbi", date="2026/11/22 07:00")
        self.assertGreater(result["motion_count"], 0)

    def test_object_of_another_document_is_refused_before_a_job_is_made(self):
        other = FreeCAD.newDocument("OtherDocument")
        try:
            box = other.addObject("Part::Box", "ElsewhereBox")
            other.recompute()
            message = self.refused_for(box)
            self.assertIn("solid ElsewhereBox is in the document 'OtherDocument', not in %r"
                          % self.doc.Name, message)
            own = self.box(10, 10, 10, name="Own")
            message = self.refused_for(own, start=(box, ["Face5"]))
            self.assertIn("start ElsewhereBox is in the document 'OtherDocument'", message)
        finally:
            FreeCAD.closeDocument(other.Name)

    def refused_for(self, solid, **kwargs):
        before = len(self.doc.Objects)
        with self.assertRaises(InvalidInput) as caught:
            api.make_job(self.doc, solid, **kwargs)
        self.assertEqual(len(self.doc.Objects), before)  # no half-made Job
        return str(caught.exception)

    def test_progress_callback_answers_and_pose_indices_are_checked(self):
        box = self.box(20, 16, 6)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0, bead_spacing=4.0,
                           point_spacing=2.0, cell_file="")
        # a callback that answers neither True nor False: a clear error, the Job marked failed
        with self.assertRaises(InvalidInput) as caught:
            api.run(job, progress=lambda stage, fraction: "yes")
        self.assertIn("the progress callback must return True (go on) or False (cancel): it "
                      "returned 'yes'", str(caught.exception))
        self.assertIn("Invalid", job.State)
        with self.assertRaises(InvalidInput) as caught:
            api.run(job, progress="dialog")
        self.assertIn("progress must be None, False or a callable", str(caught.exception))
        # a callback returning nothing (None) goes on
        api.run(job, progress=lambda stage, fraction: None)
        self.assertNotIn("Invalid", job.State)
        count = api.pose_count(job)
        for index in (count, -1, 1e12, "3", True):
            with self.assertRaises(InvalidInput) as caught:
                api.set_pose(job, index)
            self.assertIn("no motion point %s: %s has %d; pick 0 to %d"
                          % (repr(index)[:60], job.Label, count, count - 1),
                          str(caught.exception))
        self.assertEqual(api.set_pose(job, count - 1), (job.PoseA1, job.PoseA2))


cs_testing.main(__name__)
