"""Macro API of the CurvedSlicer workbench (usable headless, from macros and the console).

    from freecad.curvedslicer import api
    job = api.make_job(doc, doc.Box, start=(doc.Box, ["Face5"]), layer_thickness=1.5,
                       voxel_size=0.5)
    api.run(job)                      # raises InvalidInput, ResourceLimit, Cancelled, ...
    print(job.LayerCount, [o.Height for o in api.layers(job)])

The GUI commands call these same functions through FreeCADGui.doCommand, so a recorded macro
replays what the user did. Lengths are mm. Errors are the classes of ``freecad.curvedslicer.core``.
App side: no GUI imports (a progress dialog and view providers come through hooks.py).
"""

import operator

import FreeCAD

from . import arguments, defaults, geometry, hooks, messages, preferences, stages
from .core import (Cancelled, CurvedSlicerError, InvalidInput, IoError, NotAvailable,
                   ResourceLimit, native)
from .objects import job as job_module
from .stages import layers as layer_stage
from .stages import paths as path_stage
from .stages import poses, simulation, views
from .stages import voids as void_stage

__all__ = ["make_job", "run", "recompute", "estimate", "layers", "set_layer_range", "export",
           "export_formats", "plan", "plan_json", "path_features", "path_spacing", "motion",
           "set_pose", "pose_count", "show_layer", "layer_info", "show_results", "show_solid",
           "show_cell", "cell_shown", "pose_info", "report", "is_job", "CurvedSlicerError",
           "InvalidInput", "IoError", "ResourceLimit", "Cancelled", "NotAvailable"]

is_job = job_module.is_job
layers = layer_stage.layer_objects
report = layer_stage.report


def _link_sub(value):
    """object | (object, [subelements]) -> the value of a PropertyLinkSub."""
    if isinstance(value, tuple):
        obj, subs = value
        return (obj, [subs] if isinstance(subs, str) else list(subs))
    return (value, [])


def _set_start(job, start):
    """start: None/"build_plate"; ("plane", point, normal); (solid, ["Face1", ...]) for faces of
    the solid; (other_object, [faces]) or other_object for another object's surface."""
    if start is None or start == "build_plate":
        job.StartMode = "BuildPlate"
        return
    if isinstance(start, tuple) and len(start) == 3 and start[0] == "plane":
        job.StartMode = "Plane"
        job.StartPlanePoint = FreeCAD.Vector(*start[1])
        job.StartPlaneNormal = FreeCAD.Vector(*start[2])
        return
    if isinstance(start, tuple) and len(start) == 2:
        obj, subs = start
        subs = [subs] if isinstance(subs, str) else list(subs)
    elif hasattr(start, "TypeId"):
        obj, subs = start, []
    else:
        raise InvalidInput("start not understood: %r; pass None, ('plane', point, normal), "
                           "(solid, ['Face1']) or (surface_object, [faces])" % (start,))
    if obj == job.Solid:
        if not subs:
            raise InvalidInput("start faces missing: the solid %s without faces; pass "
                               "(solid, ['Face1', ...])" % obj.Label)
        job.StartMode = "Faces"
        job.StartFaces = [(obj, tuple(subs))]
    else:
        job.StartMode = "Surface"
        job.StartSurface = (obj, subs)


def _check_job_numbers(layer_thickness, voxel_size, deflection, memory_budget_mb, bead_spacing,
                       point_spacing, fit_tolerance, corner_angle, thin_wall):
    """The core's checks of make_job's numbers, before a length property stores -1 as 0."""
    arguments.positive_mm(layer_thickness, "layer thickness", "1.5")
    if voxel_size is not None:
        arguments.positive_mm(voxel_size, "voxel size", "0.5")
    arguments.zero_or_positive(deflection, "deflection", "millimetres", "deflection=0.1")
    arguments.zero_or_positive(memory_budget_mb, "memory budget", "MB", "memory_budget_mb=4096")
    arguments.positive_mm(bead_spacing, "bead spacing", "1.65" if thin_wall else "3.7", 4, "mm")
    arguments.positive_mm(point_spacing, "point spacing", "2", 4, "mm")
    arguments.positive_mm(fit_tolerance, "fit tolerance", "0.05", 4, "mm")
    arguments.corner_angle(corner_angle)


