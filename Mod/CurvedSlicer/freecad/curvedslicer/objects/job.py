"""The CurvedSlicer Job: a document object holding a solid, a start surface and the slicing,
path and cell parameters, and its children: a "Layers" group (one Mesh feature per curved layer
and the hidden start-surface mesh), a "Paths" group (one Part feature of bead wires per plan
layer and the arc-off travel, objects/plan_stage.py) and a "Poses" group (the positioner model
carrying the part, objects/poses.py).

Recompute reruns only what changed, stage by stage: the layer stage runs when the digest of its
inputs (the model's BREP text or mesh arrays, the start surface and the layer parameters)
differs from ``InputsDigest``; the plan stage when the layers or a path parameter changed
(``PlanDigest``), so a path parameter alone never reruns the layers; the poses follow the plan,
the cell and ``PosePoint``. PlanKind ThinWall skips the layer stage and plans the wall surface.

Layers are stored as Mesh features, the plan as its versioned JSON text (``PlanJson``), both
saved in the .FCStd, so a reopened document needs no recompute and re-exports byte-identical
programs. Errors of the core or of the input are shown in ``Status`` (layers) or ``PathsStatus``
(paths, poses) and the Report view without raising out of ``execute``; the macro API (api.run)
raises them.
"""

import hashlib
import json

import FreeCAD

from .. import SCHEMA_VERSION
from .. import geometry
from ..core import Cancelled, CurvedSlicerError, InvalidInput, native
from . import plan_stage, poses

JOB_TYPE = "CurvedSlicer::Job"

START_MODES = ["BuildPlate", "Plane", "Faces", "Surface"]
METHODS = ["AnyAngle", "Paper"]
ALIGNMENTS = ["PCA", "Model"]
INITIAL_PATHS = ["Boundary", "Plane", "Surface"]
PLAN_KINDS = plan_stage.PLAN_KINDS
WALL_EDGES = plan_stage.WALL_EDGES
SURFACE_METHODS = plan_stage.SURFACE_METHODS
NARROW_STRIPS = plan_stage.NARROW_STRIPS
PATH_DISPLAYS = plan_stage.PATH_DISPLAYS

