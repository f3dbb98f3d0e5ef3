"""Headless tests of what a Job shows (stages/views.py) and of the pose simulation's features
(stages/simulation.py): one layer isolated with its surface and paths, the layer's numbers from
the plan, the cell toggle, results shown after a run; at a motion point the torch tip on the
TCP (the part-frame point carried by the part), the stick robot ending at the flange the joints
reach, the deposit counting the welded moves; the features saved and reopened in a new process
as they were; a plan layer's coverage object passed through as the plan has it."""

import json
import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import FreeCAD  # noqa: E402

import cs_testing  # noqa: E402
from freecad.curvedslicer import api  # noqa: E402
from freecad.curvedslicer.core import InvalidInput, native  # noqa: E402
from freecad.curvedslicer.stages import paths as path_stage  # noqa: E402
from freecad.curvedslicer.stages import deviations, poses, simulation, views  # noqa: E402

CHECK = '''
import FreeCAD
doc = FreeCAD.openDocument(PATH)
job = doc.getObject("Job")
from freecad.curvedslicer.stages import poses
cell = poses.pose_objects(job)
out = {"roles": sorted(cell), "deposit": cell["Deposit"].DepositMoves,
       "edges": len(cell["Deposit"].Shape.Edges),
       "torch": list(cell["Torch"].Placement.Base), "point": job.PosePoint,
       "touched": [o.Name for o in doc.Objects if "Touched" in o.State]}
print("RESULT " + json.dumps(out))
'''


def _vector(rows):
    m = FreeCAD.Matrix(*[float(v) for row in rows for v in row])
    return m.multiply(FreeCAD.Vector(0, 0, 0))


