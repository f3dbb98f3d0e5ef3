"""The CurvedSlicer Job: a document object holding a solid, a start surface and the slicing
parameters, and its children (a "Layers" group with one Mesh feature per curved layer).

Recompute reruns only what changed: the layer stage runs when the digest of its inputs (the
model's BREP text or mesh arrays, the start surface and the layer parameters) differs from the
one stored with the current layers; the path parameters (BeadSpacing, PointSpacing, InitialPath,
CellFile) do not trigger it. Path planning, positioner poses and export are not wired yet
(``PathsStatus`` says so); nothing is faked.

Layers are computed by the core's layer job (paper §2) and stored as Mesh features, saved in the
.FCStd with the report JSON, so a reopened document needs no recompute. Errors of the core or of
the input are shown in ``Status`` (and the Report view) without raising out of ``execute``; the
macro API (api.run) raises them.
"""

import hashlib
import json

import FreeCAD

from .. import SCHEMA_VERSION
from .. import geometry
from ..core import PATHS_NOT_WIRED, Cancelled, CurvedSlicerError, InvalidInput, native

JOB_TYPE = "CurvedSlicer::Job"

START_MODES = ["BuildPlate", "Plane", "Faces", "Surface"]
METHODS = ["AnyAngle", "Paper"]
ALIGNMENTS = ["PCA", "Model"]
INITIAL_PATHS = ["Boundary", "Plane", "Surface"]

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
    ("App::PropertyLength", "BeadSpacing", "Paths (not wired yet)",
     "Distance between neighbouring beads, mm (used from the next version)", 3.7),
    ("App::PropertyLength", "PointSpacing", "Paths (not wired yet)",
     "Largest distance between robot points, mm (used from the next version)", 2.0),
    ("App::PropertyEnumeration", "InitialPath", "Paths (not wired yet)",
     "Initial curve of every layer: Boundary, Plane or Surface section (next version)",
     INITIAL_PATHS),
    ("App::PropertyFile", "CellFile", "Paths (not wired yet)",
     "Robot cell description (JSON, resources/cells), used from the next version", ""),
    ("App::PropertyString", "Status", "Results", "What the last run did", "Not run yet"),
    ("App::PropertyString", "PathsStatus", "Results", "State of paths, poses and export",
     PATHS_NOT_WIRED),
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
    ("App::PropertyString", "InputsDigest", "Internal",
     "SHA-256 of the inputs the current layers were computed from", ""),
    ("App::PropertyLink", "LayersGroup", "Internal", "The group holding the layer meshes", None),
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
    for name in ("InputsDigest", "LayersGroup"):
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
        if old < SCHEMA_VERSION or added:
            obj.SchemaVersion = SCHEMA_VERSION
            FreeCAD.Console.PrintLog("CurvedSlicer: migrated %s from schema %d (added %s)\n"
                                     % (obj.Label, old, ", ".join(added) or "nothing"))
        if FreeCAD.GuiUp:
            # A Job saved headless has no view provider proxy; give it one, and colour the layers.
            from ..viewproviders import view_job

            view_job.restore(obj)

    def execute(self, obj):
        """Recompute: reruns the layers only if their inputs changed. Errors go to Status."""
        progress = _default_progress_factory() if _default_progress_factory else None
        try:
            update_layers(obj, progress=progress, prune=False)
        except CurvedSlicerError as error:
            report_failure(obj, error)
        finally:
            if progress is not None and hasattr(progress, "close"):
                progress.close()


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
        kwargs.update(start="build_plate", start_spec="plane:bottom")
    elif mode == "Plane":
        point, normal = _vec(job.StartPlanePoint), _vec(job.StartPlaneNormal)
        if normal == (0.0, 0.0, 0.0):
            raise InvalidInput("start plane normal is zero: (0, 0, 0); set StartPlaneNormal, "
                               "e.g. (0, 0, 1)")
        kwargs.update(start="plane", plane_point=point, plane_normal=normal,
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
        kwargs.update(start="faces", start_face_ids=ids,
                      start_spec="faces:" + ",".join("Face%d" % i for i in ids))
        start_digest += repr(ids)
    elif mode == "Surface":
        link = job.StartSurface
        obj, subs = (link[0], list(link[1])) if link else (None, [])
        if obj is not None and obj == job.Solid:
            raise InvalidInput("start surface is the solid itself: %s; use StartMode Faces to "
                               "grow from faces of the solid" % obj.Label)
        vertices, triangles, digest = geometry.surface_from_object(obj, subs, deflection)
        kwargs.update(start="mesh", start_vertices=vertices, start_triangles=triangles,
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
    result = native.run_layer_job(model["vertices"], model["triangles"], model["face_ids"],
                                  memory_budget_mb=memory_budget_mb(job), progress=progress,
                                  **kwargs)
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
    for feature in existing[len(layers):]:
        if prune:
            group.removeObject(feature)
            doc.removeObject(feature.Name)
        else:
            feature.Mesh = Mesh.Mesh()
            feature.LayerIndex = 0
            feature.Label = "%s unused layer" % job.Label
            feature.Visibility = False
            feature.purgeTouched()
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
    job.PathsStatus = PATHS_NOT_WIRED
    group.purgeTouched()


def prune_unused_layers(job):
    """Removes layer objects emptied by a recompute (call outside a recompute)."""
    group = job.LayersGroup
    if group is None:
        return
    for feature in [o for o in group.Group if "LayerIndex" in o.PropertiesList
                    and o.LayerIndex == 0]:
        group.removeObject(feature)
        job.Document.removeObject(feature.Name)


def layer_objects(job):
    """The Mesh features of the Job's layers, in layer order (unused ones excluded)."""
    return [o for o in _layer_objects(job) if o.LayerIndex > 0]


def report(job):
    """The last run's report as a dict (empty dict before the first run)."""
    return json.loads(job.Report) if job.Report else {}
