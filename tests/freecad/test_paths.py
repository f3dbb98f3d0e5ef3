"""Headless tests of paths, plan, poses and export (freecadcmd): bead spacing on curved layers and
on a thin wall, positioner angles that turn V onto gravity, path parameters replan without
rerunning the layers, save -> reopen in a new process -> byte-identical programs, every export
format written all or nothing, and the errors of bad export requests."""

import glob
import json
import math
import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import FreeCAD  # noqa: E402
import Part  # noqa: E402

import cs_testing  # noqa: E402
from freecad.curvedslicer import api  # noqa: E402
from freecad.curvedslicer.core import InvalidInput, native  # noqa: E402


class PathTestCase(cs_testing.DocumentTestCase):
    def box_job(self, bead_spacing=4.0, width=30, fill_gaps=True):
        box = self.box(40, width, 6)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0,
                           bead_spacing=bead_spacing, point_spacing=2.0, cell_file="",
                           fill_gaps=fill_gaps)
        api.run(job, progress=False)
        return job

    def wall_job(self, r1, r2, height, bead_spacing=1.65):
        """A thin wall on the lateral face of a cone (cylinder when r1 == r2)."""
        if r1 == r2:
            shape = Part.makeCylinder(r1, height)
        else:
            shape = Part.makeCone(r1, r2, height)
        lateral = max(shape.Faces, key=lambda f: f.Area if f.Surface.__class__.__name__
                      in ("Cylinder", "Cone") else 0.0)
        surface = self.doc.addObject("Part::Feature", "Wall")
        surface.Shape = lateral
        solid = self.doc.addObject("Part::Feature", "WallSolid")
        solid.Shape = shape
        self.doc.recompute()
        job = api.make_job(self.doc, solid, plan_kind="ThinWall", wall_surface=surface,
                           bead_spacing=bead_spacing, point_spacing=2.0, voxel_size=1.0,
                           cell_file="")
        api.run(job, progress=False)
        return job