class TestSimulation(cs_testing.DocumentTestCase):
    def planned_job(self):
        box = self.box(30, 20, 12)
        box.Placement.Base = FreeCAD.Vector(-15, -10, 0)
        self.doc.recompute()
        job = api.make_job(self.doc, box, start=(box, ["Face5"]), layer_thickness=3.0,
                           voxel_size=1.0, cell_file="")
        api.run(job, progress=False)
        return job

    def test_one_layer_isolated(self):
        job = self.planned_job()
        self.assertGreaterEqual(job.PlanLayerCount, 3)
        api.show_layer(job, 2)
        shown = [o for o in api.layers(job) if o.Visibility]
        paths = [o for o in api.path_features(job) if o.Visibility]
        self.assertEqual([o.LayerIndex for o in shown], [2])
        self.assertEqual([o.LayerIndex for o in paths], [2])
        self.assertAlmostEqual(float(shown[0].Height), float(paths[0].Height), places=9)
        self.assertFalse(path_stage.travel_object(job).Visibility)
        api.show_layer(job, 0)
        self.assertTrue(all(o.Visibility for o in api.layers(job) + api.path_features(job)))
        self.assertTrue(path_stage.travel_object(job).Visibility)
        api.set_layer_range(job, 2, 3)
        self.assertEqual([o.Visibility for o in api.path_features(job)], [False, True, True])

    def test_layer_info_is_the_plans(self):
        job = self.planned_job()
        layer = json.loads(job.PlanJson)["layers"][1]
        info = api.layer_info(job, 2)
        self.assertEqual(info["index"], 2)
        self.assertEqual(info["count"], job.PlanLayerCount)
        self.assertEqual(info["height"], layer["height_mm"])
        self.assertEqual(info["paths"], len(layer["paths"]))
        self.assertEqual(info["points"], sum(len(p["points"]) for p in layer["paths"]))
        self.assertEqual(info["warnings"][:len(layer["warnings"])], layer["warnings"])
        self.assertEqual(info["coverage"], layer.get("coverage"))
        with self.assertRaises(InvalidInput):
            api.layer_info(job, job.PlanLayerCount + 1)

    def test_motion_warnings_of_a_layer(self):
        job = self.planned_job()
        job.MotionWarnings = ["layer 1 path 0 point 3: near singular", "layer 10 path 2",
                              "travel to layer 0"]
        self.assertEqual(views._motion_warnings(job, 2), ["layer 1 path 0 point 3: near "
                                                          "singular"])
        self.assertEqual(views._motion_warnings(job, 1), ["travel to layer 0"])

    def test_coverage_passed_through(self):
        job = self.planned_job()
        plan = json.loads(job.PlanJson)
        coverage = {"measured": True, "void_share": 0.02, "overlap_share": 0.1, "arc_starts": 3}
        plan["layers"][0]["coverage"] = coverage
        job.PlanJson = json.dumps(plan)  # as a version-2 plan carries it
        self.assertEqual(api.layer_info(job, 1)["coverage"], coverage)

    def test_results_and_cell(self):
        job = self.planned_job()
        api.show_cell(job, True)
        self.assertTrue(api.cell_shown(job))
        self.assertFalse(any(o.Visibility for o in api.layers(job) + api.path_features(job)))
        api.show_results(job)
        self.assertFalse(job.Solid.Visibility)
        self.assertFalse(api.cell_shown(job))
        self.assertTrue(all(o.Visibility for o in api.layers(job) + api.path_features(job)))
        api.show_solid(job, True)
        self.assertTrue(job.Solid.Visibility)

    def test_torch_robot_and_deposit_at_a_point(self):
        job = self.planned_job()
        motion = api.motion(job)
        welded = [i for i, on in enumerate(motion["arc_on"]) if on]
        counts = []
        for index in (welded[0], welded[len(welded) // 2], welded[-1]):
            api.set_pose(job, index)
            cell = poses.pose_objects(job)
            tip = cell["Torch"].Placement.Base
            point = cell["PosePart"].Placement.multVec(
                FreeCAD.Vector(*motion["position"][index].tolist()))
            self.assertLess((tip - point).Length, 1e-6)
            self.assertLess((tip - _vector(motion["tool_in_world"][index])).Length, 1e-9)
            arm = native.robot_arm_points(motion["cell_json"], motion["joints"][index].tolist())
            self.assertLess((_vector(arm["tcp"]) - tip).Length, 1e-3)
            box = cell["Robot"].Shape.BoundBox
            for name in ("base", "shoulder", "elbow", "wrist", "flange"):
                self.assertTrue(box.isInside(FreeCAD.Vector(*arm[name])), name)
            deposit = cell["Deposit"]
            self.assertEqual(deposit.DepositMoves, sum(1 for i in welded if i <= index))
            self.assertEqual(deposit.Placement, cell["PosePart"].Placement)
            counts.append(deposit.DepositMoves)
            info = api.pose_info(job)
            self.assertEqual(info["index"], index)
            self.assertTrue(info["arc_on"])
            self.assertEqual(len(info["joints"]), 6)
            self.assertEqual(info["deposit_moves"], deposit.DepositMoves)
        self.assertEqual(counts, sorted(counts))
        self.assertEqual(counts[-1], len(welded))
        # The torch shape is the cell's envelope: its length from the tip to the top end.
        stickout, _, _, length = simulation.torch_envelope(motion["cell_json"])
        torch = poses.pose_objects(job)["Torch"].Shape.copy()
        torch.Placement = FreeCAD.Placement()
        self.assertAlmostEqual(torch.BoundBox.ZMin, -(stickout + length), places=6)
        self.assertAlmostEqual(torch.BoundBox.ZMax, 0.0, places=6)

    def test_deviations_by_range(self):
        # Five weld moves: each falls into the range of the larger angle of its two ends; moves
        # below 1 deg are not drawn; a point after an arc-off point starts no weld move.
        import math
        deg = math.radians
        m = {"arc_on": [False, True, True, True, False, True, True],
             "position": [(float(i), 0.0, 0.0) for i in range(7)],
             "torch_angle": [0.0, deg(0.5), deg(3.0), deg(7.5), deg(20.0), deg(12.0), 0.0],
             "residual": [0.0, 0.0, 0.0, deg(1.0), 0.0, 0.0, deg(5.0)]}
        got = deviations.deviation_segments(m)
        ends = {key: [int(b[0]) for (_, b) in moves] for key, moves in got.items()}
        self.assertEqual(ends[("torch", 0)], [2])     # max(0.5, 3) = 3
        self.assertEqual(ends[("torch", 1)], [3])     # max(3, 7.5) = 7.5
        self.assertEqual(ends[("torch", 2)], [5, 6])  # 20 (arc-off start) and 12
        self.assertEqual(ends[("gravity", 0)], [3])   # 1 deg: the first range includes 1
        self.assertEqual(ends[("gravity", 1)], [6])
        self.assertEqual(ends[("gravity", 2)], [])

    def test_deviation_features_follow_the_motion(self):
        # After a run the Job holds one feature per kind and range; each has exactly the weld
        # moves the motion puts in its range (counted here from the motion dict), and is hidden
        # when it has none.
        import math
        job = self.planned_job()
        m = api.motion(job)
        features = deviations.deviation_objects(job)
        self.assertEqual(sorted(features), [(k, r) for k in ("gravity", "torch")
                                            for r in range(3)])
        for (kind, r), feature in features.items():
            field = "torch_angle" if kind == "torch" else "residual"
            low, high = deviations.RANGES[r]
            count = 0
            for i in range(1, len(m["arc_on"])):
                angle = math.degrees(max(float(m[field][i - 1]), float(m[field][i])))
                if m["arc_on"][i] and angle >= low and (high is None or angle < high):
                    count += 1
            self.assertEqual(feature.DeviationMoves, count, feature.Label)
            self.assertEqual(len(feature.Shape.Edges) if count else 0, count, feature.Label)
            self.assertEqual(bool(feature.Visibility), count > 0, feature.Label)
            self.assertIn("deg", feature.Label)

    def test_saved_and_reopened(self):
        job = self.planned_job()
        motion = api.motion(job)
        index = [i for i, on in enumerate(motion["arc_on"]) if on][10]
        api.set_pose(job, index)
        cell = poses.pose_objects(job)
        path = cs_testing.tmp_path("simulation.FCStd")
        self.doc.saveAs(path)
        out = cs_testing.run_in_new_process(CHECK.replace("PATH", repr(path)))
        self.assertNotIn("error", out, out)
        self.assertEqual(out["roles"], sorted(cell))
        self.assertEqual(out["point"], index)
        self.assertEqual(out["deposit"], cell["Deposit"].DepositMoves)
        self.assertEqual(out["edges"], len(cell["Deposit"].Shape.Edges))
        self.assertLess((FreeCAD.Vector(*out["torch"]) - cell["Torch"].Placement.Base).Length,
                        1e-9)
        self.assertEqual(out["touched"], [])


cs_testing.main(__name__)
