"""Headless Job tests (freecadcmd): Part box and cylinder through the macro API, layer count and
thickness, recompute reruns only what changed, parameter changes update the children, cancel
mid-run leaves the document consistent."""

import json
import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import numpy as np  # noqa: E402

import FreeCAD  # noqa: E402
import cs_testing  # noqa: E402
from freecad.curvedslicer import api, defaults  # noqa: E402
from freecad.curvedslicer.core import Cancelled, native  # noqa: E402
from freecad.curvedslicer.stages import layers as layer_stage  # noqa: E402


def mesh_points(feature):
    return np.array([(p.x, p.y, p.z) for p in feature.Mesh.Points])


class TestJob(cs_testing.DocumentTestCase):
    def test_box_build_plate_gives_flat_layers_at_multiples_of_h(self):
        box = self.box(20, 16, 10)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=0.5)
        self.assertTrue(api.run(job, progress=False))
        # Layers at 2, 4, 6, 8 (and 10 only if the field reaches the top face).
        self.assertEqual(job.LayerCount, int(job.MaxDistance // 2.0 + 1e-9))
        self.assertIn(job.LayerCount, (4, 5))
        layers = api.layers(job)
        self.assertEqual(len(layers), job.LayerCount)
        for k, layer in enumerate(layers, start=1):
            self.assertAlmostEqual(float(layer.Height), 2.0 * k, places=9)
            z = mesh_points(layer)[:, 2]
            self.assertLess(np.abs(z - 2.0 * k).max(), 0.05, "layer %d not flat" % k)
            self.assertAlmostEqual(float(layer.Area), 20 * 16, delta=1.0)
            self.assertAlmostEqual(layer.ThicknessMean, 2.0, delta=0.05)
        self.assertTrue(job.Status.startswith("Up to date"), job.Status)
        self.assertEqual(job.RunCount, 1)
        self.assertNotIn("Touched", job.State)
        report = api.report(job)
        self.assertEqual(len(report["layers"]), job.LayerCount)

    def test_box_from_picked_face_grows_along_x(self):
        box = self.box(12, 10, 8)
        job = api.make_job(self.doc, box, start=(box, ["Face1"]), layer_thickness=3.0,
                           voxel_size=0.5)
        # Layers are the point here: only the layer stage runs (the parts are sliced sideways,
        # which the default cell cannot weld without the torch reaching the table).
        layer_stage.update_layers(job)
        self.assertEqual(job.StartMode, "Faces")
        self.assertIn(job.LayerCount, (3, 4))
        for k, layer in enumerate(api.layers(job), start=1):
            x = mesh_points(layer)[:, 0]
            self.assertLess(np.abs(x - 3.0 * k).max(), 0.05)

    def test_tilted_start_plane_gives_parallel_planes(self):
        # A box turned 45° about y: its bottom face lies in the plane through the origin with
        # normal (1, 0, 1), so the layers are the planes n·p = k·h.
        box = self.box(20, 20, 20)
        box.Placement = FreeCAD.Placement(FreeCAD.Vector(),
                                          FreeCAD.Rotation(FreeCAD.Vector(0, 1, 0), 45))
        self.doc.recompute()
        normal = FreeCAD.Vector(1, 0, 1)
        job = api.make_job(self.doc, box, start=("plane", (0, 0, 0), (1, 0, 1)),
                           layer_thickness=4.0, voxel_size=1.0)
        # Layers are the point here: only the layer stage runs (the parts are sliced sideways,
        # which the default cell cannot weld without the torch reaching the table).
        layer_stage.update_layers(job)
        self.assertEqual(job.StartMode, "Plane")
        self.assertEqual(job.LayerCount, 4)  # 4, 8, 12, 16 (the top at 20 is not reached)
        n = np.array([normal.x, normal.y, normal.z]) / normal.Length
        for k, layer in enumerate(api.layers(job), start=1):
            d = mesh_points(layer) @ n
            self.assertLess(np.abs(d - 4.0 * k).max(), 0.1, "layer %d" % k)

    def test_cylinder_from_its_lateral_face_gives_coaxial_cylinders(self):
        cylinder = self.doc.addObject("Part::Cylinder", "Cylinder")
        cylinder.Radius, cylinder.Height = 10.0, 6.0
        self.doc.recompute()
        job = api.make_job(self.doc, cylinder, start=(cylinder, ["Face1"]), layer_thickness=2.0,
                           voxel_size=0.5, deflection=0.01)
        # Layers are the point here: only the layer stage runs (the parts are sliced sideways,
        # which the default cell cannot weld without the torch reaching the table).
        layer_stage.update_layers(job)
        self.assertIn(job.LayerCount, (4, 5))
        for k, layer in enumerate(api.layers(job), start=1):
            p = mesh_points(layer)
            r = np.hypot(p[:, 0], p[:, 1])
            self.assertLess(np.abs(r - (10.0 - 2.0 * k)).max(), 0.15,
                            "layer %d radius %g..%g" % (k, r.min(), r.max()))

    def test_recompute_reruns_only_what_changed_and_updates_children(self):
        box = self.box(10, 10, 9)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0)
        self.doc.recompute()
        self.assertEqual(job.RunCount, 1)
        self.assertEqual(job.LayerCount, 4)
        names = [o.Name for o in api.layers(job)]
        # A path parameter: the layers are not recomputed.
        job.BeadSpacing = 4.0
        self.doc.recompute()
        self.assertEqual(job.RunCount, 1)
        self.assertEqual([o.Name for o in api.layers(job)], names)
        self.assertTrue(job.PathsStatus.startswith("Planned"), job.PathsStatus)
        # A layer parameter: rerun, children follow.
        job.LayerThickness = 3.0
        self.doc.recompute()
        self.assertEqual(job.RunCount, 2)
        self.assertEqual(job.LayerCount, 2)
        self.assertEqual([float(o.Height) for o in api.layers(job)], [3.0, 6.0])
        api.recompute(job)  # prunes the emptied layer objects
        self.assertEqual(len([o for o in job.LayersGroup.Group
                              if "LayerIndex" in o.PropertiesList]), 2)
        # The paths followed the layers: one path feature per layer, on the new heights.
        self.assertEqual([round(f.Shape.BoundBox.ZMin, 1) for f in api.path_features(job)],
                         [3.0, 6.0])
        # The solid changes: rerun.
        box.Height = 13
        self.doc.recompute()
        self.assertEqual(job.RunCount, 3)
        self.assertEqual(job.LayerCount, 4)

    def test_simplified_and_full_resolution_layers(self):
        box = self.box(20, 16, 10)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=0.5)
        self.assertEqual(job.SimplifyLayers, defaults.SIMPLIFY_LAYERS)
        self.assertEqual(defaults.SIMPLIFY_LAYERS, native.LayerJobOptions().simplify_layers)
        job.SimplifyLayers = True
        api.run(job, progress=False)
        simplified = [layer.Mesh.CountFacets for layer in api.layers(job)]
        self.assertAlmostEqual(api.report(job)["inputs"]["layer_tolerance_mm"], 0.025)
        self.assertAlmostEqual(json.loads(job.PlanJson)["parameters"]["layer_tolerance_mm"],
                               0.025)
        job.SimplifyLayers = False
        api.run(job, progress=False)
        self.assertEqual(job.RunCount, 2)  # a layer input: rerun
        full = [layer.Mesh.CountFacets for layer in api.layers(job)]
        self.assertEqual(len(full), len(simplified))
        for k, (a, b) in enumerate(zip(simplified, full), start=1):
            self.assertLess(3 * a, b, "layer %d: %d simplified, %d full" % (k, a, b))
        self.assertIsNone(api.report(job)["inputs"]["layer_tolerance_mm"])
        self.assertNotIn("layer_tolerance_mm", json.loads(job.PlanJson)["parameters"])
        for k, layer in enumerate(api.layers(job), start=1):
            self.assertAlmostEqual(float(layer.Area), 20 * 16, delta=1.0)

    def test_cancel_mid_run_keeps_the_previous_layers(self):
        box = self.box(10, 10, 9)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0)
        api.run(job, progress=False)
        before = [(o.Name, float(o.Height), o.Mesh.CountFacets) for o in api.layers(job)]
        objects = sorted(o.Name for o in self.doc.Objects)
        stages = []

        def cancel_in_field(stage, fraction):
            stages.append((stage, fraction))
            return fraction < 0.3

        job.LayerThickness = 1.0
        with self.assertRaises(Cancelled):
            api.run(job, progress=cancel_in_field)
        self.assertGreater(len(stages), 1)
        self.assertTrue(all(b[1] >= a[1] for a, b in zip(stages, stages[1:])))
        self.assertEqual([(o.Name, float(o.Height), o.Mesh.CountFacets) for o in api.layers(job)],
                         before)
        self.assertEqual(sorted(o.Name for o in self.doc.Objects), objects)
        self.assertTrue(job.Status.startswith("Cancelled"), job.Status)

        def raising(stage, fraction):
            raise KeyboardInterrupt("stop")

        with self.assertRaises(Cancelled) as caught:
            api.run(job, progress=raising)
        self.assertIn("KeyboardInterrupt", str(caught.exception))
        # The document is usable afterwards.
        api.run(job, progress=False)
        self.assertEqual(job.LayerCount, 8)

    def test_layer_range_hides_the_other_layers(self):
        box = self.box(10, 10, 9)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0)
        api.run(job, progress=False)
        api.set_layer_range(job, 2, 3)
        self.assertEqual([o.Visibility for o in api.layers(job)], [False, True, True, False])


cs_testing.main(__name__)