# (type, name, group, tooltip, default). Enumerations take their list as default (first = value).
PROPERTIES = [
    ("App::PropertyLink", "Solid", "Model",
     "The part to slice: a Part solid, a PartDesign Body or a closed Mesh", None),
    ("App::PropertyEnumeration", "StartMode", "Start surface",
     "Where layer 0 lies: BuildPlate (plane z = the model's lowest z), Plane (StartPlanePoint/"
     "StartPlaneNormal), Faces (StartFaces of the solid) or Surface (StartSurface object)",
     START_MODES),
    ("App::PropertyLinkSubList", "StartFaces", "Start surface",
     "Faces of the Solid the layers grow from (StartMode Faces)", None),
    ("App::PropertyLinkSub", "StartSurface", "Start surface",
     "Another object (optionally some of its faces) whose surface the part grows from "
     "(StartMode Surface), e.g. a curved base", None),
    ("App::PropertyVectorDistance", "StartPlanePoint", "Start surface",
     "A point of the start plane, mm, document coordinates (StartMode Plane)",
     FreeCAD.Vector(0, 0, 0)),
    ("App::PropertyVector", "StartPlaneNormal", "Start surface",
     "Normal of the start plane, towards the part (StartMode Plane)", FreeCAD.Vector(0, 0, 1)),
    ("App::PropertyLength", "LayerThickness", "Layers", "Layer thickness h, mm", 1.5),
    ("App::PropertyLength", "VoxelSize", "Layers",
     "Voxel edge length L, mm; time and memory grow as 1/L^3", None),
    ("App::PropertyEnumeration", "Method", "Layers",
     "Geodesic field: AnyAngle (accurate) or Paper (the paper's optimised search)", METHODS),
    ("App::PropertyEnumeration", "GridAlignment", "Layers",
     "Voxel grid axes: PCA (principal axes, paper 2.1) or Model (document axes)", ALIGNMENTS),
    ("App::PropertyBool", "CapHoles", "Layers",
     "Close the holes of an open mesh first (caps on the start surface follow it)", False),
    ("App::PropertyLength", "Deflection", "Layers",
     "Tessellation chord error, mm; 0 = a quarter of the voxel size", 0.0),
    ("App::PropertyFloat", "MemoryBudget", "Layers",
     "Memory the layer job may use, MB; 0 = 80 % of physical memory", 0.0),
    ("App::PropertyEnumeration", "PlanKind", "Model",
     "CurvedLayers: paths on curved layers grown from the start surface; ThinWall: one bead per "
     "layer on WallSurface from its lower edge (the paper's turbine base)", PLAN_KINDS),
    ("App::PropertyLinkSub", "WallSurface", "Thin wall",
     "The wall's surface (PlanKind ThinWall), e.g. the turbine base's outer surface", None),
    ("App::PropertyEnumeration", "WallEdge", "Thin wall",
     "Edge the wall grows from: Lowest (the boundary loop lowest along WallAxis) or Nearest "
     "(the loop nearest to WallPoint)", WALL_EDGES),
    ("App::PropertyVector", "WallAxis", "Thin wall", "Up direction for WallEdge Lowest",
     FreeCAD.Vector(0, 0, 1)),
    ("App::PropertyVectorDistance", "WallPoint", "Thin wall",
     "A point near the wall's start edge, mm (WallEdge Nearest)", FreeCAD.Vector(0, 0, 0)),
    ("App::PropertyLength", "BeadSpacing", "Paths",
     "Distance between neighbouring beads, mm (thin wall: between consecutive beads along the "
     "wall)", 3.7),
    ("App::PropertyLength", "PointSpacing", "Paths", "Largest distance between robot points, mm",
     2.0),
    ("App::PropertyFloat", "FitTolerance", "Paths", "Spline fit tolerance of the paths, mm",
     0.05),
    ("App::PropertyAngle", "CornerAngle", "Paths",
     "Where a path turns by more than this within 0.2 mm, the spline fit keeps the raw vertex as "
     "an exact corner, degrees in (0, 180]; 180 keeps no corners (every path one smooth spline)",
     plan_stage.DEFAULT_CORNER_ANGLE),
    ("App::PropertyEnumeration", "InitialPath", "Paths",
     "Initial curve of every layer: Boundary (contour-parallel paths), Plane (section with "
     "InitialPlanePoint/InitialPlaneNormal) or Surface (section with InitialSurface)",
     INITIAL_PATHS),
    ("App::PropertyVectorDistance", "InitialPlanePoint", "Paths",
     "A point of the initial plane, mm (InitialPath Plane)", FreeCAD.Vector(0, 0, 0)),
    ("App::PropertyVector", "InitialPlaneNormal", "Paths",
     "Normal of the initial plane (InitialPath Plane)", FreeCAD.Vector(1, 0, 0)),
    ("App::PropertyLinkSub", "InitialSurface", "Paths",
     "Surface whose section with each layer is the first path (InitialPath Surface)", None),
    ("App::PropertyEnumeration", "SurfaceMethod", "Paths",
     "Surface geodesic field (GDTC): Accurate, or Paper (the paper's search, eq. 15)",
     SURFACE_METHODS),
    ("App::PropertyEnumeration", "NarrowStrips", "Paths",
     "Where paths of one level come closer than 0.95 x BeadSpacing (the innermost ring of a thin "
     "region, a hole's front meeting the rim's): CentreBead puts one bead on the strip's centre "
     "line, joined to the ring piece it continues, and reports it per layer; Overlap keeps the "
     "paths and their beads overlap", NARROW_STRIPS),
    ("App::PropertyEnumeration", "PathDisplay", "Paths",
     "Draw the paths as Polyline (the robot points) or BSpline (interpolated)", PATH_DISPLAYS),
    ("App::PropertyFile", "CellFile", "Robot",
     "Robot cell description (JSON, resources/cells); empty = the paper's cell (Motoman HP20D "
     "with a tilt-rotate positioner)", ""),
    ("App::PropertyBool", "ToolAlongTravel", "Robot",
     "Torch x axis along the travel direction; off keeps the torch orientation fixed while the "
     "positioner turns the part (default; no wrist wind-up on long rings)", False),
    ("App::PropertyInteger", "PosePoint", "Robot",
     "Motion point (0-based, execution order) the positioner model shows", 0),
    ("App::PropertyString", "Status", "Results", "What the last run did", "Not run yet"),
    ("App::PropertyString", "PathsStatus", "Results", "What the last path planning did",
     "Not run yet"),
    ("App::PropertyInteger", "LayerCount", "Results", "Number of curved layers", 0),
    ("App::PropertyFloatList", "LayerHeights", "Results",
     "Geodesic distance of each layer from the start surface, mm", []),
    ("App::PropertyString", "GridDims", "Results", "Voxel grid cells nx x ny x nz", ""),
    ("App::PropertyFloat", "InsideVoxels", "Results", "Voxels inside the solid", 0.0),
    ("App::PropertyFloat", "MaxDistance", "Results",
     "Largest geodesic distance from the start surface, mm", 0.0),
    ("App::PropertyFloat", "TotalSeconds", "Results", "Wall time of the last layer run, s", 0.0),
    ("App::PropertyFloat", "PeakMemoryMB", "Results", "Peak resident memory of the run, MB",
     0.0),
    ("App::PropertyStringList", "StageTimes", "Results", "Wall time per stage of the last run",
     []),
    ("App::PropertyString", "Report", "Results",
     "Report JSON of the layer job (inputs, mesh, grid, field, per-layer statistics)", ""),
    ("App::PropertyInteger", "RunCount", "Results", "Layer computations so far", 0),
    ("App::PropertyInteger", "PlanLayerCount", "Results", "Layers of the plan", 0),
    ("App::PropertyInteger", "PathCount", "Results", "Beads (paths) of the plan", 0),
    ("App::PropertyInteger", "PathPointCount", "Results", "Robot points of the plan", 0),
    ("App::PropertyString", "PlanStats", "Results", "Planner statistics (JSON)", ""),
    ("App::PropertyInteger", "PoseCount", "Results", "Motion points (PosePoint range)", 0),
    ("App::PropertyFloat", "PoseA1", "Results", "Positioner tilt a1 at PosePoint, degrees", 0.0),
    ("App::PropertyFloat", "PoseA2", "Results", "Positioner rotation a2 at PosePoint, degrees",
     0.0),
    ("App::PropertyFloat", "PoseResidual", "Results",
     "Angle between the turned deposition direction and gravity at PosePoint, degrees", 0.0),
    ("App::PropertyInteger", "PoseLayer", "Results", "Plan layer of PosePoint, 1-based", 0),
    ("App::PropertyInteger", "PosePath", "Results", "Path of PosePoint in its layer, 1-based",
     0),
    ("App::PropertyVector", "PoseDeposition", "Results",
     "Deposition direction V of PosePoint turned by the positioner (world; gravity ideally)",
     FreeCAD.Vector(0, 0, -1)),
    ("App::PropertyStringList", "MotionWarnings", "Results",
     "Warnings of the motion planning (limits, unreachable points)", []),
    ("App::PropertyString", "InputsDigest", "Internal",
     "SHA-256 of the inputs the current layers were computed from", ""),
    ("App::PropertyString", "PlanDigest", "Internal",
     "SHA-256 of the inputs the current plan was computed from", ""),
    ("App::PropertyString", "PlanJson", "Internal",
     "The deposition plan, versioned JSON (plan/plan_io.hpp)", ""),
    ("App::PropertyLink", "LayersGroup", "Internal", "The group holding the layer meshes", None),
    ("App::PropertyLink", "PathsGroup", "Internal", "The group holding the path wires", None),
    ("App::PropertyLink", "PosesGroup", "Internal", "The group holding the positioner model",
     None),
    ("App::PropertyInteger", "SchemaVersion", "Internal",
     "Property layout version of this Job (migrated on load)", SCHEMA_VERSION),
]

