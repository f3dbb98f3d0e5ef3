"""Headless tests of the compiled module's options classes (cpp/bindings/option_bindings.cpp) and
of the jobs that take them: keyword construction, defaults equal to the core's documented ones,
repr, unknown keywords and bad enum names rejected (the latter with the core's message), nested
options changed in place, and the plan job in one call equal to the layer job followed by the
plan stage on its layers (same plan JSON)."""

import json
import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import numpy  # noqa: E402
import Part  # noqa: E402

import cs_testing  # noqa: E402
from freecad.curvedslicer import api  # noqa: E402
from freecad.curvedslicer.core import Cancelled, InvalidInput, native  # noqa: E402

# The defaults the core documents (field comments in cpp/include/curvedslicer/**, README),
# written down once here; the module must report the same, since it constructs `Options{}`.
DOCUMENTED_DEFAULTS = {
    "LayerJobOptions": {"voxel_size": 1.0, "layer_thickness": 1.5, "method": "anyangle",
                        "alignment": "pca", "memory_budget_bytes": 0.0, "cap_holes": False,
                        "clip_to_solid": True, "thickness_samples": 4096,
                        "max_layers": 100000, "simplify_layers": False, "layer_tolerance": 0.0},
    "VoxelizeOptions": {"voxel_size": 1.0, "alignment": "pca", "padding": 2,
                        "bytes_per_cell": 16.0},
    "StartSurface": {"kind": "plane", "plane_at_model_bottom": True,
                     "plane_normal": (0.0, 0.0, 1.0), "face_ids": []},
    "InitialCurve": {"kind": "boundary", "plane_normal": (1.0, 0.0, 0.0)},
    "PlannerOptions": {"bead_spacing": 3.7, "point_spacing": 2.0, "fit_tolerance": 0.05,
                       "corner_angle": 30.0, "surface_method": "accurate",
                       "narrow_strips": "centre_bead", "min_path_length": -1.0,
                       "seam_separation": -1.0, "improvement_passes": 4},
    "ThinWallOptions": {"bead_spacing": 1.65, "point_spacing": 2.0, "fit_tolerance": 0.05,
                        "corner_angle": 30.0, "edge": "lowest", "axis": (0.0, 0.0, 1.0),
                        "point": (0.0, 0.0, 0.0), "surface_method": "accurate"},
    "PlanJobOptions": {"thin_wall": None, "model_name": "", "start_spec": "",
                       "layer_format": "ply"},
    "MotionOptions": {"tool_along_travel": False, "unreachable": "throw",
                      "prefer_positive_tilt": True, "smoothing_length": 0.0,
                      "clearance": 10.0, "allow_collisions": False, "add_home": True,
                      "merge_tolerance": 0.01, "max_a2_step": 0.0872664625997165,  # 5°
                      "time_parameterise": True, "placement": "rest"},
    "ExportOptions": {"program_name": "", "date": "2000/01/01 00:00", "gcode_mode": "tcp",
                      "gcode_dialect": "generic", "gcode_max_lines_per_file": 40000,
                      "arc_output": 1},
}


def box_arrays(length=40.0, width=30.0, height=6.0):
    mesh = native.tessellate_brep(Part.makeBox(length, width, height).exportBrepToString(),
                                  deflection=0.1)
    return mesh["vertices"], mesh["triangles"], mesh["face_ids"]


def without_layer_surfaces(plan_json):
    plan = json.loads(plan_json)
    names = [layer.pop("surface") for layer in plan["layers"]]
    return plan, names


