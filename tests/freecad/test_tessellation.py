"""OpenCASCADE tessellation in the core: every triangle carries FreeCAD's FaceN, lies on that
face, the mesh is closed and outward oriented; STEP/BREP files give the same mesh; STL export."""

import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import numpy as np  # noqa: E402

import FreeCAD  # noqa: E402
import Part  # noqa: E402

import cs_testing  # noqa: E402
from freecad.curvedslicer import api  # noqa: E402
from freecad.curvedslicer.core import InvalidInput, native  # noqa: E402


def shapes():
    box = Part.makeBox(20, 10, 5)
    cylinder = Part.makeCylinder(6, 8, FreeCAD.Vector(30, 0, 0))
    fused = box.fuse(Part.makeSphere(4, FreeCAD.Vector(20, 5, 5)))
    return {"box": box, "cylinder": cylinder, "fused": fused}


class TestTessellation(cs_testing.DocumentTestCase):
    def test_triangles_carry_the_face_they_lie_on(self):
        for name, shape in shapes().items():
            mesh = native.tessellate_brep(shape.exportBrepToString(), deflection=0.05)
            v, t, ids = mesh["vertices"], mesh["triangles"], mesh["face_ids"]
            self.assertEqual(sorted(set(ids.tolist())), list(range(1, len(shape.Faces) + 1)), name)
            for k, face in enumerate(shape.Faces, start=1):
                tris = t[ids == k]
                centroids = v[tris].mean(axis=1)
                for c in centroids[:: max(1, len(centroids) // 20)]:
                    d = face.distToShape(Part.Vertex(FreeCAD.Vector(*c)))[0]
                    self.assertLess(d, 0.1, "%s Face%d: centroid %.3f mm off" % (name, k, d))
            report = native.analyze_mesh(v, t)
            self.assertTrue(report["closed"], name)
            self.assertEqual(report["inconsistent_edges"], 0, name)
            self.assertAlmostEqual(report["volume"], shape.Volume, delta=0.02 * shape.Volume)

    def test_placement_is_applied(self):
        box = Part.makeBox(10, 10, 10)
        box.Placement = FreeCAD.Placement(FreeCAD.Vector(100, 0, 0), FreeCAD.Rotation())
        v = native.tessellate_brep(box.exportBrepToString(), deflection=0.1)["vertices"]
        self.assertAlmostEqual(v[:, 0].min(), 100.0, places=9)

    def test_deflection_controls_the_chord_error(self):
        cylinder = Part.makeCylinder(10, 5)
        coarse = native.tessellate_brep(cylinder.exportBrepToString(), deflection=0.5)
        fine = native.tessellate_brep(cylinder.exportBrepToString(), deflection=0.01)
        self.assertGreater(len(fine["triangles"]), 3 * len(coarse["triangles"]))
        self.assertEqual(native.deflection_for_voxel_size(0.8), 0.2)

    def test_cad_files_and_stl_export(self):
        shape = shapes()["fused"]
        step, brep = cs_testing.tmp_path("part.step"), cs_testing.tmp_path("part.brep")
        shape.exportStep(step)
        shape.exportBrep(brep)
        from_text = native.tessellate_brep(shape.exportBrepToString(), deflection=0.1)
        from_brep = native.tessellate_cad_file(brep, deflection=0.1)
        self.assertTrue(np.array_equal(from_text["triangles"], from_brep["triangles"]))
        from_step = native.tessellate_cad_file(step, deflection=0.1)
        self.assertEqual(from_step["face_ids"].max(), len(shape.Faces))
        feature = self.doc.addObject("Part::Feature", "Part")
        feature.Shape = shape
        stl = cs_testing.tmp_path("part.stl")
        api.write_stl(feature, stl, deflection=0.1)
        back = native.read_mesh(stl)
        self.assertEqual(len(back["triangles"]), len(from_text["triangles"]))

    def test_bad_shapes(self):
        with self.assertRaises(InvalidInput):
            native.tessellate_brep("not a brep", deflection=0.1)
        wire = Part.makeCircle(5)
        with self.assertRaises(InvalidInput) as caught:
            native.tessellate_brep(wire.exportBrepToString(), deflection=0.1)
        self.assertIn("no faces", str(caught.exception))
        with self.assertRaises(InvalidInput):
            native.tessellate_brep(Part.makeBox(1, 1, 1).exportBrepToString(), deflection=0.0)
        with self.assertRaises(InvalidInput):
            native.tessellate_cad_file(cs_testing.tmp_path("missing.step"), deflection=0.1)


cs_testing.main(__name__)