def _check_job_choices(**choices):
    """Each keyword is a make_job enumeration argument; its value must be one of the Job's."""
    lists = {"method": job_module.METHODS, "grid_alignment": job_module.ALIGNMENTS,
             "surface_method": job_module.SURFACE_METHODS,
             "narrow_strips": job_module.NARROW_STRIPS,
             "deposition_direction": job_module.DEPOSITION_DIRECTIONS,
             "initial_path": job_module.INITIAL_PATHS, "path_display": job_module.PATH_DISPLAYS}
    for keyword, value in choices.items():
        arguments.choice(value, keyword, lists[keyword])


def make_job(doc, solid, start=None, layer_thickness=defaults.LAYER_THICKNESS, voxel_size=None,
             method="AnyAngle", grid_alignment="PCA", cap_holes=False, deflection=0.0,
             memory_budget_mb=0.0, bead_spacing=defaults.BEAD_SPACING,
             point_spacing=defaults.POINT_SPACING, initial_path="Boundary", cell_file=None,
             name="Job", plan_kind="CurvedLayers", wall_surface=None, wall_axis=(0, 0, 1),
             fit_tolerance=defaults.FIT_TOLERANCE, surface_method="Accurate", initial_plane=None,
             initial_surface=None, path_display="Polyline", tool_along_travel=False,
             narrow_strips="CentreBead", corner_angle=defaults.CORNER_ANGLE,
             min_feature_width=None, bead_width_range=(defaults.BEAD_WIDTH_MIN,
                                                       defaults.BEAD_WIDTH_MAX),
             connect_insets=defaults.CONNECT_INSETS, measure_coverage=defaults.MEASURE_COVERAGE,
             fill_gaps=defaults.FILL_GAPS, simplify_layers=defaults.SIMPLIFY_LAYERS,
             min_gap_area=None, corner_fill=defaults.CORNER_FILL,
             corner_fill_angle=defaults.CORNER_FILL_ANGLE, deposition_direction="Growth"):
    """Creates a Job for `solid` in `doc` (no computation; call run() or doc.recompute()).

    start: see _set_start. voxel_size None = the preference (default 1 mm). method "AnyAngle" |
    "Paper"; grid_alignment "PCA" | "Model"; memory_budget_mb 0 = 80 % of physical memory;
    simplify_layers: layer surfaces simplified within 0.05 x voxel_size (False: the
    marching-tetrahedra surfaces, about 4-5 triangles per voxel crossed).
    Paths: bead_spacing and point_spacing (mm), fit_tolerance (mm), surface_method "Accurate" |
    "Paper", initial_path "Boundary" | "Plane" (initial_plane = (point, normal)) | "Surface"
    (initial_surface = object or (object, [faces])); path_display "Polyline" | "BSpline";
    narrow_strips "CentreBead" (one bead where paths of one level come closer than 0.95 x
    bead_spacing) | "Overlap"; corner_angle (degrees, in (0, 180]): turns sharper than this
    within 0.2 mm are kept as exact corners by the spline fit (180: none).
    Bead coverage: min_feature_width (mm, None = half of bead_spacing),
    bead_width_range (min, max) fractions of bead_spacing ((1, 1) = fixed width), connect_insets
    (join consecutive rings into one arc-on path), fill_gaps (a centre-line bead in every
    uncovered strip between beads at least min_feature_width wide), min_gap_area (mm², None =
    bead_spacing squared: smaller uncovered patches get no fill bead), corner_fill (the outer
    ring dips into convex corners sharper than corner_fill_angle degrees), measure_coverage (void and overlap shares per
    layer); their ranges are checked when the paths are planned (InvalidInput naming the Job
    property).
    deposition_direction "Growth" (the paper's V, towards the nearest deposited point, where it
    lies within 30 degrees of the layer's growth direction, else that direction) | "Nearest"
    (the paper's V everywhere).
    tool_along_travel: torch x along the travel (True) or fixed while the positioner turns.
    plan_kind "ThinWall": no volume layers; wall_surface (object or (object, [faces])) is planned
    as a thin wall from its lowest edge along wall_axis, one bead per bead_spacing; `solid` may
    then be None or the wall's solid (carried by the positioner model). cell_file None = the
    preference ("" = the paper's cell). Raises InvalidInput when `solid` is not a solid (checked
    here, before any computation)."""
    if plan_kind not in path_stage.PLAN_KINDS:
        raise InvalidInput("unknown plan_kind: %r; use one of %s"
                           % (plan_kind, ", ".join(path_stage.PLAN_KINDS)))
    arguments.document_object(solid, "solid", allow_none=True)
    if plan_kind == "CurvedLayers" or solid is not None:
        if solid is not None and not geometry.is_mesh_object(solid):
            geometry.solid_shape(solid)
    _check_job_numbers(layer_thickness=layer_thickness, voxel_size=voxel_size,
                       deflection=deflection, memory_budget_mb=memory_budget_mb,
                       bead_spacing=bead_spacing, point_spacing=point_spacing,
                       fit_tolerance=fit_tolerance, corner_angle=corner_angle,
                       thin_wall=plan_kind == "ThinWall")
    _check_job_choices(method=method, grid_alignment=grid_alignment,
                       surface_method=surface_method, narrow_strips=narrow_strips,
                       deposition_direction=deposition_direction, initial_path=initial_path, path_display=path_display)
    wall_axis = arguments.vector(wall_axis, "wall_axis")
    if initial_plane is not None:
        initial_plane = (arguments.vector(initial_plane[0], "initial_plane point"),
                         arguments.vector(initial_plane[1], "initial_plane normal"))
    for what, value in (("solid", solid), ("start", start), ("wall_surface", wall_surface),
                        ("initial_surface", initial_surface)):
        _check_same_document(value, doc, what)
    obj = doc.addObject("App::DocumentObjectGroupPython", name)
    try:
        _fill_job(obj, locals())
    except Exception:
        doc.removeObject(obj.Name)  # no half-made Job left behind
        raise
    return obj