class TestOptionsClasses(cs_testing.DocumentTestCase):
    def test_defaults_are_the_documented_ones(self):
        for name, fields in DOCUMENTED_DEFAULTS.items():
            options = getattr(native, name)()
            for field, value in fields.items():
                self.assertEqual(getattr(options, field), value, "%s.%s" % (name, field))
        # A Job's CornerAngle defaults to the core's.
        job = api.make_job(self.doc, self.box(), cell_file="")
        corner = float(job.CornerAngle.getValueAs("deg"))
        self.assertEqual(native.PlannerOptions().corner_angle, corner)
        self.assertEqual(native.ThinWallOptions().corner_angle, corner)

    def test_every_field_round_trips(self):
        for name in DOCUMENTED_DEFAULTS:
            cls = getattr(native, name)
            default = cls()
            values = {f: getattr(default, f) for f in cls._fields}
            rebuilt = cls(**values)
            self.assertEqual(repr(rebuilt), repr(default), name)
            for field, value in values.items():
                setattr(rebuilt, field, value)
            self.assertEqual(repr(rebuilt), repr(default), name)

    def test_keyword_construction_and_repr(self):
        options = native.LayerJobOptions(layer_thickness=1.5, voxel_size=0.5, method="paper",
                                         start=native.StartSurface.horizontal_plane(2.0))
        self.assertEqual((options.layer_thickness, options.voxel_size, options.method),
                         (1.5, 0.5, "paper"))
        self.assertEqual(options.start.plane_point, (0.0, 0.0, 2.0))
        self.assertFalse(options.start.plane_at_model_bottom)
        text = repr(options)
        self.assertTrue(text.startswith("LayerJobOptions(start=StartSurface(kind='plane'"), text)
        for field in native.LayerJobOptions._fields:
            self.assertIn(field + "=", text)
        self.assertIn("layer_thickness=1.5", text)
        self.assertIn("method='paper'", text)
        surface = native.InitialCurve(kind="surface", surface=box_arrays()[:2])
        self.assertIn("surface=mesh(8 vertices, 12 triangles)", repr(surface))
        self.assertIn("corner_angle = 30.0", native.PlannerOptions.__doc__)
        # "exact" names the default any-angle method (the reference for approximations).
        self.assertEqual(native.LayerJobOptions(method="exact").method, "anyangle")

    def test_unknown_keyword_and_positional_arguments_are_rejected(self):
        with self.assertRaises(TypeError) as caught:
            native.PlannerOptions(bead_spacing=3.0, bead_spcing=4.0)
        self.assertIn("unknown option of PlannerOptions: 'bead_spcing'", str(caught.exception))
        self.assertIn("bead_spacing", str(caught.exception))
        with self.assertRaises(TypeError):
            native.PlannerOptions(3.0)
        with self.assertRaises(AttributeError):
            native.PlannerOptions().bead_spcing = 4.0

    def test_bad_values_are_rejected(self):
        cases = [
            (native.LayerJobOptions, "method", "bogus", "unknown geodesic method: 'bogus'"),
            (native.LayerJobOptions, "alignment", "x", "x"),
            (native.PlannerOptions, "surface_method", "exact",
             "unknown surface geodesic method: 'exact'; choose accurate or paper"),
            (native.PlannerOptions, "narrow_strips", "none", "unknown narrow-strip mode"),
            (native.ThinWallOptions, "edge", "top", "unknown thin-wall edge: 'top'"),
            (native.MotionOptions, "unreachable", "ignore",
             "unknown unreachable-point policy: 'ignore'"),
            (native.MotionOptions, "placement", "floor", "unknown part placement: 'floor'"),
            (native.ExportOptions, "gcode_mode", "abs", "unknown G-code mode: 'abs'"),
            (native.StartSurface, "kind", "sphere", "unknown start surface kind: 'sphere'"),
            (native.InitialCurve, "kind", "line", "unknown initial curve kind: 'line'"),
            (native.PlanJobOptions, "layer_format", "stl", "stl"),
        ]
        for cls, field, value, message in cases:
            with self.assertRaises(InvalidInput) as caught:
                cls(**{field: value})
            self.assertIn(message, str(caught.exception))
            options = cls()
            with self.assertRaises(InvalidInput):
                setattr(options, field, value)
            self.assertEqual(repr(options), repr(cls()), "a failed set changed %s" % field)
        with self.assertRaises(TypeError) as caught:
            native.PlannerOptions(bead_spacing="wide")
        self.assertIn("PlannerOptions.bead_spacing needs a number", str(caught.exception))
        with self.assertRaises(InvalidInput) as caught:
            native.ThinWallOptions(axis=(0, 1))
        self.assertIn("ThinWallOptions.axis needs 3 numbers: 2 given", str(caught.exception))
        with self.assertRaises(TypeError):
            native.PlanJobOptions(planner=native.ThinWallOptions())
        with self.assertRaises(InvalidInput) as caught:
            native.tessellate_cad_file(cs_testing.tmp_path("box.stl"), deflection=0.1,
                                       format="stl")
        self.assertIn("unknown CAD format: 'stl'", str(caught.exception))

    def test_nested_options_change_in_place(self):
        options = native.PlanJobOptions()
        options.planner.bead_spacing = 2.5
        options.layer_job.start.face_ids = [1, 2]
        options.planner.initial_curve = native.InitialCurve.plane((0, 0, 0), (1, 0, 0))
        self.assertEqual(options.planner.bead_spacing, 2.5)
        self.assertEqual(options.layer_job.start.face_ids, [1, 2])
        self.assertEqual(options.planner.initial_curve.describe(), "plane:0,0,0,1,0,0")
        self.assertIsNone(options.thin_wall)
        options.thin_wall = native.ThinWallOptions(edge="nearest", point=(1, 2, 3))
        self.assertEqual(options.thin_wall.point, (1.0, 2.0, 3.0))
        options.thin_wall = None
        self.assertIsNone(options.thin_wall)


