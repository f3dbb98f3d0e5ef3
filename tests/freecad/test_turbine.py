"""The bundled turbine (resources/examples/turbine.py, paper §4): the model has the paper's
dimensions, and a Job for the blades grown from the base's outer surface at 1.5 mm gives the
paper's 20 ± 1 layers; the document saves and reopens with its layers."""

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

    def test_blade_job_gives_the_papers_20_layers_and_reopens(self):
        parts = turbine.build_turbine(self.doc)
        job = api.make_job(self.doc, parts["Blades"], start=parts["BaseOuterSurface"],
                           layer_thickness=1.5, voxel_size=1.5, bead_spacing=3.7)
        api.run(job, progress=False)
        self.assertLessEqual(abs(job.LayerCount - 20), 1, job.LayerCount)
        for layer in api.layers(job)[:3]:
            self.assertAlmostEqual(layer.ThicknessMean, 1.5, delta=0.15)
        path = cs_testing.tmp_path("turbine.FCStd")
        self.doc.saveAs(path)
        out = cs_testing.run_in_new_process(
            "import FreeCAD\nfrom freecad.curvedslicer import api\n"
            "doc = FreeCAD.openDocument(%r)\njob = doc.getObject('Job')\n"
            "print('RESULT ' + json.dumps({'layers': job.LayerCount, 'meshes': "
            "[o.Mesh.CountFacets > 0 for o in api.layers(job)]}))" % path)
        self.assertEqual(out.get("layers"), job.LayerCount, out)
        self.assertTrue(all(out["meshes"]))


cs_testing.main(__name__)
