"""What a Job shows: the results after a run with the solid hidden, the cell at
the pose on or off (it sits in cell coordinates, a metre or more from the part's own frame, so
Fit All frames the part only without it), one layer isolated — its surface and its paths — and
that layer's numbers (height, paths, coverage, warnings) from the stored plan.

Visibility here is the App-side ``Visibility`` of document objects: document state, saved with
the document, recorded in macros through the API. App side: no GUI imports.
"""

import json
import re

from .layers import layer_objects
from .paths import path_objects, travel_object
from .poses import pose_objects
from .voids import sync_voids

_plan_cache = {}  # (document name, job name) -> (PlanJson digest, parsed layers)


def _set(obj, visible):
    if obj is not None and bool(obj.Visibility) != bool(visible):
        obj.Visibility = bool(visible)


def show_solid(job, visible):
    _set(job.Solid, visible)


def show_cell(job, visible):
    """The cell at the pose shown or hidden; the layers, paths and travel in the part's own
    frame (which sits at the world origin, inside the robot's base) the other way round: all
    of them shown again when the cell is hidden."""
    if job.PosesGroup is None:
        return
    for obj in pose_objects(job).values():
        _set(obj, visible)
    if visible:
        show_layer_range(job, 1, 0)  # an empty range: nothing of the part frame
    else:
        show_layer(job, 0)


def cell_shown(job):
    return any(o.Visibility for o in pose_objects(job).values()) if job.PosesGroup else False


def show_layer_range(job, first, last):
    """Layer surfaces and path features with first <= LayerIndex <= last shown, others hidden;
    the travel shown only when every plan layer is in the range."""
    for feature in layer_objects(job):
        _set(feature, first <= feature.LayerIndex <= last)
    features = path_objects(job)
    for feature in features:
        _set(feature, first <= feature.LayerIndex <= last)
    everything = all(first <= f.LayerIndex <= last for f in features)
    _set(travel_object(job), everything)
    sync_voids(job)  # a shown layer's uncovered regions with it


def show_layer(job, index):
    """Only layer `index` (1-based); 0: every layer."""
    if index <= 0:
        show_layer_range(job, 1, max(job.LayerCount, job.PlanLayerCount, 1))
    else:
        show_layer_range(job, index, index)


def show_results(job):
    show_solid(job, False)
    show_cell(job, False)


def plan_layers(job):
    """The stored plan's layers as parsed JSON objects (cached per plan text)."""
    key = (job.Document.Name, job.Name)
    text = job.PlanJson
    cached = _plan_cache.get(key)
    if cached is not None and cached[0] == hash(text):
        return cached[1]
    layers = json.loads(text)["layers"] if text else []
    _plan_cache[key] = (hash(text), layers)
    return layers


def _motion_warnings(job, index):
    """The Job's motion warnings naming plan layer `index` (1-based; the core names layers by
    their 0-based plan index, e.g. "layer 3 path 0 point 12")."""
    pattern = re.compile(r"\blayer %d\b" % (index - 1))
    return [w for w in job.MotionWarnings if pattern.search(w)]


def layer_info(job, index):
    """Numbers of plan layer `index` (1-based) for display (see api.layer_info)."""
    layers = plan_layers(job)
    if not 1 <= index <= len(layers):
        from ..core import InvalidInput

        raise InvalidInput("no layer %d: %s has %d plan layers; pick 1 to %d"
                           % (index, job.Label, len(layers), len(layers)))
    layer = layers[index - 1]
    paths = layer.get("paths", [])
    return {"index": index, "count": len(layers), "height": float(layer["height_mm"]),
            "paths": len(paths), "points": sum(len(p.get("points", [])) for p in paths),
            "warnings": list(layer.get("warnings", [])) + _motion_warnings(job, index),
            "coverage": layer.get("coverage")}