RESULT_PROPERTIES = [name for (_, name, group, _, _) in PROPERTIES
                     if group in ("Results", "Internal")]

LAYER_PROPERTIES = [
    ("App::PropertyInteger", "LayerIndex", "Layer", "1-based layer index"),
    ("App::PropertyDistance", "Height", "Layer", "Geodesic distance from the start surface, mm"),
    ("App::PropertyArea", "Area", "Layer", "Surface area, mm^2"),
    ("App::PropertyFloat", "ThicknessMean", "Layer",
     "Mean measured distance to the previous layer, mm (-1: not measured)"),
    ("App::PropertyFloat", "ThicknessMin", "Layer", "Smallest measured distance, mm"),
    ("App::PropertyFloat", "ThicknessMax", "Layer", "Largest measured distance, mm"),
]


def default_voxel_size():
    from ..preferences import default_voxel_size as preferred

    return preferred()


def add_missing_properties(obj):
    """Adds the properties a Job of this version has and `obj` lacks (new or migrated Job)."""
    added = []
    for (ptype, name, group, tooltip, default) in PROPERTIES:
        if name in obj.PropertiesList:
            continue
        obj.addProperty(ptype, name, group, tooltip)
        added.append(name)
        if name == "VoxelSize":
            default = default_voxel_size()
        if ptype == "App::PropertyEnumeration":
            setattr(obj, name, list(default))
            setattr(obj, name, default[0])
        elif default is not None:
            setattr(obj, name, default)
    for name in RESULT_PROPERTIES:
        obj.setEditorMode(name, 1)  # read-only
    for name in ("InputsDigest", "LayersGroup", "PlanDigest", "PlanJson", "PathsGroup",
                 "PosesGroup"):
        obj.setEditorMode(name, 2)  # hidden
    return added


