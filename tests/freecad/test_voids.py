"""Headless tests of the uncovered-region markers (stages/voids.py): after a run,
api.show_voids draws one feature per plan layer with voids holding one disc per void of the plan's
coverage, at the void's centre (lifted VOID_LIFT along the layer normal) with the void's area; the
markers hide and reappear with the toggle, follow the layer isolated by show_layer, are redrawn
when the plan changes and survive save → reopen."""

import math
import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import FreeCAD  # noqa: E402

import cs_testing  # noqa: E402
from freecad.curvedslicer import api  # noqa: E402
from freecad.curvedslicer.core import native  # noqa: E402
from freecad.curvedslicer.stages import voids  # noqa: E402


def layers_with_voids(job):
    """{plan layer (1-based): [void]} of the stored plan's coverage."""
    return {layer["index"] + 1: layer["coverage"]["voids"]
            for layer in native.plan_summary(job.PlanJson)["per_layer"]
            if layer["coverage"] is not None and layer["coverage"]["voids"]}


class TestVoids(cs_testing.DocumentTestCase):
    def job(self, bead_spacing=4.0):
        # 11 mm wide at s = 4: one ring covers 8 mm of the width, a strip about 3 mm wide along
        # the middle stays uncovered on every layer.
        return api.make_job(self.doc, self.box(30, 11, 6), layer_thickness=2.0, voxel_size=1.0,
                            bead_spacing=bead_spacing, point_spacing=2.0, cell_file="")

    def assert_markers_match_plan(self, job):
        expected = layers_with_voids(job)
        self.assertTrue(expected, "the test part must have voids")
        markers = api.void_markers(job)
        self.assertEqual([m.LayerIndex for m in markers], sorted(expected))
        for marker in markers:
            report = expected[marker.LayerIndex]
            self.assertEqual(marker.VoidCount, len(report))
            self.assertEqual(len(marker.Voids), len(report))
            faces = marker.Shape.Faces
            self.assertEqual(len(faces), len(report))
            for face, void, centre in zip(faces, report, marker.VoidCentres):
                planned = FreeCAD.Vector(*void["centre_mm"])
                self.assertLess((centre - planned).Length, 1e-9)
                # the disc's centre is the void's, lifted along the layer normal
                offset = (face.CenterOfMass - planned).Length
                self.assertAlmostEqual(offset, voids.VOID_LIFT, delta=1e-6)
                radius = max(math.sqrt(void["area_mm2"] / math.pi), voids.VOID_MIN_RADIUS)
                self.assertAlmostEqual(face.Area, math.pi * radius ** 2,
                                       delta=1e-3 * face.Area)
        return markers

    def test_markers_where_the_report_says_and_toggle(self):
        job = self.job()
        api.run(job, progress=False)
        self.assertEqual(api.void_markers(job), [])
        self.assertFalse(api.voids_shown(job))
        self.assertNotIn("Touched", job.State)
        api.show_voids(job)
        self.assertTrue(api.voids_shown(job))
        self.assertNotIn("Touched", job.State)  # nothing for a recompute to redo
        self.assertNotIn("Touched", job.PathsGroup.State)
        markers = self.assert_markers_match_plan(job)
        self.assertTrue(all(m.Visibility for m in markers))
        api.show_voids(job, False)
        self.assertFalse(api.voids_shown(job))
        self.assertFalse(any(m.Visibility for m in api.void_markers(job)))
        self.assertEqual(len(api.void_markers(job)), len(markers))  # hidden, not removed
        api.show_voids(job, True)
        self.assertTrue(all(m.Visibility for m in api.void_markers(job)))
        # One layer isolated: only its markers; all layers again: all of them.
        chosen = markers[-1].LayerIndex
        api.show_layer(job, chosen)
        self.assertEqual([m.LayerIndex for m in api.void_markers(job) if m.Visibility], [chosen])
        api.show_layer(job, 0)
        self.assertTrue(all(m.Visibility for m in api.void_markers(job)))
        # Hidden, isolating a layer shows none.
        api.show_voids(job, False)
        api.show_layer(job, chosen)
        self.assertFalse(any(m.Visibility for m in api.void_markers(job)))

    def test_markers_follow_a_new_plan(self):
        job = self.job()
        api.run(job, progress=False)
        api.show_voids(job)
        before = [(m.LayerIndex, list(m.VoidCentres)) for m in api.void_markers(job)]
        job.BeadSpacing = 3.3
        api.run(job, progress=False)
        after = self.assert_markers_match_plan(job)
        self.assertNotEqual(before, [(m.LayerIndex, list(m.VoidCentres)) for m in after])
        self.assertEqual(voids.voids_group(job).VoidsDigest, voids.plan_text_digest(job))

    def test_a_plan_without_coverage_has_no_markers(self):
        job = self.job()
        job.MeasureCoverage = False
        api.run(job, progress=False)
        api.show_voids(job)
        self.assertEqual(api.void_markers(job), [])

    def test_markers_survive_save_and_reopen(self):
        job = self.job()
        api.run(job, progress=False)
        api.show_voids(job)
        expected = [(m.LayerIndex, m.VoidCount) for m in api.void_markers(job)]
        path = cs_testing.tmp_path("curvedslicer_voids.FCStd")
        self.doc.saveAs(path)
        result = cs_testing.run_in_new_process(
            "import FreeCAD\n"
            "from freecad.curvedslicer import api\n"
            "doc = FreeCAD.openDocument(%r)\n"
            "job = doc.getObject(%r)\n"
            "print('RESULT ' + json.dumps({'shown': api.voids_shown(job), 'markers': "
            "[[m.LayerIndex, m.VoidCount] for m in api.void_markers(job)]}))\n"
            % (path, job.Name))
        self.assertNotIn("error", result)
        self.assertTrue(result["shown"])
        self.assertEqual([tuple(m) for m in result["markers"]], expected)


cs_testing.main(__name__)
