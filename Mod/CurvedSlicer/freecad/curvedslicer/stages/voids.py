"""Uncovered regions of a plan in the 3D view: per layer, the uncovered regions coloured.

The plan's coverage (paths/coverage.hpp) lists per layer its largest voids: area, centre and size.
Each plan layer with voids gets one Part feature in the "Voids" group (inside the Job's Paths
group) holding one disc per void: centred on the void's centre, in the layer's tangent plane there
(the layer surface's area-weighted normal within the disc's radius, at least 1 mm; without a layer
surface, the normal of the nearest plan point), lifted VOID_LIFT along that normal so that it is
not hidden in the layer surface, with the void's area (radius sqrt(area / pi), at least
VOID_MIN_RADIUS so a speck stays visible). The discs mark where the holes are and how big; they
are not the holes' outlines.

The markers are made on demand (show_voids) and redrawn with the paths while the group exists.
Shown, a layer's markers follow its path feature: isolating one layer (views.show_layer) shows
that layer's voids only. State is the App-side ``Visibility`` (saved with the document; the group
carries ``VoidsShown``). App side: no GUI imports.
"""

import hashlib
import math

import FreeCAD

from ..core import native
from .features import group_members, prune_unused_features, retire_features
from .paths import ensure_paths_group, path_objects

VOID_LIFT = 0.1  # mm along the layer normal
VOID_MIN_RADIUS = 0.5  # mm

VOID_PROPERTIES = [
    ("App::PropertyInteger", "LayerIndex", "Voids", "Plan layer index, 1-based"),
    ("App::PropertyInteger", "VoidCount", "Voids", "Voids marked on this layer"),
    ("App::PropertyStringList", "Voids", "Voids",
     "The marked voids: area, centre and size (the plan's coverage)"),
    ("App::PropertyVectorList", "VoidCentres", "Voids", "The voids' centres, mm (part frame)"),
]


def voids_group(job):
    """The Job's "Voids" group, or None before the markers were first shown."""
    for obj in group_members(job.PathsGroup):
        if "VoidsShown" in obj.PropertiesList:
            return obj
    return None


def _ensure_group(job):
    group = voids_group(job)
    if group is None:
        group = job.Document.addObject("App::DocumentObjectGroup", "Voids")
        group.addProperty("App::PropertyBool", "VoidsShown", "Voids",
                          "Whether the uncovered regions are shown")
        group.addProperty("App::PropertyString", "VoidsDigest", "Voids",
                          "Digest of the plan text the markers were drawn for")
        group.setEditorMode("VoidsDigest", 2)
        group.Label = "%s uncovered regions" % job.Label
        paths = ensure_paths_group(job)
        paths.addObject(group)
        paths.purgeTouched()
    return group


def plan_text_digest(job):
    return hashlib.sha256(job.PlanJson.encode("utf-8")).hexdigest()


def void_objects(job):
    """The marker features (LayerIndex > 0), in layer order."""
    return sorted((o for o in group_members(voids_group(job))
                   if "LayerIndex" in o.PropertiesList and o.LayerIndex > 0),
                  key=lambda o: o.LayerIndex)


def _normals_by_layer(plan_json):
    """{plan layer (0-based): (points (n,3), normals (n,3))} of the plan's points."""
    import numpy as np

    gathered = {}
    for (layer, _index, _closed, points, normals, _dep) in native.plan_paths(plan_json):
        gathered.setdefault(layer, []).append((np.asarray(points), np.asarray(normals)))
    return {layer: (np.vstack([p for p, _ in parts]), np.vstack([n for _, n in parts]))
            for layer, parts in gathered.items()}


def _surface_normals(job):
    """{plan layer (0-based): (facet centroids (m,3), area-weighted facet normals (m,3))} of the
    Job's layer surfaces."""
    import numpy as np

    from .layers import layer_objects

    result = {}
    for feature in layer_objects(job):
        points, triangles = feature.Mesh.Topology
        if not triangles:
            continue
        vertices = np.array([(p.x, p.y, p.z) for p in points])
        corners = vertices[np.array(triangles)]
        normals = 0.5 * np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        result[feature.LayerIndex - 1] = (corners.mean(axis=1), normals)
    return result


