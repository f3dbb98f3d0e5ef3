"""The bundled turbine (resources/examples/turbine.py, paper §4): the model has the paper's
dimensions; the main job (the base as a thin wall, the blades as curved layers grown from the
base's outer surface) gives the paper's 54 ± 2 base paths and 20 ± 1 blade layers, exports one
program, and the document saves and reopens with its layers and paths."""

import json
import math
import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))
sys.path.insert(0, os.path.join(os.environ.get("CURVEDSLICER_SOURCE_DIR", ""), "resources",
                                "examples"))

import FreeCAD  # noqa: E402
import Part  # noqa: E402

import cs_testing  # noqa: E402
import turbine  # noqa: E402
from freecad.curvedslicer import api  # noqa: E402


class TestTurbine(cs_testing.DocumentTestCase):
    def test_model_has_the_papers_dimensions(self):
        parts = turbine.build_turbine(self.doc)
        surface = parts["BaseOuterSurface"].Shape
        edges = sorted(surface.Edges, key=lambda e: e.BoundBox.ZMin)
        circles = [e for e in edges if isinstance(e.Curve, Part.Circle)]
        self.assertEqual(sorted(round(c.Curve.Radius, 6) for c in circles), [50.0, 100.0])
        self.assertAlmostEqual(surface.BoundBox.ZLength, 55.0, places=6)
        blades = parts["Blades"].Shape
        self.assertEqual(len(blades.Solids), turbine.BLADES)
        self.assertTrue(all(s.isValid() for s in blades.Solids))
        # Blade thickness and twist, measured on each blade: its end faces on the plate (z = 0)
        # and at the top (z = 55) are 38° apart about the axis, and the top face (a section
        # nearly normal to the profile there) is 10 mm wide.
        for blade in blades.Solids:
            ends = {}
            for z in (0.0, turbine.HEIGHT):
                faces = [f for f in blade.Faces if abs(f.BoundBox.ZMin - z) < 1e-6
                         and abs(f.BoundBox.ZMax - z) < 1e-6]
                self.assertTrue(faces, "no blade face at z=%g" % z)
                c = sum((f.CenterOfMass * f.Area for f in faces), FreeCAD.Vector())
                ends[z] = (math.degrees(math.atan2(c.y, c.x)), faces)
            twist = (ends[turbine.HEIGHT][0] - ends[0.0][0] + 180.0) % 360.0 - 180.0
            self.assertAlmostEqual(twist, 38.0, delta=0.5)
            top = ends[turbine.HEIGHT][1][0]
            phi = math.radians(ends[turbine.HEIGHT][0])
            across = [p.x * -math.sin(phi) + p.y * math.cos(phi)
                      for p in top.Wires[0].discretize(400)]
            self.assertAlmostEqual(max(across) - min(across), 10.0, delta=0.05)
        # The base paths: floor(profile length / 1.65) = 54 (the paper: 54).
        self.assertEqual(int(turbine.profile_length() // 1.65), 54)
        base = parts["Base"].Shape
        self.assertTrue(base.isValid() and len(base.Solids) == 1)
        self.assertGreaterEqual(base.BoundBox.ZMin, -1e-6)

    def test_turbine_jobs_give_the_papers_counts_and_reopen(self):
        # The main job on coarse voxels (1.5 mm; the example uses 1 mm): base 54 ± 2 thin-wall
        # paths, blades 20 ± 1 curved layers with paths, one program for both.
        parts, base, blades = turbine.make_turbine_jobs(self.doc, voxel=1.5)
        api.run(base, progress=False)
        api.run(blades, progress=False)
        self.assertLessEqual(abs(base.PathCount - 54), 2, base.PathCount)
        self.assertEqual(base.PlanLayerCount, base.PathCount)  # one bead per wall layer
        self.assertLessEqual(abs(blades.LayerCount - 20), 1, blades.LayerCount)
        for layer in api.layers(blades)[:3]:
            self.assertAlmostEqual(layer.ThicknessMean, 1.5, delta=0.15)
        self.assertGreaterEqual(blades.PathCount, blades.PlanLayerCount)
        self.assertGreaterEqual(blades.PlanLayerCount, blades.LayerCount - 1)
        self.check_void_markers_on_curved_layers(blades)
        spacing = api.path_spacing(base)
        self.assertLess(abs(sorted(spacing)[len(spacing) // 2] - 1.65), 0.05)
        program = cs_testing.tmp_path("TURBINE.JBI")
        result = api.export([base, blades], program, format="jbi", program_name="TURBINE",
                            warn_unreachable=True, tool_along_travel=False)
        self.assertEqual(result["arc_count"], base.PathCount + blades.PathCount)
        self.assertTrue(os.path.exists(program))
        path = cs_testing.tmp_path("turbine.FCStd")
        self.doc.saveAs(path)
        out = cs_testing.run_in_new_process(
            "import FreeCAD\nfrom freecad.curvedslicer import api\n"
            "doc = FreeCAD.openDocument(%r)\nbase, blades = doc.BaseJob, doc.BladesJob\n"
            "print('RESULT ' + json.dumps({'layers': blades.LayerCount, 'base': base.PathCount, "
            "'meshes': [o.Mesh.CountFacets > 0 for o in api.layers(blades)], "
            "'paths': len(api.path_features(blades)) + len(api.path_features(base))}))" % path)
        self.assertEqual(out.get("layers"), blades.LayerCount, out)
        self.assertEqual(out.get("base"), base.PathCount, out)
        self.assertTrue(all(out["meshes"]))
        self.assertEqual(out["paths"], blades.PlanLayerCount + base.PlanLayerCount)

    def check_void_markers_on_curved_layers(self, blades):
        """The uncovered-region discs on the curved blade layers: one per void the plan lists,
        VOID_LIFT from its centre, each in the tangent plane of its layer (the normal within 25° of
        the nearest facet's, either side) wherever the layer is smooth under the disc; on a fold
        (the facets within the disc's radius turn by more than 50° between them) the disc can only
        follow the surface's mean, so those are counted apart, and they must stay a minority."""
        import numpy as np

        from freecad.curvedslicer.stages import voids

        api.show_voids(blades)
        markers = api.void_markers(blades)
        report = {layer["layer"]: layer["coverage"]["voids"]
                  for layer in json.loads(blades.CoverageReport)["layers"]}
        self.assertEqual(sorted(m.LayerIndex for m in markers),
                         sorted(k for k, v in report.items() if v))
        surfaces = {layer.LayerIndex: layer for layer in api.layers(blades)}
        checked = aligned = folds = 0
        for marker in markers:
            faces = marker.Shape.Faces
            self.assertEqual(len(faces), len(report[marker.LayerIndex]))
            surface = surfaces.get(marker.LayerIndex)
            if surface is None:
                continue
            points, triangles = surface.Mesh.Topology
            corners = np.array([[tuple(p) for p in points]])[0][np.array(triangles)]
            centroids = corners.mean(axis=1)
            normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
            normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
            for face, void in zip(faces, report[marker.LayerIndex]):
                centre = np.array(void["centre_mm"])
                self.assertAlmostEqual((face.CenterOfMass - FreeCAD.Vector(*centre)).Length,
                                       voids.VOID_LIFT, delta=1e-6)
                distance = np.linalg.norm(centroids - centre, axis=1)
                nearest = normals[int(np.argmin(distance))]
                normal = face.normalAt(0, 0)
                checked += 1
                # A fold: two facets under the disc (within its radius, at least 1 mm) whose
                # normals differ by more than 50°, so no plane is within 25° of both.
                under = normals[distance <= max(math.sqrt(void["area_mm2"] / math.pi), 1.0)]
                if len(under) > 1 and float(np.min(under @ under.T)) < math.cos(math.radians(50)):
                    folds += 1
                    continue
                aligned += abs(float(np.dot(tuple(normal), nearest))) > math.cos(math.radians(25))
        # A disc's normal is the surface's averaged over its radius: where a void lies on a fold
        # (the slivers where the outer layers graze the blades' tops) the nearest facet differs.
        print("void discs within 25 degrees of the nearest facet's normal: %d of %d off folds"
              " (%d on folds)" % (aligned, checked - folds, folds))
        self.assertGreater(checked - folds, 0)
        self.assertEqual(aligned, checked - folds)
        self.assertLess(folds, 0.5 * checked)
        api.show_voids(blades, False)


cs_testing.main(__name__)