class JobProxy:
    """Proxy of a Job (App::DocumentObjectGroupPython)."""

    Type = JOB_TYPE

    def __init__(self, obj):
        obj.Proxy = self
        self.Type = JOB_TYPE
        add_missing_properties(obj)

    # -- persistence (0.20 calls __getstate__/__setstate__, newer versions dumps/loads) --------
    def __getstate__(self):
        return {"Type": self.Type, "SchemaVersion": SCHEMA_VERSION}

    def __setstate__(self, state):
        self.Type = (state or {}).get("Type", JOB_TYPE)

    dumps = __getstate__
    loads = __setstate__

    def onDocumentRestored(self, obj):
        """Migrates a Job saved by an older workbench: adds missing properties, bumps the
        schema version. Layers are kept (no recompute)."""
        self.Type = JOB_TYPE
        old = obj.SchemaVersion if "SchemaVersion" in obj.PropertiesList else 0
        added = add_missing_properties(obj)
        if "NarrowStrips" in added:
            # Planned before the option existed: keep what it planned (overlapping paths).
            obj.NarrowStrips = "Overlap"
        if old < SCHEMA_VERSION or added:
            obj.SchemaVersion = SCHEMA_VERSION
            FreeCAD.Console.PrintLog("CurvedSlicer: migrated %s from schema %d (added %s)\n"
                                     % (obj.Label, old, ", ".join(added) or "nothing"))
        if FreeCAD.GuiUp:
            # A Job saved headless has no view provider proxy; give it one, and colour the layers.
            from ..viewproviders import view_job

            view_job.restore(obj)

    def execute(self, obj):
        """Recompute: reruns the layers, the paths and the poses only if their inputs changed.
        Errors go to Status / PathsStatus (never raised out of a recompute)."""
        progress = _default_progress_factory() if _default_progress_factory else None
        try:
            update_job(obj, progress=progress, prune=False)
        except CurvedSlicerError:
            pass  # reported by update_job
        finally:
            if progress is not None and hasattr(progress, "close"):
                progress.close()


def _scaled(progress, begin, end):
    """progress(stage, fraction) mapped into [begin, end] (fractions never go backwards)."""
    if progress is None:
        return None
    return lambda stage, fraction: progress(stage, begin + (end - begin) * fraction)


