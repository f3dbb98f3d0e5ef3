"""The stages of a Job, run in order: layers (stages/layers.py, CurvedLayers only), paths
(stages/paths.py) and poses (stages/poses.py). Each stage reads the Job's properties, reruns only
when the digest of its inputs changed (or when forced), writes its results into the Job's result
properties and its group of result features, and reports errors in ``Status`` (layers) or
``PathsStatus`` (paths, poses). The Job's proxy (objects/job.py) and the macro API (api.py) both
call ``update_job``; it is App side: no GUI imports (docs/WORKBENCH.md).
"""

import FreeCAD

from ..core import Cancelled, CurvedSlicerError
from ..messages import rephrased
from . import layers, paths, poses, voids


def _scaled(progress, begin, end):
    """progress(stage, fraction) mapped into [begin, end] (fractions never go backwards)."""
    if progress is None:
        return None
    return lambda stage, fraction: progress(stage, begin + (end - begin) * fraction)


def update_job(job, progress=None, force=False, prune=True):
    """Layers (CurvedLayers only), then paths, then poses, each only if its inputs changed (or
    `force`). Reports an error in Status (layers) or PathsStatus (paths, poses) and re-raises it;
    what an earlier run computed stays. `prune`: remove surplus result features at once (False
    inside a recompute). Returns (layers ran, paths ran)."""
    ran_layers = False
    if job.PlanKind == "CurvedLayers":
        try:
            ran_layers = layers.update_layers(job, progress=_scaled(progress, 0.0, 0.85),
                                              force=force, prune=prune)
        except CurvedSlicerError as error:
            error = rephrased(error)
            report_failure(job, error)
            raise error from None
    else:
        job.Status = "Thin wall: no volume layers (the wall's beads are the plan layers)"
    try:
        ran_paths = paths.update_paths(job, progress=_scaled(progress, 0.85, 1.0),
                                       force=force or ran_layers, prune=prune)
        poses.update_poses(job)
    except CurvedSlicerError as error:
        error = rephrased(error)
        report_paths_failure(job, error)
        raise error from None
    job.PathsStatus = "%s: %d paths (%d points) on %d plan layers%s" % (
        "Planned" if ran_paths else "Up to date", job.PathCount, job.PathPointCount,
        job.PlanLayerCount, "" if ran_paths else " (inputs unchanged, not rerun)")
    return ran_layers, ran_paths


def stale_reason(job, motion=True):
    """Why the Job's stored results do not belong to its current inputs, or "" when they do: its
    last run failed, or an input of its layers, its paths or (`motion`) its motion — the cell
    and the robot options — changed since they were computed. The 3D view then shows, and an
    export would write, the earlier results."""
    if "Invalid" in job.State:
        status = job.PathsStatus if job.PathsStatus.startswith(("Invalid", "Resource", "Io")) \
            else job.Status
        return "its last run failed (%s)" % status
    if job.PlanKind == "CurvedLayers" and layers.layer_inputs(job)[2] != job.InputsDigest:
        return "its layer inputs changed since the layers were computed"
    if paths.path_inputs(job)[1] != job.PlanDigest:
        return "its path inputs changed since the paths were planned"
    if motion and job.MotionDigest and poses.motion_digest(job) != job.MotionDigest:
        return "its cell or robot options changed since its motion was planned"
    return ""


def report_failure(job, error):
    """A layer-stage error in Status and the Report view."""
    kind = type(error).__name__
    if isinstance(error, Cancelled):
        job.Status = "Cancelled: the layers shown are from the previous run"
    else:
        job.Status = "%s: %s" % (kind, error)
    FreeCAD.Console.PrintError("CurvedSlicer %s: %s: %s\n" % (job.Label, kind, error))


def report_paths_failure(job, error):
    """A path- or pose-stage error in PathsStatus and the Report view."""
    kind = type(error).__name__
    job.PathsStatus = ("Cancelled: the paths shown are from the previous run"
                       if isinstance(error, Cancelled) else "%s: %s" % (kind, error))
    FreeCAD.Console.PrintError("CurvedSlicer %s paths: %s: %s\n" % (job.Label, kind, error))


def prune_unused(job):
    """Removes the result features a recompute emptied (call outside a recompute)."""
    layers.prune_unused_layers(job)
    paths.prune_unused_paths(job)
    voids.prune_unused_voids(job)