def _check_same_document(value, doc, what):
    """InvalidInput when `value` (an object, (object, sub-elements) or a list of them) holds an
    object of another document: a Job links only objects of its own document."""
    if isinstance(value, (list, tuple)):
        for item in value:
            _check_same_document(item, doc, what)
        return
    other = getattr(value, "Document", None)
    if other is not None and hasattr(value, "isDerivedFrom") and other is not doc:
        raise InvalidInput("%s %s is in the document %r, not in %r where the Job is made; pass an "
                           "object of the Job's document (copy it there first)"
                           % (what, value.Label, other.Name, doc.Name))


def _fill_job(obj, a):
    """Sets the new Job's properties from make_job's arguments `a` (its locals)."""
    solid, plan_kind, wall_surface, wall_axis = (a["solid"], a["plan_kind"], a["wall_surface"],
                                                 a["wall_axis"])
    layer_thickness, voxel_size, bead_spacing = (a["layer_thickness"], a["voxel_size"],
                                                 a["bead_spacing"])
    min_feature_width, min_gap_area, initial_plane = (a["min_feature_width"], a["min_gap_area"],
                                                      a["initial_plane"])
    initial_surface, cell_file, start = a["initial_surface"], a["cell_file"], a["start"]
    job_module.JobProxy(obj)
    obj.Solid = solid
    obj.PlanKind = plan_kind
    if wall_surface is not None:
        obj.WallSurface = _link_sub(wall_surface)
    obj.WallAxis = FreeCAD.Vector(*wall_axis)
    obj.LayerThickness = layer_thickness
    if voxel_size is not None:
        obj.VoxelSize = voxel_size
    obj.Method = a["method"]
    obj.GridAlignment = a["grid_alignment"]
    obj.CapHoles = a["cap_holes"]
    obj.SimplifyLayers = bool(a["simplify_layers"])
    obj.Deflection = a["deflection"]
    obj.MemoryBudget = a["memory_budget_mb"]
    obj.BeadSpacing = bead_spacing
    obj.PointSpacing = a["point_spacing"]
    obj.FitTolerance = a["fit_tolerance"]
    obj.CornerAngle = a["corner_angle"]
    obj.SurfaceMethod = a["surface_method"]
    obj.NarrowStrips = a["narrow_strips"]
    obj.DepositionDirection = a["deposition_direction"]
    obj.MinFeatureWidth = (0.5 * float(bead_spacing) if min_feature_width is None
                           else float(min_feature_width))
    obj.BeadWidthMin, obj.BeadWidthMax = (float(a["bead_width_range"][0]),
                                          float(a["bead_width_range"][1]))
    obj.ConnectInsets = bool(a["connect_insets"])
    obj.FillGaps = bool(a["fill_gaps"])
    obj.MinGapArea = (float(bead_spacing) ** 2 if min_gap_area is None else float(min_gap_area))
    obj.CornerFill = bool(a["corner_fill"])
    obj.CornerFillAngle = float(a["corner_fill_angle"])
    obj.MeasureCoverage = bool(a["measure_coverage"])
    obj.InitialPath = a["initial_path"]
    if initial_plane is not None:
        obj.InitialPlanePoint = FreeCAD.Vector(*initial_plane[0])
        obj.InitialPlaneNormal = FreeCAD.Vector(*initial_plane[1])
    if initial_surface is not None:
        obj.InitialSurface = _link_sub(initial_surface)
    obj.PathDisplay = a["path_display"]
    obj.ToolAlongTravel = a["tool_along_travel"]
    obj.CellFile = preferences.default_cell_file() if cell_file is None else cell_file
    if plan_kind == "CurvedLayers":
        _set_start(obj, start)
        layer_stage.ensure_layers_group(obj)
    hooks.attach_view(obj)