def marker_normal(centre, radius, layer, surfaces, by_layer):
    """Unit normal at `centre`: the area-weighted normal of the layer surface's facets within
    max(radius, 1 mm) of it (the nearest facet's if none), else (no surface) the nearest plan
    point's on `layer` or any layer, else +z."""
    import numpy as np

    if layer in surfaces:
        centroids, normals = surfaces[layer]
        distance = np.linalg.norm(centroids - np.asarray(centre), axis=1)
        near = distance <= max(radius, 1.0)
        total = normals[near].sum(axis=0) if near.any() else normals[int(np.argmin(distance))]
        if np.linalg.norm(total) > 0:
            return tuple(float(c) for c in total / np.linalg.norm(total))
    candidates = [by_layer[layer]] if layer in by_layer else list(by_layer.values())
    best, best_d = (0.0, 0.0, 1.0), math.inf
    for points, normals in candidates:
        d = np.linalg.norm(points - np.asarray(centre), axis=1)
        k = int(np.argmin(d))
        if d[k] < best_d and np.linalg.norm(normals[k]) > 0:
            best, best_d = tuple(float(c) for c in normals[k] / np.linalg.norm(normals[k])), d[k]
    return best


def marker_radius(area_mm2):
    return max(math.sqrt(max(float(area_mm2), 0.0) / math.pi), VOID_MIN_RADIUS)


def _disc(centre, normal, radius):
    import Part

    n = FreeCAD.Vector(*normal)
    c = FreeCAD.Vector(*centre) + n * VOID_LIFT
    return Part.Face(Part.Wire(Part.makeCircle(radius, c, n)))


def _describe(void):
    return ("%.3g mm2 at (%.1f, %.1f, %.1f) mm, %.3g mm across"
            % ((void["area_mm2"],) + tuple(void["centre_mm"]) + (void["size_mm"],)))


def draw_voids(job, prune=True):
    """(Re)builds the markers from job.PlanJson: one feature per plan layer with voids."""
    import Part

    group = _ensure_group(job)
    existing = [o for o in group_members(group) if "LayerIndex" in o.PropertiesList]
    summary = native.plan_summary(job.PlanJson) if job.PlanJson else {"per_layer": []}
    by_layer = _normals_by_layer(job.PlanJson) if job.PlanJson else {}
    surfaces = _surface_normals(job)
    layers = [layer for layer in summary["per_layer"]
              if layer["coverage"] is not None and layer["coverage"]["voids"]]
    for i, layer in enumerate(layers):
        if i < len(existing):
            feature = existing[i]
        else:
            feature = job.Document.addObject("Part::Feature", "VoidMarkers")
            group.addObject(feature)
        for (ptype, name, pgroup, tooltip) in VOID_PROPERTIES:
            if name not in feature.PropertiesList:
                feature.addProperty(ptype, name, pgroup, tooltip)
                feature.setEditorMode(name, 1)
        voids = layer["coverage"]["voids"]
        discs = []
        for v in voids:
            radius = marker_radius(v["area_mm2"])
            normal = marker_normal(v["centre_mm"], radius, layer["index"], surfaces, by_layer)
            discs.append(_disc(v["centre_mm"], normal, radius))
        feature.Shape = Part.makeCompound(discs)
        feature.LayerIndex = int(layer["index"]) + 1
        feature.VoidCount = len(voids)
        feature.Voids = [_describe(v) for v in voids]
        feature.VoidCentres = [FreeCAD.Vector(*v["centre_mm"]) for v in voids]
        feature.Label = "%s voids %03d" % (job.Label, feature.LayerIndex)
        feature.purgeTouched()
    retire_features(group, existing[len(layers):], prune,
                    lambda f: setattr(f, "Shape", Part.Shape()), "%s unused voids" % job.Label)
    group.VoidsDigest = plan_text_digest(job)
    sync_voids(job)
    group.purgeTouched()


def refresh_voids(job, prune=True):
    """After the paths were drawn: redraws the markers if they were ever shown."""
    if voids_group(job) is not None:
        draw_voids(job, prune=prune)


def prune_unused_voids(job):
    group = voids_group(job)
    if group is not None:
        prune_unused_features(group)


def _set(obj, visible):
    if obj is not None and bool(obj.Visibility) != bool(visible):
        obj.Visibility = bool(visible)


def sync_voids(job):
    """Markers shown exactly where the group is shown and the layer's paths are shown."""
    group = voids_group(job)
    if group is None:
        return
    shown = bool(group.VoidsShown)
    visible_layers = {f.LayerIndex for f in path_objects(job) if f.Visibility}
    _set(group, shown)
    for feature in void_objects(job):
        _set(feature, shown and feature.LayerIndex in visible_layers)


def show_voids(job, visible):
    """Shows (drawing them first if missing or older than the plan) or hides the markers. Only
    the markers' group changes: the Job is not marked for a recompute."""
    group = voids_group(job)
    if visible and (group is None or group.VoidsDigest != plan_text_digest(job)):
        draw_voids(job)
        group = voids_group(job)
    if group is None:
        return
    group.VoidsShown = bool(visible)
    sync_voids(job)
    group.purgeTouched()


def voids_shown(job):
    group = voids_group(job)
    return bool(group is not None and group.VoidsShown)
