"""Macro API of the CurvedSlicer workbench (usable headless, from macros and the console).

    from freecad.curvedslicer import api
    job = api.make_job(doc, doc.Box, start=(doc.Box, ["Face5"]), layer_thickness=1.5,
                       voxel_size=0.5)
    api.run(job)                      # raises InvalidInput, ResourceLimit, Cancelled, ...
    print(job.LayerCount, [o.Height for o in api.layers(job)])

The GUI commands call these same functions through FreeCADGui.doCommand, so a recorded macro
replays what the user did. Lengths are mm. Errors are the classes of ``freecad.curvedslicer.core``.
"""

import FreeCAD

from . import geometry, preferences
from .core import (PATHS_NOT_WIRED, Cancelled, CurvedSlicerError, InvalidInput, NotAvailable,
                   ResourceLimit, native)
from .objects import job as job_module

__all__ = ["make_job", "run", "recompute", "estimate", "layers", "set_layer_range", "export",
           "report", "is_job", "CurvedSlicerError", "InvalidInput", "ResourceLimit", "Cancelled",
           "NotAvailable"]

is_job = job_module.is_job
layers = job_module.layer_objects
report = job_module.report


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


def make_job(doc, solid, start=None, layer_thickness=1.5, voxel_size=None, method="AnyAngle",
             grid_alignment="PCA", cap_holes=False, deflection=0.0, memory_budget_mb=0.0,
             bead_spacing=3.7, point_spacing=2.0, initial_path="Boundary", cell_file=None,
             name="Job"):
    """Creates a Job for `solid` in `doc` (no computation; call run() or doc.recompute()).

    start: see _set_start. voxel_size None = the preference (default 1 mm). method "AnyAngle" |
    "Paper"; grid_alignment "PCA" | "Model"; memory_budget_mb 0 = 80 % of physical memory.
    bead_spacing, point_spacing, initial_path ("Boundary" | "Plane" | "Surface") and cell_file
    are stored for path planning, which is not wired yet (cell_file None = the preference).
    Raises InvalidInput when `solid` is not a solid (checked here, before any computation)."""
    if solid is not None and not geometry.is_mesh_object(solid):
        geometry.solid_shape(solid)
    obj = doc.addObject("App::DocumentObjectGroupPython", name)
    job_module.JobProxy(obj)
    obj.Solid = solid
    obj.LayerThickness = layer_thickness
    if voxel_size is not None:
        obj.VoxelSize = voxel_size
    obj.Method = method
    obj.GridAlignment = grid_alignment
    obj.CapHoles = cap_holes
    obj.Deflection = deflection
    obj.MemoryBudget = memory_budget_mb
    obj.BeadSpacing = bead_spacing
    obj.PointSpacing = point_spacing
    obj.InitialPath = initial_path
    obj.CellFile = preferences.default_cell_file() if cell_file is None else cell_file
    _set_start(obj, start)
    job_module.ensure_layers_group(obj)
    if FreeCAD.GuiUp:
        from .viewproviders import view_job

        view_job.attach(obj)
    return obj


def run(job, progress=None, force=False):
    """Computes the Job's layers now (outside a recompute) and updates its children.

    progress: None = a progress dialog with Cancel in the GUI, nothing headless; False = none;
    or a callable (stage: str, fraction: float) -> bool, False (or raising) to cancel.
    force: rerun even if the inputs did not change. Returns True if the layers were computed.
    Raises the core's exceptions; after any error (including Cancelled) the document is as it
    was before except for the Job's Status."""
    if not is_job(job):
        raise InvalidInput("not a CurvedSlicer Job: %s; pass the object make_job returned"
                           % getattr(job, "Label", job))
    owned = None
    if progress is None and job_module._default_progress_factory is not None:
        owned = progress = job_module._default_progress_factory()
    if progress is False:
        progress = None
    try:
        ran = job_module.update_layers(job, progress=progress, force=force, prune=True)
    except CurvedSlicerError as error:
        job_module.report_failure(job, error)
        raise
    finally:
        if owned is not None and hasattr(owned, "close"):
            owned.close()
    job.purgeTouched()
    if FreeCAD.GuiUp:
        from .viewproviders import view_job

        view_job.color_layers(job)
    return ran


def recompute(job):
    """doc.recompute() for the Job, then removal of layer objects a smaller result left unused."""
    job.touch()
    job.Document.recompute()
    job_module.prune_unused_layers(job)


def estimate(job, voxel_size=None, grid_alignment=None, memory_budget_mb=None, deflection=None):
    """Voxel grid and memory of a run before running it (no allocation): dict with dims, cells,
    bytes, budget_bytes, fits, message (the core's advice when it does not fit) and triangles.
    Keyword values override the Job's properties (the task panel's unsaved values)."""
    voxel = float(job.VoxelSize) if voxel_size is None else float(voxel_size)
    if not voxel > 0:
        raise InvalidInput("voxel size must be positive: %g mm; set VoxelSize, e.g. 0.5" % voxel)
    d = float(job.Deflection) if deflection is None else float(deflection)
    d = d if d > 0 else native.deflection_for_voxel_size(voxel)
    budget = job_module.memory_budget_mb(job) if memory_budget_mb is None else memory_budget_mb
    if budget < 0:
        raise InvalidInput("memory budget must not be negative: %g MB; use 0 for 80 %% of "
                           "physical memory" % budget)
    alignment = job.GridAlignment if grid_alignment is None else grid_alignment
    model = geometry.model_from_object(job.Solid, d, cap_holes=job.CapHoles)
    result = native.estimate_grid(model["vertices"], model["triangles"], voxel_size=voxel,
                                  alignment={"PCA": "pca", "Model": "model"}[alignment],
                                  memory_budget_mb=float(budget))
    result["triangles"] = len(model["triangles"])
    return result


def set_layer_range(job, first, last):
    """Shows layers first..last (1-based, inclusive) and hides the others."""
    for feature in layers(job):
        feature.Visibility = first <= feature.LayerIndex <= last


def export(job, path, format="jbi"):
    """Robot program export. Not available in this version (paths and exporters are not wired
    into the workbench yet): raises NotAvailable rather than writing anything."""
    raise NotAvailable("program export is not available yet: format %r to %s; %s"
                       % (format, path, PATHS_NOT_WIRED))


def tessellate(obj, deflection):
    """The mesh the core slices for `obj` (vertices, triangles, FaceN ids), for inspection."""
    return geometry.model_from_object(obj, deflection)


def write_stl(obj, path, deflection):
    """Tessellates `obj` as the core does and writes a binary STL (face ids are not kept)."""
    model = geometry.model_from_object(obj, deflection)
    native.write_mesh(path, model["vertices"], model["triangles"])