def run(job, progress=None, force=False):
    """Computes the Job's layers, paths and poses now (outside a recompute); each stage reruns
    only if its inputs changed.

    progress: None = a progress dialog with Cancel in the GUI, nothing headless; False = none;
    or a callable (stage: str, fraction: float) -> bool, False (or raising) to cancel.
    force: rerun even if the inputs did not change. Returns (layers ran, paths ran).
    Raises the core's exceptions; after any error (including Cancelled) the document is as it
    was before except for the Job's Status."""
    if not is_job(job):
        raise InvalidInput("not a CurvedSlicer Job: %s; pass the object make_job returned"
                           % getattr(job, "Label", job))
    owned = None
    if progress is None:
        owned = progress = hooks.make_progress()
    if progress is False:
        progress = None
    elif not callable(progress):
        raise InvalidInput("progress must be None, False or a callable (stage, fraction) -> "
                           "bool: %s; pass e.g. lambda stage, fraction: True"
                           % arguments.short_repr(progress))
    elif owned is None:
        progress = _CheckedProgress(progress)
    try:
        ran = stages.update_job(job, progress=progress, force=force, prune=True)
    except Exception as error:
        hooks.close_progress(owned)
        owned = None
        bad_answer = getattr(progress, "error", None)
        if bad_answer is not None:
            job_module.mark_failed(job, bad_answer)
            raise bad_answer from None
        if not isinstance(error, Cancelled):
            job_module.mark_failed(job, error)  # FreeCAD's error state, message in the tree
        raise
    finally:
        hooks.close_progress(owned)
    job_module.clear_failed(job)
    job.purgeTouched()
    return ran