def update_job(job, progress=None, force=False, prune=True):
    """Layers (CurvedLayers only), then paths, then poses, each only if its inputs changed (or
    `force`). Reports an error in Status (layers) or PathsStatus (paths, poses) and re-raises it;
    what an earlier run computed stays. Returns (layers ran, paths ran)."""
    ran_layers = False
    if job.PlanKind == "CurvedLayers":
        try:
            ran_layers = update_layers(job, progress=_scaled(progress, 0.0, 0.85), force=force,
                                       prune=prune)
        except CurvedSlicerError as error:
            report_failure(job, error)
            raise
    else:
        job.Status = "Thin wall: no volume layers (the wall's beads are the plan layers)"
    try:
        ran_paths = plan_stage.update_paths(job, progress=_scaled(progress, 0.85, 1.0),
                                            force=force or ran_layers, prune=prune)
        poses.update_poses(job)
    except CurvedSlicerError as error:
        kind = type(error).__name__
        job.PathsStatus = ("Cancelled: the paths shown are from the previous run"
                           if isinstance(error, Cancelled) else "%s: %s" % (kind, error))
        FreeCAD.Console.PrintError("CurvedSlicer %s paths: %s: %s\n" % (job.Label, kind, error))
        raise
    job.PathsStatus = "%s: %d paths (%d points) on %d plan layers%s" % (
        "Planned" if ran_paths else "Up to date", job.PathCount, job.PathPointCount,
        job.PlanLayerCount, "" if ran_paths else " (inputs unchanged, not rerun)")
    return ran_layers, ran_paths


# A factory of progress callbacks the GUI installs (init_gui.py); None when headless.
_default_progress_factory = None


def set_default_progress_factory(factory):
    """Installs ``factory() -> callable(stage, fraction) -> bool`` used when none is given."""
    global _default_progress_factory
    _default_progress_factory = factory


def is_job(obj):
    proxy = getattr(obj, "Proxy", None)
    return proxy is not None and getattr(proxy, "Type", None) == JOB_TYPE


def report_failure(job, error):
    kind = type(error).__name__
    if isinstance(error, Cancelled):
        job.Status = "Cancelled: the layers shown are from the previous run"
    else:
        job.Status = "%s: %s" % (kind, error)
    FreeCAD.Console.PrintError("CurvedSlicer %s: %s: %s\n" % (job.Label, kind, error))


# ---- inputs ------------------------------------------------------------------------------------

def _deflection(job):
    voxel = float(job.VoxelSize)
    if not voxel > 0:
        raise InvalidInput("voxel size must be positive: %g mm; set VoxelSize, e.g. 0.5" % voxel)
    d = float(job.Deflection)
    return d if d > 0 else native.deflection_for_voxel_size(voxel)


def _vec(v):
    return (float(v.x), float(v.y), float(v.z))