class TestJobs(cs_testing.DocumentTestCase):
    def plan_job_options(self):
        return native.PlanJobOptions(
            layer_job=native.LayerJobOptions(layer_thickness=2.0, voxel_size=1.0),
            planner=native.PlannerOptions(bead_spacing=4.0),
            model_name="Box", start_spec="plane:bottom")

    def test_plan_job_equals_layer_job_then_plan_stage(self):
        vertices, triangles, face_ids = box_arrays()
        options = self.plan_job_options()
        whole = native.run_plan_job(vertices, triangles, face_ids, options=options)
        layers = native.run_layer_job(vertices, triangles, face_ids, options=options.layer_job)
        staged = native.plan_layers(layers["layers"],
                                    start_vertices=layers["source"]["vertices"],
                                    start_triangles=layers["source"]["triangles"],
                                    options=options)
        plan, names = without_layer_surfaces(whole["plan_json"])
        staged_plan, staged_names = without_layer_surfaces(staged["plan_json"])
        self.assertEqual(plan, staged_plan)
        self.assertEqual(names, whole["layer_files"])
        self.assertEqual(len(names), len(layers["layers"]))
        self.assertTrue(all(name.endswith(".ply") for name in names), names)
        self.assertEqual(set(staged_names), {""})
        self.assertEqual((plan["model"], plan["start"]), ("Box", "plane:bottom"))
        parameters = plan["parameters"]
        self.assertEqual((parameters["layer_thickness_mm"], parameters["voxel_size_mm"],
                          parameters["field_method"], parameters["bead_spacing_mm"]),
                         (2.0, 1.0, "anyangle", 4.0))
        self.assertEqual(len(whole["layers"]["layers"]), len(layers["layers"]))
        self.assertEqual(whole["stats"]["paths"], staged["stats"]["paths"])

    def test_thin_wall_plan_job_equals_plan_thin_wall(self):
        cylinder = Part.makeCylinder(10.0, 8.0)
        lateral = [f for f in cylinder.Faces if f.Surface.__class__.__name__ == "Cylinder"][0]
        mesh = native.tessellate_brep(lateral.exportBrepToString(), deflection=0.05)
        options = native.PlanJobOptions(thin_wall=native.ThinWallOptions(), model_name="Wall",
                                        start_spec="thin-wall:lowest")
        whole = native.run_plan_job(mesh["vertices"], mesh["triangles"], options=options)
        alone = native.plan_thin_wall(mesh["vertices"], mesh["triangles"], options=options)
        self.assertEqual(whole["plan_json"], alone["plan_json"])
        self.assertIsNone(whole["layers"])
        self.assertEqual(json.loads(alone["plan_json"])["start"], "thin-wall:lowest")
        with self.assertRaises(InvalidInput) as caught:
            native.plan_thin_wall(mesh["vertices"], mesh["triangles"],
                                  options=native.PlanJobOptions())
        self.assertIn("plan_thin_wall needs options.thin_wall", str(caught.exception))

    def test_options_are_checked_before_any_work_and_progress_cancels(self):
        vertices, triangles, face_ids = box_arrays()
        options = self.plan_job_options()
        options.planner.corner_angle = 200.0
        calls = []
        with self.assertRaises(InvalidInput) as caught:
            native.run_plan_job(vertices, triangles, options=options,
                                progress=lambda stage, fraction: calls.append(stage))
        self.assertIn("corner angle must be in (0, 180] degrees", str(caught.exception))
        self.assertEqual(calls, [])
        with self.assertRaises(Cancelled):
            native.run_plan_job(vertices, triangles, options=self.plan_job_options(),
                                progress=lambda stage, fraction: fraction < 0.3)

    def test_estimate_grid_takes_voxelize_options(self):
        vertices, triangles, _ = box_arrays()
        estimate = native.estimate_grid(vertices, triangles,
                                        options=native.VoxelizeOptions(voxel_size=1.0))
        self.assertTrue(estimate["fits"])
        self.assertEqual(estimate["bytes"],
                         estimate["cells"] * native.VoxelizeOptions().bytes_per_cell)
        tight = native.estimate_grid(
            vertices, triangles,
            options=native.VoxelizeOptions(voxel_size=0.01, memory_budget_bytes=1e6))
        self.assertFalse(tight["fits"])
        self.assertEqual(tight["budget_bytes"], 1e6)
        # Beyond the 2^31-cell limit the estimate still answers (the panel shows it) instead of
        # raising: about 4,000 x 3,000 x 600 cells of 0.01 mm for the 40 x 30 x 6 mm box.
        self.assertGreater(tight["cells"], 2 ** 31)
        self.assertEqual(tight["cells"], tight["dims"][0] * tight["dims"][1] * tight["dims"][2])
        self.assertIn("use a voxel size of at least", tight["message"])


cs_testing.main(__name__)