class _CheckedProgress:
    """The caller's progress callable with its answer checked: True (or None, from a function
    that returns nothing) goes on, False cancels; any other answer cancels the run and is kept
    as `error`, an InvalidInput naming it, which api.run raises instead of Cancelled (the core
    could only have reported a value it cannot read as a bool)."""

    def __init__(self, progress):
        self.progress = progress
        self.error = None

    def __call__(self, stage, fraction):
        answer = self.progress(stage, fraction)
        if answer is None or isinstance(answer, bool):
            return answer is not False
        self.error = InvalidInput("the progress callback must return True (go on) or False "
                                  "(cancel): it returned %s; return a bool"
                                  % arguments.short_repr(answer))
        return False


def recompute(job):
    """doc.recompute() for the Job, then removal of layer objects a smaller result left unused."""
    job.touch()
    job.Document.recompute()
    stages.prune_unused(job)


def estimate(job, voxel_size=None, grid_alignment=None, memory_budget_mb=None, deflection=None,
             solid=None, cap_holes=None):
    """Voxel grid and memory of a run before running it (no allocation): dict with dims, cells,
    bytes, budget_bytes, fits, message (the core's advice when it does not fit) and triangles.
    Keyword values override the Job's properties (the task panel's unsaved values); a deflection
    of 0 means the one tied to the voxel size."""
    voxel = float(job.VoxelSize) if voxel_size is None else float(voxel_size)
    if not voxel > 0:
        raise InvalidInput("voxel size must be positive: %g mm; set VoxelSize, e.g. 0.5" % voxel)
    d = float(job.Deflection) if deflection is None else float(deflection)
    d = d if d > 0 else native.deflection_for_voxel_size(voxel)
    budget = layer_stage.memory_budget_mb(job) if memory_budget_mb is None else memory_budget_mb
    if budget < 0:
        raise InvalidInput("memory budget must not be negative: %g MB; use 0 for 80 %% of "
                           "physical memory" % budget)
    alignment = job.GridAlignment if grid_alignment is None else grid_alignment
    model = geometry.model_from_object(job.Solid if solid is None else solid, d,
                                       cap_holes=job.CapHoles if cap_holes is None else cap_holes)
    options = native.VoxelizeOptions(voxel_size=voxel,
                                     alignment={"PCA": "pca", "Model": "model"}[alignment],
                                     memory_budget_bytes=float(budget) * 1024.0 * 1024.0)
    result = native.estimate_grid(model["vertices"], model["triangles"], options=options)
    result["triangles"] = len(model["triangles"])
    return result


def set_layer_range(job, first, last):
    """Shows layers first..last (1-based, inclusive), their surfaces and their paths, and hides
    the others (the travel is shown only with every plan layer in the range)."""
    views.show_layer_range(job, first, last)


def show_layer(job, index):
    """Shows only layer `index` (1-based): its surface and its paths; 0 shows every layer.
    Returns layer_info(job, index) (or None for 0)."""
    views.show_layer(job, int(index))
    return views.layer_info(job, int(index)) if index else None


def layer_info(job, index):
    """Layer `index` (1-based) of the stored plan: dict index, count (plan layers), height (mm),
    paths, points, warnings (the plan's and the motion's for this layer), coverage (the plan's
    per-layer coverage object, None when the plan has none)."""
    return views.layer_info(job, int(index))


def show_results(job):
    """After a run: the solid hidden, the layers, paths and travel shown, the cell (positioner,
    robot, torch, deposit) hidden so that Fit All frames the part. show_solid / show_cell
    restore them."""
    views.show_results(job)


def show_solid(job, visible=True):
    """Shows (or hides) the Job's solid."""
    views.show_solid(job, bool(visible))


def show_cell(job, visible=True):
    """Shows (or hides) the cell at the pose: positioner carrying the part, robot, torch and
    deposit (they sit in cell coordinates, far from the part's own frame). The layers, paths
    and travel in the part's frame go the other way: hidden with the cell shown, every layer
    shown again with it hidden."""
    views.show_cell(job, bool(visible))


def cell_shown(job):
    """True if the cell at the pose is shown."""
    return views.cell_shown(job)


