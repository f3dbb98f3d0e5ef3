"""Bad input gives its error with a message saying what to do, and leaves the document as it
was: a non-solid, an open mesh, a start face not on the model, a start surface away from the
model, a run over the memory budget, bad parameters."""

import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import FreeCAD  # noqa: E402
import Mesh  # noqa: E402
import Part  # noqa: E402

import cs_testing  # noqa: E402
from freecad.curvedslicer import api  # noqa: E402
from freecad.curvedslicer.core import InvalidInput, ResourceLimit  # noqa: E402


class TestBadInput(cs_testing.DocumentTestCase):
    def assert_unchanged(self, job, objects):
        self.assertEqual(sorted(o.Name for o in self.doc.Objects), objects)
        self.assertEqual(job.LayerCount, 0)

    def test_non_solid_selection(self):
        plane = self.doc.addObject("Part::Plane", "Plane")
        plane.Length = plane.Width = 10
        self.doc.recompute()
        with self.assertRaises(InvalidInput) as caught:
            api.make_job(self.doc, plane)
        self.assertIn("not a solid", str(caught.exception))
        self.assertIn("select a closed solid", str(caught.exception))
        self.assertEqual([o.Name for o in self.doc.Objects], ["Plane"])

    def test_open_mesh(self):
        box = Part.makeBox(10, 10, 10)
        mesh = Mesh.Mesh(box.tessellate(0.1))
        mesh.removeFacets([0])
        feature = self.doc.addObject("Mesh::Feature", "OpenMesh")
        feature.Mesh = mesh
        job = api.make_job(self.doc, feature, layer_thickness=2.0, voxel_size=1.0)
        objects = sorted(o.Name for o in self.doc.Objects)
        with self.assertRaises(InvalidInput) as caught:
            api.run(job, progress=False)
        self.assertIn("open mesh", str(caught.exception))
        self.assertIn("CapHoles", str(caught.exception))
        self.assert_unchanged(job, objects)
        self.assertTrue(job.Status.startswith("InvalidInput"), job.Status)
        # The advice works: with CapHoles the same mesh slices.
        job.CapHoles = True
        api.run(job, progress=False)
        self.assertEqual(job.LayerCount, 4)

    def test_start_face_not_on_the_model(self):
        box = self.box(10, 10, 10)
        other = self.box(5, 5, 5, name="Other")
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0)
        job.StartMode = "Faces"
        job.StartFaces = [(other, ("Face5",))]
        objects = sorted(o.Name for o in self.doc.Objects)
        with self.assertRaises(InvalidInput) as caught:
            api.run(job, progress=False)
        self.assertIn("start face not on the model", str(caught.exception))
        self.assertIn("pick faces of Box", str(caught.exception))
        self.assert_unchanged(job, objects)
        job.StartFaces = [(box, ("Face42",))]
        with self.assertRaises(InvalidInput) as caught:
            api.run(job, progress=False)
        self.assertIn("Face42", str(caught.exception))

    def test_start_surface_away_from_the_model(self):
        box = self.box(10, 10, 10)
        far = self.doc.addObject("Part::Plane", "FarPlane")
        far.Length = far.Width = 10
        far.Placement.Base = FreeCAD.Vector(0, 0, 50)
        self.doc.recompute()
        job = api.make_job(self.doc, box, start=far, layer_thickness=2.0, voxel_size=1.0)
        self.assertEqual(job.StartMode, "Surface")
        with self.assertRaises(InvalidInput) as caught:
            api.run(job, progress=False)
        self.assertIn("start surface", str(caught.exception))

    def test_run_over_the_memory_budget(self):
        box = self.box(100, 100, 100)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=0.1,
                           memory_budget_mb=64)
        estimate = api.estimate(job)
        self.assertFalse(estimate["fits"])
        self.assertGreater(estimate["bytes"], 64 * 2 ** 20)
        objects = sorted(o.Name for o in self.doc.Objects)
        with self.assertRaises(ResourceLimit) as caught:
            api.run(job, progress=False)
        self.assertIn("voxel size", str(caught.exception))
        self.assert_unchanged(job, objects)
        job.VoxelSize = 2.0
        self.assertTrue(api.estimate(job)["fits"])

    def test_bad_parameters(self):
        box = self.box(10, 10, 10)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0)
        job.VoxelSize = 0
        with self.assertRaises(InvalidInput) as caught:
            api.run(job, progress=False)
        self.assertIn("voxel size must be positive", str(caught.exception))
        job.VoxelSize = 1.0
        job.MemoryBudget = -5
        with self.assertRaises(InvalidInput):
            api.run(job, progress=False)
        with self.assertRaises(InvalidInput):
            api.run(box)

    def test_errors_during_recompute_go_to_status_and_the_error_state(self):
        plane = self.doc.addObject("Part::Plane", "Plane")
        plane.Length = plane.Width = 10
        box = self.box(10, 10, 10)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0)
        job.Solid = plane
        self.doc.recompute()
        self.assertTrue(job.Status.startswith("InvalidInput: not a solid"), job.Status)
        self.assertEqual(job.LayerCount, 0)
        self.assertIn("Invalid", job.State)  # FreeCAD's error state
        job.Solid = box
        self.doc.recompute()
        self.assertEqual(job.State, ["Up-to-date"])
        self.assertEqual(job.LayerCount, 4)  # at 2, 4, 6 and 8 mm of the 10 mm box

    def test_a_failed_run_puts_the_job_in_the_error_state_and_a_good_run_clears_it(self):
        box = self.box(10, 10, 10)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0)
        job.LayerThickness = 0
        with self.assertRaises(InvalidInput):
            api.run(job, progress=False)
        self.assertIn("Invalid", job.State)
        self.assertEqual(job.LayerCount, 0)
        job.LayerThickness = 2.0
        api.run(job, progress=False)
        self.assertEqual(job.State, ["Up-to-date"])
        self.assertEqual(job.LayerCount, 4)  # at 2, 4, 6 and 8 mm of the 10 mm box

    def test_a_recompute_with_fewer_layers_leaves_no_unused_features(self):
        box = self.box(10, 10, 12)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0)
        self.doc.recompute()
        self.assertEqual(job.LayerCount, 5)
        self.assertEqual(len(api.layers(job)), 5)
        job.LayerThickness = 5.0
        self.doc.recompute()  # a plain recompute (Std_Refresh), not api.recompute
        self.assertEqual(job.LayerCount, 2)  # at 5 and 10 mm
        self.assertEqual(len(api.layers(job)), 2)
        self.assertEqual(len(api.path_features(job)), job.PlanLayerCount)
        unused = [o.Label for o in self.doc.Objects if "LayerIndex" in o.PropertiesList
                  and o.LayerIndex == 0]
        self.assertEqual(unused, [])


cs_testing.main(__name__)