def layer_inputs(job):
    """Gathers everything the layer stage needs. Returns (model dict, kwargs, digest).

    Raises InvalidInput for a missing/non-solid Solid, an open mesh, start faces that are not
    faces of the Solid, or an empty start surface."""
    deflection = _deflection(job)
    model = geometry.model_from_object(job.Solid, deflection, cap_holes=job.CapHoles)
    kwargs = {
        "layer_thickness": float(job.LayerThickness),
        "voxel_size": float(job.VoxelSize),
        "method": {"AnyAngle": "anyangle", "Paper": "paper"}[job.Method],
        "alignment": {"PCA": "pca", "Model": "model"}[job.GridAlignment],
        "cap_holes": bool(job.CapHoles),
        "model_name": job.Solid.Label,
    }
    mode = job.StartMode
    start_digest = mode
    if mode == "BuildPlate":
        kwargs.update(start=native.StartSurface.build_plate(), start_spec="plane:bottom")
    elif mode == "Plane":
        point, normal = _vec(job.StartPlanePoint), _vec(job.StartPlaneNormal)
        if normal == (0.0, 0.0, 0.0):
            raise InvalidInput("start plane normal is zero: (0, 0, 0); set StartPlaneNormal, "
                               "e.g. (0, 0, 1)")
        kwargs.update(start=native.StartSurface.plane(point, normal),
                      start_spec="plane:%g,%g,%g,%g,%g,%g" % (point + normal))
        start_digest += repr((point, normal))
    elif mode == "Faces":
        ids = []
        for (owner, subs) in job.StartFaces:
            if owner != job.Solid:
                raise InvalidInput(
                    "start face not on the model: %s belongs to %s, not to the solid %s; pick "
                    "faces of %s, or use StartMode Surface for another object's surface"
                    % (", ".join(subs) or "(whole object)", owner.Label, job.Solid.Label,
                       job.Solid.Label))
            if model["kind"] != "shape":
                raise InvalidInput(
                    "start faces on a mesh: %s is a mesh; use StartMode Surface with a separate "
                    "surface object, or Plane" % job.Solid.Label)
            ids.extend(geometry.face_numbers(subs, owner))
        if not ids:
            raise InvalidInput("no start faces: StartFaces is empty; pick faces of %s (FaceN) or "
                               "choose another StartMode" % job.Solid.Label)
        face_count = int(model["face_ids"].max()) if len(model["face_ids"]) else 0
        missing = [i for i in ids if i > face_count]
        if missing:
            raise InvalidInput("start face not on the model: Face%d (the solid %s has %d faces); "
                               "pick faces of the solid again" % (missing[0], job.Solid.Label,
                                                                 face_count))
        ids = sorted(set(ids))
        kwargs.update(start=native.StartSurface.faces(ids),
                      start_spec="faces:" + ",".join("Face%d" % i for i in ids))
        start_digest += repr(ids)
    elif mode == "Surface":
        link = job.StartSurface
        obj, subs = (link[0], list(link[1])) if link else (None, [])
        if obj is not None and obj == job.Solid:
            raise InvalidInput("start surface is the solid itself: %s; use StartMode Faces to "
                               "grow from faces of the solid" % obj.Label)
        vertices, triangles, digest = geometry.surface_from_object(obj, subs, deflection)
        kwargs.update(start=native.StartSurface.surface(vertices, triangles),
                      start_spec="surface:%s%s" % (obj.Label, (":" + ",".join(subs)) if subs
                                                   else ""))
        start_digest += digest
    else:  # pragma: no cover - the enumeration has no other values
        raise InvalidInput("unknown StartMode: %s; use one of %s" % (mode, ", ".join(START_MODES)))
    h = hashlib.sha256()
    for part in (model["digest"], start_digest, kwargs["layer_thickness"], kwargs["voxel_size"],
                 kwargs["method"], kwargs["alignment"], kwargs["cap_holes"], deflection):
        h.update(repr(part).encode("utf-8"))
        h.update(b"\0")
    return model, kwargs, h.hexdigest()


def memory_budget_mb(job):
    value = float(job.MemoryBudget)
    if value < 0:
        raise InvalidInput("memory budget must not be negative: %g MB; set MemoryBudget to 0 "
                           "(80 %% of physical memory) or a size in MB" % value)
    return value


# ---- running -----------------------------------------------------------------------------------

def update_layers(job, progress=None, force=False, prune=True):
    """Recomputes the layers if their inputs changed (or `force`). Returns True if it ran.

    Raises the core's exceptions (InvalidInput, ResourceLimit, Cancelled, ...); on any error the
    layers and results of the previous run stay as they were."""
    model, kwargs, digest = layer_inputs(job)
    have_layers = job.LayersGroup is not None and job.LayerCount == len(layer_objects(job))
    if not force and digest == job.InputsDigest and have_layers:
        job.Status = _done_status(job) + " (inputs unchanged, not rerun)"
        return False
    fields = dict(kwargs)
    names = {"model_name": fields.pop("model_name"), "start_spec": fields.pop("start_spec")}
    options = native.LayerJobOptions(
        memory_budget_bytes=memory_budget_mb(job) * 1024.0 * 1024.0, **fields)
    result = native.run_layer_job(model["vertices"], model["triangles"], model["face_ids"],
                                  options=options, progress=progress, **names)
    apply_result(job, result, digest, prune=prune)
    return True


def _done_status(job):
    return "Up to date: %d layers of %s mm" % (job.LayerCount,
                                                 FreeCAD.Units.Quantity(job.LayerThickness)
                                                 .getValueAs("mm"))


def _layer_objects(job):
    group = job.LayersGroup
    if group is None:
        return []
    return [o for o in group.Group if "LayerIndex" in o.PropertiesList]


def ensure_layers_group(job):
    if job.LayersGroup is None:
        group = job.Document.addObject("App::DocumentObjectGroup", "Layers")
        group.Label = "%s layers" % job.Label
        job.addObject(group)
        job.LayersGroup = group
    return job.LayersGroup