def show_voids(job, visible=True):
    """Shows (or hides) the uncovered regions of the stored plan: per plan layer a red disc for
    each of the largest voids its coverage lists (centre, area) in an "uncovered regions" group
    inside the Job's Paths group, drawn on first use and redrawn with the paths. Shown, a layer's discs follow its paths
    (show_layer isolates them too). A plan without measured coverage has none."""
    void_stage.show_voids(job, bool(visible))


def voids_shown(job):
    """True if the uncovered regions are shown."""
    return void_stage.voids_shown(job)


def void_markers(job):
    """The marker features of the uncovered regions (one per plan layer with voids, LayerIndex
    1-based, VoidCentres as the plan lists them); [] before show_voids."""
    return void_stage.void_objects(job)


def pose_info(job, index=None):
    """Motion point `index` (default: the one shown, PosePoint): dict index, count, kind, layer,
    path (1-based), a1/a2 (deg), joints (deg, 6), configuration (IK branch names), flags (names),
    tcp (world, mm), time (s), speed (mm/s), arc_on, deposit_moves (welded moves up to it)."""
    motion_ = poses.motion(job)
    return simulation.point_info(motion_, job.PosePoint if index is None else int(index))


def export_formats():
    """[(name, main file extension)] of every program format ("jbi", "krl", "rapid", "ls",
    "gcode", "csv", "json")."""
    return [tuple(f) for f in native.export_formats()]


def _jobs(jobs):
    jobs = list(jobs) if isinstance(jobs, (list, tuple)) else [jobs]
    if not jobs:
        raise InvalidInput("no Job to export: an empty list; pass a Job or a list of Jobs")
    for job in jobs:
        if not is_job(job):
            raise InvalidInput("not a CurvedSlicer Job: %s; pass the object make_job returned"
                               % getattr(job, "Label", job))
        if not job.PlanJson:
            raise InvalidInput("no plan to export: %s has no paths; run it first (api.run)"
                               % job.Label)
    return jobs


def plan_json(jobs):
    """The stored plan of a Job, or of several Jobs deposited one after the other (their layers
    concatenated in the given order, renumbered), as canonical plan JSON. No recompute."""
    jobs = _jobs(jobs)
    if len(jobs) == 1:
        return jobs[0].PlanJson
    import json

    merged = None
    for job in jobs:
        plan = json.loads(job.PlanJson)
        if merged is None:
            merged = plan
            merged["model"] = " + ".join(j.Label for j in jobs)
            merged["start"] = " + ".join(json.loads(j.PlanJson)["start"] for j in jobs)
            continue
        for layer in plan["layers"]:
            layer["index"] = len(merged["layers"])
            for path in layer["paths"]:
                path["layer"] = layer["index"]
            merged["layers"].append(layer)
    return native.format_plan_json(json.dumps(merged))


def plan(job):
    """The stored plan as a summary dict (layers, paths, points, per_layer, parameters)."""
    return native.plan_summary(plan_json(job))