class TestPaths(PathTestCase):
    def test_curved_layer_beads_are_one_bead_spacing_apart(self):
        # 32 mm wide: the innermost ring's sides are exactly s apart, so every path is a ring.
        job = self.box_job(bead_spacing=4.0, width=32)
        self.assertEqual(job.LayerCount, 2)
        self.assertEqual(job.PlanLayerCount, 2)
        # The rings of a layer are joined into one path (connected insets): beads, not paths.
        self.assertGreater(len(api.path_beads(job)), 2)
        spacing = api.path_spacing(job)
        self.assertTrue(spacing)
        # Contour-parallel rings on flat layers: neighbours exactly s apart (fit tolerance 0.05).
        self.assertLess(max(abs(d - 4.0) for d in spacing), 0.06, spacing)
        # 30 mm wide, the innermost ring's sides would be 2 mm apart: one open centre bead on
        # y = 15 instead (NarrowStrips CentreBead), s + 1 mm from the ring beside it, reported;
        # with Overlap every path stays a closed ring. Gap fill off: it would widen the beads
        # beside the 1 mm strips and move them (checked below).
        narrow = self.box_job(bead_spacing=4.0, width=30, fill_gaps=False)
        spacing = sorted(api.path_spacing(narrow))
        self.assertLess(abs(spacing[0] - 4.0), 0.06, spacing)
        self.assertLess(abs(spacing[-1] - 5.0), 0.06, spacing)
        self.assertTrue(any("centre bead" in w for layer in json.loads(narrow.PlanJson)["layers"]
                            for w in layer["warnings"]))
        self.assertEqual(sum(1 for _, _, ring in api.path_beads(narrow) if not ring), 2)
        narrow_layers = json.loads(narrow.PlanJson)["layers"]
        # Gap fill on: the beads beside the 1 mm strips widen into them, so less area is void.
        narrow.FillGaps = True
        self.doc.recompute()
        filled = json.loads(narrow.PlanJson)["layers"]
        self.assertTrue(json.loads(narrow.PlanJson)["parameters"]["fill_gaps"])
        self.assertTrue(all(after["coverage"]["void_share"] < before["coverage"]["void_share"]
                            for before, after in zip(narrow_layers, filled)),
                        [(b["coverage"]["void_share"], a["coverage"]["void_share"])
                         for b, a in zip(narrow_layers, filled)])
        narrow.FillGaps = False
        narrow.NarrowStrips = "Overlap"
        self.doc.recompute()
        self.assertTrue(all(ring for _, _, ring in api.path_beads(narrow)))
        self.assertEqual(json.loads(narrow.PlanJson)["parameters"]["narrow_strips"], "overlap")
        features = api.path_features(job)
        self.assertEqual(len(features), 2)
        for feature in features:
            self.assertEqual(len(feature.Shape.Wires), feature.PathCount)
            z = [v.Point.z for v in feature.Shape.Vertexes]
            self.assertAlmostEqual(min(z), max(z), delta=0.05)
            self.assertAlmostEqual(min(z), 2.0 * feature.LayerIndex, delta=0.05)
        travel = [o for o in job.PathsGroup.Group if "TravelMoves" in o.PropertiesList][0]
        self.assertEqual(travel.TravelMoves, job.PathCount - 1)
        self.assertTrue(job.PathsStatus.startswith("Planned"), job.PathsStatus)

    def test_thin_wall_beads_are_equidistant_from_the_lower_edge(self):
        job = self.wall_job(20.0, 20.0, 10.0, bead_spacing=1.65)
        self.assertEqual(job.LayerCount, 0)  # no volume layers for a thin wall
        self.assertEqual(job.PathCount, int(10.0 // 1.65))  # beads at 1.65, 3.3, ... 9.9 mm
        heights = sorted(f.Shape.BoundBox.ZMin for f in api.path_features(job))
        for k, z in enumerate(heights, start=1):
            self.assertAlmostEqual(z, 1.65 * k, delta=0.03)
        spacing = api.path_spacing(job)
        self.assertLess(max(abs(d - 1.65) for d in spacing), 0.03, spacing)

    def test_layer_without_room_for_a_bead_has_a_null_shape(self):
        # A cone narrowing from r = 20 to 0.5 mm: with 12 mm beads the top layer (r about 2.5 mm)
        # is narrower than the minimum feature width 0.5·s = 6 mm even for a centre bead or spot.
        cone = self.doc.addObject("Part::Feature", "Cone")
        cone.Shape = Part.makeCone(20, 0.5, 10)
        self.doc.recompute()
        job = api.make_job(self.doc, cone, layer_thickness=1.0, voxel_size=0.5, bead_spacing=12.0,
                           cell_file="")
        api.run(job, progress=False)
        features = api.path_features(job)
        empty = [f for f in features if f.PathCount == 0]
        self.assertTrue(empty and len(empty) < len(features), [f.PathCount for f in features])
        for feature in features:
            # An empty compound would have no bounding box for the 3D view.
            self.assertEqual(feature.Shape.isNull(), feature.PathCount == 0, feature.Label)
        warnings = [w for layer in json.loads(job.PlanJson)["layers"] for w in layer["warnings"]]
        self.assertTrue(any("no room for a bead" in w for w in warnings), warnings)

    def test_path_parameter_replans_without_rerunning_the_layers(self):
        job = self.box_job(bead_spacing=4.0)
        runs, digest, beads = job.RunCount, job.PlanDigest, len(api.path_beads(job))
        job.BeadSpacing = 6.0
        self.doc.recompute()
        self.assertEqual(job.RunCount, runs)  # the layers were not recomputed
        self.assertNotEqual(job.PlanDigest, digest)
        self.assertLess(len(api.path_beads(job)), beads)  # rings joined: count beads, not paths
        self.assertLess(max(abs(d - 6.0) for d in api.path_spacing(job)), 0.06)
        self.assertEqual(sum(f.PathCount for f in api.path_features(job)), job.PathCount)
        # The corner angle reaches the fit (at 180° every ring is one smooth spline that rounds
        # its corners within the fit tolerance; the C++ test
        # ContourPaths.CornerAngleDecidesWhichCornersStayExact measures it); it replans the
        # paths only.
        sharp = [p[3].tolist() for p in native.plan_paths(job.PlanJson)]
        digest = job.PlanDigest
        job.CornerAngle = 180.0
        self.doc.recompute()
        self.assertEqual(job.RunCount, runs)
        self.assertNotEqual(job.PlanDigest, digest)
        plan = json.loads(job.PlanJson)
        self.assertEqual(plan["parameters"]["corner_angle_deg"], 180.0)
        self.assertLessEqual(json.loads(job.PlanStats)["max_fit_deviation_mm"], 0.05 + 1e-9)
        self.assertNotEqual([p[3].tolist() for p in native.plan_paths(job.PlanJson)], sharp)
        job.CornerAngle = 0.0
        with self.assertRaisesRegex(InvalidInput, r"CornerAngle must be in \(0, 180\] degrees"):
            api.run(job, progress=False)
        job.CornerAngle = 30.0
        self.doc.recompute()
        # A layer parameter reruns both stages.
        job.LayerThickness = 2.5
        self.doc.recompute()
        api.recompute(job)
        self.assertEqual(job.RunCount, runs + 1)
        self.assertEqual(job.LayerCount, 2)  # at 2.5 and 5 mm
        self.assertEqual(len(api.path_features(job)), job.PlanLayerCount)
        for feature in api.path_features(job):
            z = feature.Shape.BoundBox.ZMin
            self.assertAlmostEqual(z, 2.5 * feature.LayerIndex, delta=0.05)
        # Nothing changed: nothing reruns.
        self.assertEqual(api.run(job, progress=False), (False, False))


class TestPoses(PathTestCase):
    def test_pose_turns_the_deposition_direction_onto_gravity(self):
        # A cone wall leaning inwards by 45 degrees: V runs down the slope, so the positioner must
        # tilt the part for V to point along gravity.
        job = self.wall_job(30.0, 15.0, 15.0, bead_spacing=1.65)
        count = api.pose_count(job)
        self.assertEqual(count, job.PoseCount)
        self.assertGreater(count, 50)
        motion = api.motion(job)
        part = [o for o in job.PosesGroup.Group if getattr(o, "PoseRole", "") == "PosePart"][0]
        # weld points (kind 0 = path; the program starts and ends at the cell's home pose)
        welds = [i for i in range(count) if int(motion["kind"][i]) == 0]
        self.assertEqual(int(motion["kind"][0]), 4)  # home
        # Beads 0 and 1 (1.2 and 2.3 mm up the 45 degree wall, nearer the plate than the bead
        # before them or farther by less than half a bead) are laid onto the plate: no tilt.
        first = api.set_pose(job, welds[0])[0]
        self.assertLess(abs(first), 1.0)
        above = [i for i in welds if int(motion["layer"][i]) >= 2]
        self.assertGreater(len(above), 20)
        for index in (above[0], above[len(above) // 3], above[len(above) // 2], above[-1]):
            a1, a2 = api.set_pose(job, index)
            self.assertAlmostEqual(a1, math.degrees(motion["a1"][index]), places=9)
            self.assertAlmostEqual(a2, math.degrees(motion["a2"][index]), places=9)
            v = FreeCAD.Vector(*motion["deposition"][index].tolist())
            turned = part.Placement.Rotation.multVec(v)
            # on gravity within the 3 degrees the smooth positioner may leave
            self.assertLess(turned.getAngle(FreeCAD.Vector(0, 0, -1)), math.radians(3.0) + 1e-9)
            self.assertLess((job.PoseDeposition - turned).Length, 1e-9)
            # The deposited direction is not vertical in the part frame: the tilt does the work.
            self.assertGreater(abs(a1), 20.0)
        # The table carries the part: the part frame origin stays on the table's axis, where
        # the motion placed it (resting on the table: lifted along the table's z).
        table = [o for o in job.PosesGroup.Group if getattr(o, "PoseRole", "")
                 == "PositionerTable"][0]
        in_table = table.Placement.inverse().multiply(part.Placement)
        self.assertLess(math.hypot(in_table.Base.x, in_table.Base.y), 1e-6)
        self.assertAlmostEqual(in_table.Base.z, motion["table_to_part"][2][3], places=6)


class TestExport(PathTestCase):
    def test_every_format_is_written_all_or_nothing(self):
        job = self.box_job()
        folder = cs_testing.tmp_path("export_all")
        os.makedirs(folder, exist_ok=True)
        for name, extension in api.export_formats():
            target = os.path.join(folder, "BOX" + extension)
            # the Job's cell is the (Yaskawa) default: KRL, RAPID and LS need the option
            result = api.export(job, target, format=name, allow_foreign_cell=True)
            self.assertEqual(result["format"], name)
            self.assertGreater(result["motion_count"], 0)
            with open(target, "rb") as f:
                self.assertEqual(f.read(), result["files"][0][1])
        # A folder that does not exist: IoError and no file anywhere.
        missing = os.path.join(folder, "missing", "BOX.JBI")
        with self.assertRaises(api.IoError):
            api.export(job, missing, format="jbi")
        self.assertFalse(os.path.exists(os.path.dirname(missing)))
        self.assertFalse(glob.glob(os.path.join(folder, "*.tmp*")))

    def test_bad_export_requests_raise_invalid_input(self):
        box = self.box(10, 10, 4)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0)
        with self.assertRaisesRegex(api.InvalidInput, "no plan to export"):
            api.export(job, cs_testing.tmp_path("none.JBI"))
        job = self.box_job()
        with self.assertRaisesRegex(api.InvalidInput, "jbi"):
            api.export(job, cs_testing.tmp_path("x.prg"), format="fanuc-karel")
        with self.assertRaises(api.InvalidInput):
            api.export(job, cs_testing.tmp_path("x.JBI"), cell_file=__file__)  # not a cell
        # KRL is KUKA's language; the Job's cell (the default) is a Yaskawa cell: refused, no
        # file, unless allowed; a KUKA cell writes it.
        krl = cs_testing.tmp_path("foreign.src")
        with self.assertRaisesRegex(api.InvalidInput,
                                    "cell is for a yaskawa controller but the format krl"):
            api.export(job, krl, format="krl")
        self.assertFalse(os.path.exists(krl))
        self.assertGreater(api.export(job, krl, format="krl",
                                      allow_foreign_cell=True)["total_bytes"], 0)
        kuka = os.path.join(os.environ.get("CURVEDSLICER_SOURCE_DIR", ""), "resources",
                            "cells", "kuka_kr16_r1610_2_dkp400.json")
        self.assertGreater(api.export(job, None, format="krl", cell_file=kuka)["total_bytes"], 0)
        with self.assertRaisesRegex(api.InvalidInput, "kuka controller but the format jbi"):
            api.export(job, None, format="jbi", cell_file=kuka)

    def test_reopened_document_reexports_identical_programs_without_recompute(self):
        job = self.box_job()
        path = cs_testing.tmp_path("paths_reopen.FCStd")
        self.doc.saveAs(path)
        programs = {}
        for name in ("jbi", "krl", "csv"):
            result = api.export(job, None, format=name, allow_foreign_cell=True)
            programs[name] = [(n, text.decode("latin-1")) for (n, text, _) in result["files"]]
        out = cs_testing.run_in_new_process(
            "import FreeCAD\nfrom freecad.curvedslicer import api\n"
            "doc = FreeCAD.openDocument(%r)\njob = doc.getObject(%r)\n"
            "touched = [o.Name for o in doc.Objects if 'Touched' in o.State]\n"
            "progs = {}\n"
            "for name in ('jbi', 'krl', 'csv'):\n"
            "    r = api.export(job, None, format=name, allow_foreign_cell=True)\n"
            "    progs[name] = [(n, t.decode('latin-1')) for (n, t, _) in r['files']]\n"
            "print('RESULT ' + json.dumps({'touched': touched, 'programs': progs, "
            "'runs': job.RunCount, 'paths': len(api.path_features(job)), "
            "'plan': job.PlanJson == api.plan_json(job)}))" % (path, job.Name))
        self.assertNotIn("error", out, out)
        self.assertEqual(out["touched"], [])
        self.assertEqual(out["runs"], job.RunCount)
        self.assertEqual(out["paths"], len(api.path_features(job)))
        self.assertTrue(out["plan"])
        for name in programs:
            self.assertEqual([tuple(f) for f in out["programs"][name]], programs[name], name)


cs_testing.main(__name__)