def apply_result(job, result, digest, prune=True):
    """Writes a core result into the document: one Mesh feature per layer (reused by index),
    result properties and the report. Surplus layer objects of an earlier run are removed when
    `prune` (not possible inside a recompute; they are emptied and hidden then)."""
    import Mesh

    doc = job.Document
    group = ensure_layers_group(job)
    existing = _layer_objects(job)
    layers = result["layers"]
    for i, layer in enumerate(layers):
        if i < len(existing):
            feature = existing[i]
        else:
            feature = doc.addObject("Mesh::Feature", "Layer")
            for (ptype, name, pgroup, tooltip) in LAYER_PROPERTIES:
                feature.addProperty(ptype, name, pgroup, tooltip)
                feature.setEditorMode(name, 1)
            group.addObject(feature)
        feature.Mesh = Mesh.Mesh((geometry.vectors(layer["vertices"]),
                                  [tuple(t) for t in layer["triangles"].tolist()]))
        feature.Label = "%s layer %03d" % (job.Label, layer["index"])
        feature.LayerIndex = int(layer["index"])
        feature.Height = float(layer["height"])
        feature.Area = float(layer["area"])
        t = layer["thickness"]
        feature.ThicknessMean = -1.0 if t["mean"] is None else float(t["mean"])
        feature.ThicknessMin = -1.0 if t["min"] is None else float(t["min"])
        feature.ThicknessMax = -1.0 if t["max"] is None else float(t["max"])
        feature.purgeTouched()
    plan_stage.retire_features(group, existing[len(layers):], prune,
                               lambda f: setattr(f, "Mesh", Mesh.Mesh()),
                               "%s unused layer" % job.Label)
    grid = result["grid"]
    job.LayerCount = len(layers)
    job.LayerHeights = [float(layer["height"]) for layer in layers]
    job.GridDims = "%d x %d x %d" % tuple(grid["dims"])
    job.InsideVoxels = float(grid["inside_voxels"])
    job.MaxDistance = float(grid["max_distance"])
    job.TotalSeconds = float(result["total_seconds"])
    job.PeakMemoryMB = float(result["peak_memory_bytes"]) / 2 ** 20
    job.StageTimes = ["%s: %.3f s" % (name, seconds) for (name, seconds) in result["stage_times"]]
    job.Report = result["report_json"]
    job.InputsDigest = digest
    job.RunCount = job.RunCount + 1
    job.Status = _done_status(job)
    _store_start_mesh(job, result.get("source"))
    group.purgeTouched()


def start_mesh_object(job):
    """The hidden Mesh feature holding the start-surface triangles of the last layer run."""
    group = job.LayersGroup
    if group is None:
        return None
    for o in group.Group:
        if "StartSurfaceMesh" in o.PropertiesList:
            return o
    return None


def _store_start_mesh(job, source):
    """Keeps the start surface the layers grew from (deposited material under layer 1, which the
    path planner's deposition directions point to)."""
    import Mesh

    feature = start_mesh_object(job)
    if feature is None:
        feature = job.Document.addObject("Mesh::Feature", "StartSurfaceMesh")
        feature.addProperty("App::PropertyBool", "StartSurfaceMesh", "Layer",
                            "Start-surface triangles of the last layer run")
        feature.setEditorMode("StartSurfaceMesh", 2)
        feature.StartSurfaceMesh = True
        job.LayersGroup.addObject(feature)
    if source is not None and len(source["triangles"]):
        feature.Mesh = Mesh.Mesh((geometry.vectors(source["vertices"]),
                                  [tuple(t) for t in source["triangles"].tolist()]))
    else:
        feature.Mesh = Mesh.Mesh()
    feature.Label = "%s start surface" % job.Label
    feature.Visibility = False
    feature.purgeTouched()


def prune_unused_layers(job):
    """Removes layer objects emptied by a recompute (call outside a recompute)."""
    plan_stage.prune_unused_features(job.LayersGroup)


def layer_objects(job):
    """The Mesh features of the Job's layers, in layer order (unused ones excluded)."""
    return [o for o in _layer_objects(job) if o.LayerIndex > 0]


def report(job):
    """The last run's report as a dict (empty dict before the first run)."""
    return json.loads(job.Report) if job.Report else {}