def export(job, path=None, format="jbi", program_name="", date="", gcode_mode="tcp",
           arc_output=1, warn_unreachable=False, cell_file=None, tool_along_travel=None,
           allow_foreign_cell=False, gcode_dialect="generic"):
    """Writes the robot program of the stored plan (no recompute) for the Job's cell.

    job: a Job or a list of Jobs (deposited in that order, one program). format: one of
    export_formats() names. path: the main file (further files, e.g. JBI sub-jobs, go beside it);
    None = nothing written, only returned. All files are written or none. date: header date
    ("" = the exporters' fixed default, so a re-export is byte-identical). warn_unreachable:
    keep points the robot cannot reach (warnings) instead of raising InvalidInput.
    tool_along_travel: True = torch x axis along the travel direction; False (the core's
    default) keeps a fixed torch orientation while the positioner turns the part (no wrist
    wind-up on long rings); None = the (first) Job's ToolAlongTravel. cell_file:
    None = the (first) Job's CellFile. allow_foreign_cell: write a vendor's language (jbi
    yaskawa, krl kuka, rapid abb, ls fanuc) for another vendor's cell (default: InvalidInput
    naming the cell's vendor and the format). gcode_dialect: "generic" or "linuxcnc"
    (G-code only). The program is named after the file (program_name "" and a path) and
    the file must carry the program's name (InvalidInput otherwise). Returns {format, files
    [(name, bytes, lines)],
    motion_count, arc_count, warnings, total_bytes}."""
    jobs = _jobs(job)
    path = arguments.output_path(path)
    arguments.program_date(date)
    for j in jobs:
        # the program must be what the 3D view shows: not an earlier plan or another cell's
        reason = stages.stale_reason(j, motion=cell_file is None)
        if reason:
            raise InvalidInput("%s is not exported: %s; run it again (Recompute, or api.run) so "
                               "the program matches its inputs" % (j.Label, reason))
    text = plan_json(jobs)
    if cell_file is None:
        cell = poses.cell_json(jobs[0])
    else:
        cell = native.read_cell_json(cell_file) if cell_file else native.default_cell_json()
    if tool_along_travel is None:
        tool_along_travel = bool(jobs[0].ToolAlongTravel)
    options = native.ExportOptions(program_name=program_name, gcode_mode=gcode_mode,
                                   gcode_dialect=gcode_dialect, arc_output=arc_output)
    if date:
        options.date = date
    motion = poses.motion_options(jobs[0],
                                  unreachable="warn" if warn_unreachable else "throw",
                                  tool_along_travel=bool(tool_along_travel))
    try:
        return native.export_program(text, cell, format=format, path=path, options=options,
                                     motion=motion, allow_foreign_cell=bool(allow_foreign_cell))
    except CurvedSlicerError as error:
        raise messages.rephrased(error) from None


def path_features(job):
    """The Part features of the Job's plan layers (one compound of bead wires each)."""
    return path_stage.path_objects(job)


def path_beads(job):
    """The beads of the stored plan, [(layer, points (k,3) mm, ring)]: ring parts of joined paths
    (connected insets) apart, links left out (stages/paths.py)."""
    return path_stage.plan_beads(job)


def path_spacing(job):
    """Measured distances between neighbouring beads of the stored plan, mm (stages/paths.py)."""
    return path_stage.plan_spacing(job)


def motion(job):
    """The planned motion of the stored plan in the Job's cell (positioner angles a1/a2 in rad,
    deposition directions, ... per point; see native.plan_motion)."""
    return poses.motion(job)


def pose_count(job):
    return len(poses.motion(job)["a1"]) if job.PlanJson else 0


def set_pose(job, index):
    """Shows the positioner at motion point `index` (0-based, 0 .. pose_count(job) - 1); returns
    the point's (a1, a2) in degrees. InvalidInput for an index outside the motion (as
    layer_info for a layer outside the plan)."""
    count, given = pose_count(job), index
    try:
        index = None if isinstance(index, bool) else operator.index(index)  # ints, numpy ints
    except TypeError:
        index = None
    if index is None or not 0 <= index < count:
        raise InvalidInput("no motion point %s: %s has %d; pick 0 to %d"
                           % (arguments.short_repr(given), job.Label, count, max(count - 1, 0))
                           if count else
                           "no motion point %s: %s has no motion; run it first"
                           % (arguments.short_repr(given), job.Label))
    job.PosePoint = index
    poses.update_poses(job)
    job.purgeTouched()
    return job.PoseA1, job.PoseA2


def tessellate(obj, deflection):
    """The mesh the core slices for `obj` (vertices, triangles, FaceN ids), for inspection."""
    return geometry.model_from_object(obj, deflection)


def write_stl(obj, path, deflection):
    """Tessellates `obj` as the core does and writes a binary STL (face ids are not kept)."""
    model = geometry.model_from_object(obj, deflection)
    native.write_mesh(path, model["vertices"], model["triangles"])
