"""The layer stage of a Job (paper §2): the curved layers of the Job's solid grown from its start
surface, computed by the core's layer job (native.run_layer_job) and stored in the Job's "Layers"
group as one Mesh feature per layer plus the hidden start-surface mesh.

The stage reruns only when the digest of its inputs (the model's BREP text or mesh arrays, the
start surface and the layer parameters) differs from the Job's ``InputsDigest``. Layers are saved
in the .FCStd, so a reopened document needs no recompute. App side: no GUI imports (the view
provider colours the layers).
"""

import hashlib
import json

import FreeCAD

from .. import geometry
from ..core import InvalidInput, native
from .features import ensure_group, group_members, prune_unused_features, retire_features

START_MODES = ["BuildPlate", "Plane", "Faces", "Surface"]
METHODS = ["AnyAngle", "Paper"]
ALIGNMENTS = ["PCA", "Model"]

LAYER_PROPERTIES = [
    ("App::PropertyInteger", "LayerIndex", "Layer", "1-based layer index"),
    ("App::PropertyDistance", "Height", "Layer", "Geodesic distance from the start surface, mm"),
    ("App::PropertyArea", "Area", "Layer", "Surface area, mm^2"),
    ("App::PropertyFloat", "ThicknessMean", "Layer",
     "Mean measured distance to the previous layer, mm (-1: not measured)"),
    ("App::PropertyFloat", "ThicknessMin", "Layer", "Smallest measured distance, mm"),
    ("App::PropertyFloat", "ThicknessMax", "Layer", "Largest measured distance, mm"),
]



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
        "simplify_layers": bool(job.SimplifyLayers),
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
    parts = [model["digest"], start_digest, kwargs["layer_thickness"], kwargs["voxel_size"],
             kwargs["method"], kwargs["alignment"], kwargs["cap_holes"], deflection]
    if job.SimplifyLayers:  # a Job from before simplification (False) keeps its digest
        parts.append("simplify_layers")
    h = hashlib.sha256()
    for part in parts:
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
    return [o for o in group_members(job.LayersGroup) if "LayerIndex" in o.PropertiesList]


def ensure_layers_group(job):
    return ensure_group(job, "LayersGroup", "Layers", "layers")


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
    retire_features(group, existing[len(layers):], prune,
                    lambda f: setattr(f, "Mesh", Mesh.Mesh()), "%s unused layer" % job.Label)
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
    for warning in report(job).get("warnings", []):  # where the part may differ from the model
        FreeCAD.Console.PrintWarning("CurvedSlicer %s: %s\n" % (job.Label, warning))
    job.InputsDigest = digest
    job.RunCount = job.RunCount + 1
    job.Status = _done_status(job)
    _store_start_mesh(job, result.get("source"))
    group.purgeTouched()


def start_mesh_object(job):
    """The hidden Mesh feature holding the start-surface triangles of the last layer run."""
    for o in group_members(job.LayersGroup):
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
    prune_unused_features(job.LayersGroup)


def layer_objects(job):
    """The Mesh features of the Job's layers, in layer order (unused ones excluded)."""
    return [o for o in _layer_objects(job) if o.LayerIndex > 0]


def report(job):
    """The last run's report as a dict (empty dict before the first run)."""
    return json.loads(job.Report) if job.Report else {}
