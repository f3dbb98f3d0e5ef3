"""Paths of a Job (paper §3.1): the plan stage between the layers and the poses.

Two kinds of Job plan paths:
 - CurvedLayers: the planner (paths/planner.hpp planLayers) on the layer meshes stored in the
   Job's "Layers" group and the start-surface triangles of the last layer run, with BeadSpacing,
   PointSpacing, FitTolerance, SurfaceMethod, InitialPath (Boundary, or the section with
   InitialPlane*/InitialSurface) and NarrowStrips (where paths of one level come closer than
   0.95·s: one centre bead, or the overlapping paths kept);
 - ThinWall: the thin-wall planner (planThinWall, the paper's turbine base) on WallSurface, paths
   at k·BeadSpacing from its lowest edge along WallAxis (or the edge nearest WallPoint).

The plan is stored in the Job as its versioned JSON text (``PlanJson``, plan/plan_io.hpp) and drawn
as one Part feature per plan layer (compound of arc-on wires: polylines or B-splines) plus one
"Travel" feature holding the arc-off moves. The stage has its own digest (``PlanDigest``): it
reruns when the layers or a path parameter changed, and a change of a path parameter alone never
reruns the layers. App side: no GUI imports (the view provider styles the lines).
"""

import hashlib
import json

import FreeCAD

from .. import defaults, geometry
from ..core import InvalidInput, native
from .features import ensure_group, group_members, prune_unused_features, retire_features
from .layers import _deflection, layer_objects, memory_budget_mb, start_mesh_object

PLAN_KINDS = ["CurvedLayers", "ThinWall"]
INITIAL_PATHS = ["Boundary", "Plane", "Surface"]
PATH_DISPLAYS = ["Polyline", "BSpline"]
SURFACE_METHODS = ["Accurate", "Paper"]
NARROW_STRIPS = ["CentreBead", "Overlap"]
_NARROW_STRIP_NAMES = {"CentreBead": "centre_bead", "Overlap": "overlap"}
DEPOSITION_DIRECTIONS = ["Growth", "Nearest"]
WALL_EDGES = ["Lowest", "Nearest"]

PATH_PROPERTIES = [
    ("App::PropertyInteger", "LayerIndex", "Paths", "Plan layer index, 1-based"),
    ("App::PropertyInteger", "PathCount", "Paths", "Beads on this layer"),
    ("App::PropertyDistance", "Height", "Paths", "Geodesic height of the layer, mm"),
    ("App::PropertyBool", "CoverageMeasured", "Coverage",
     "Whether the plan measured this layer's coverage (not for thin walls or older plans)"),
    ("App::PropertyFloat", "VoidShare", "Coverage", "Share of the layer no bead covers, %"),
    ("App::PropertyFloat", "OverlapShare", "Coverage",
     "Share of the layer two or more beads cover, %"),
    ("App::PropertyInteger", "ArcStarts", "Coverage", "Arc starts on this layer (its paths)"),
    ("App::PropertyStringList", "Voids", "Coverage",
     "The largest uncovered patches: area, centre and size"),
]


def _vec(v):
    return (float(v.x), float(v.y), float(v.z))


def _mm(quantity):
    return float(FreeCAD.Units.Quantity(quantity).getValueAs("mm"))


def _degrees(quantity):
    return float(FreeCAD.Units.Quantity(quantity).getValueAs("deg"))


#: The corner angle every fit used before CornerAngle existed (Job schema < 4), degrees. Not a
#: default (that is defaults.CORNER_ANGLE, from the core): a migrated Job gets this value, and a
#: Job with it keeps the digest it had then.
LEGACY_CORNER_ANGLE = 30.0


def _corner_angle(job):
    angle = _degrees(job.CornerAngle)
    if not 0.0 < angle <= 180.0:
        raise InvalidInput("CornerAngle must be in (0, 180] degrees: %g; set it, e.g. %g, or 180 "
                           "to keep no corners" % (angle, defaults.CORNER_ANGLE))
    return angle


def mm(quantity):
    """A length property's value in mm."""
    return _mm(quantity)


def _coverage_options(job):
    """The bead coverage options of a Job, checked so that the message names the property,
    and the digest part (empty for the values every plan had before the options existed)."""
    width = _mm(job.MinFeatureWidth)
    if not width > 0:
        raise InvalidInput("MinFeatureWidth must be a positive length: %g mm; set it, e.g. %g "
                           "(half the bead spacing)" % (width, 0.5 * _mm(job.BeadSpacing)))
    low, high = float(job.BeadWidthMin), float(job.BeadWidthMax)
    if not (0 < low <= 1 <= high):
        raise InvalidInput("bead width range BeadWidthMin..BeadWidthMax excludes the bead "
                           "spacing or is empty: %g..%g; set 0 < BeadWidthMin <= 1 <= "
                           "BeadWidthMax, e.g. 0.7 and 1.3, or 1 and 1 for a fixed width"
                           % (low, high))
    area = float(job.MinGapArea)
    if not area > 0:
        raise InvalidInput("MinGapArea must be a positive area: %g mm²; set it, e.g. %g (the "
                           "bead spacing squared)" % (area, _mm(job.BeadSpacing) ** 2))
    options = {"min_feature_width": width, "width_min": low, "width_max": high,
               "min_gap_area": area, "corner_fill": bool(job.CornerFill),
               "corner_fill_angle": float(job.CornerFillAngle),
               "connect_insets": bool(job.ConnectInsets),
               "fill_gaps": bool(job.FillGaps),
               "measure_coverage": bool(job.MeasureCoverage)}
    part = []
    if abs(width - 0.5 * _mm(job.BeadSpacing)) > 1e-12:
        part.append(("min_feature_width", width))
    if (low, high) != (1.0, 1.0):
        part.append(("width_range", low, high))
    if job.ConnectInsets:  # a Job migrated from before the option (False) keeps its digest
        part.append("connect_insets")
    if job.FillGaps:  # likewise for a Job from before gap fill
        part.append("fill_gaps")
    if not job.MeasureCoverage:
        part.append("no_coverage")
    if abs(area - _mm(job.BeadSpacing) ** 2) > 1e-9:  # a migrated Job keeps its digest
        part.append(("min_gap_area", area))
    if job.CornerFill:  # likewise for a Job from before corner fill
        part.append(("corner_fill", float(job.CornerFillAngle)))
    return options, part


def _digest(parts):
    h = hashlib.sha256()
    for part in parts:
        h.update(repr(part).encode("utf-8"))
        h.update(b"\0")
    return h.hexdigest()


# ---- inputs ------------------------------------------------------------------------------------

def _initial_curve(job, deflection):
    """kwargs and digest part of the initial curve of CurvedLayers."""
    kind = job.InitialPath
    if kind == "Boundary":
        return {"initial_curve": native.InitialCurve.boundary()}, "boundary"
    if kind == "Plane":
        point, normal = _vec(job.InitialPlanePoint), _vec(job.InitialPlaneNormal)
        if normal == (0.0, 0.0, 0.0):
            raise InvalidInput("initial plane normal is zero: (0, 0, 0); set InitialPlaneNormal, "
                               "e.g. (1, 0, 0)")
        return ({"initial_curve": native.InitialCurve.plane(point, normal)},
                ("plane", point, normal))
    link = job.InitialSurface
    obj, subs = (link[0], list(link[1])) if link else (None, [])
    if obj is None:
        raise InvalidInput("no initial surface: InitialSurface is empty; link the surface whose "
                           "section with each layer is the first path, or use InitialPath "
                           "Boundary")
    vertices, triangles, digest = geometry.surface_from_object(obj, subs, deflection)
    return ({"initial_curve": native.InitialCurve(kind="surface", surface=(vertices, triangles))},
            ("surface", digest))


def _common_parameters(job):
    spacing, points, tolerance = (_mm(job.BeadSpacing), _mm(job.PointSpacing),
                                  float(job.FitTolerance))
    for name, value in (("BeadSpacing", spacing), ("PointSpacing", points),
                        ("FitTolerance", tolerance)):
        if not value > 0:
            raise InvalidInput("%s must be positive: %g mm; set it, e.g. %s" % (
                name, value, "%g" % {"BeadSpacing": defaults.BEAD_SPACING,
                                     "PointSpacing": defaults.POINT_SPACING,
                                     "FitTolerance": defaults.FIT_TOLERANCE}[name]))
    return {"bead_spacing": spacing, "point_spacing": points, "fit_tolerance": tolerance,
            "surface_method": job.SurfaceMethod.lower(),
            "deposition_direction": job.DepositionDirection.lower()}


def _common_digest(common):
    """The digest part of the common parameters: a Job migrated from before DepositionDirection
    (Nearest) keeps its digest, so a reopened document needs no replan."""
    return sorted((k, v) for k, v in common.items()
                  if (k, v) != ("deposition_direction", "nearest"))


def path_inputs(job):
    """Everything the plan stage needs: (callable that plans, digest)."""
    common = _common_parameters(job)
    corner_angle = _corner_angle(job)
    corner_part = [] if corner_angle == LEGACY_CORNER_ANGLE else [("corner_angle", corner_angle)]
    if job.PlanKind == "ThinWall":
        link = job.WallSurface
        obj, subs = (link[0], list(link[1])) if link else (None, [])
        if obj is None:
            raise InvalidInput("no wall surface: WallSurface is empty; link the wall's surface "
                               "(e.g. the turbine's BaseOuterSurface), or use PlanKind "
                               "CurvedLayers")
        deflection = _deflection(job)
        vertices, triangles, surface_digest = geometry.surface_from_object(obj, subs, deflection)
        edge = {"Lowest": "lowest", "Nearest": "nearest"}[job.WallEdge]
        axis, point = _vec(job.WallAxis), _vec(job.WallPoint)
        if edge == "lowest" and axis == (0.0, 0.0, 0.0):
            raise InvalidInput("wall axis is zero: (0, 0, 0); set WallAxis to the up direction, "
                               "e.g. (0, 0, 1)")
        digest = _digest(["ThinWall", surface_digest, deflection, _common_digest(common), edge,
                          axis, point] + corner_part)

        def plan(progress):
            wall = native.ThinWallOptions(edge=edge, axis=axis, point=point,
                                          corner_angle=corner_angle, **common)
            # The start the plan records, as the bindings wrote it before (std::to_string).
            start = "thin-wall:%s:%f,%f,%f" % ((edge,) + (axis if edge == "lowest" else point))
            options = native.PlanJobOptions(
                thin_wall=wall, model_name=obj.Label, start_spec=start,
                layer_job=native.LayerJobOptions(memory_budget_bytes=_budget_bytes(job)))
            return native.plan_thin_wall(vertices, triangles, options=options,
                                         progress=progress)

        return plan, digest

    layers = layer_objects(job)
    if not layers:
        raise InvalidInput("no layers to plan paths on: %s has no layers; run the Job (its layer "
                           "stage) first" % job.Label)
    deflection = _deflection(job)
    curve, curve_digest = _initial_curve(job, deflection)
    narrow = _NARROW_STRIP_NAMES[job.NarrowStrips]
    coverage, coverage_part = _coverage_options(job)
    parts = ["CurvedLayers", job.InputsDigest, _common_digest(common), curve_digest]
    if narrow != "overlap":  # a Job saved before the option (migrated as Overlap) keeps its digest
        parts.append(narrow)
    digest = _digest(parts + corner_part + coverage_part)
    start = start_mesh_object(job)

    def plan(progress):
        arrays = []
        for feature in layers:
            vertices, triangles = geometry.mesh_arrays(feature.Mesh)
            arrays.append({"index": int(feature.LayerIndex), "height": float(feature.Height),
                           "vertices": vertices, "triangles": triangles})
        kwargs = dict(common)
        kwargs.update(curve)
        kwargs["narrow_strips"] = narrow
        kwargs["corner_angle"] = corner_angle
        kwargs.update(coverage)
        surface = {}
        if start is not None and start.Mesh.CountFacets:
            surface["start_vertices"], surface["start_triangles"] = geometry.mesh_arrays(
                start.Mesh)
        report = json.loads(job.Report) if job.Report else {}
        options = native.PlanJobOptions(
            layer_job=native.LayerJobOptions(
                layer_thickness=_mm(job.LayerThickness), voxel_size=_mm(job.VoxelSize),
                method={"AnyAngle": "anyangle", "Paper": "paper"}[job.Method],
                simplify_layers=bool(job.SimplifyLayers),  # the plan records its tolerance
                memory_budget_bytes=_budget_bytes(job)),
            planner=native.PlannerOptions(**kwargs),
            model_name=job.Solid.Label if job.Solid else "",
            start_spec=str(report.get("inputs", {}).get("start", job.StartMode)))
        return native.plan_layers(arrays, options=options, progress=progress, **surface)

    return plan, digest


def _budget_bytes(job):
    """The Job's memory budget in bytes (0 = 80 % of physical memory): the plan's estimated robot
    points must fit it (the core refuses a point spacing that would not, ResourceLimit)."""
    return memory_budget_mb(job) * 1024.0 * 1024.0


# ---- running -----------------------------------------------------------------------------------

def update_paths(job, progress=None, force=False, prune=True):
    """Replans the paths if their inputs changed (or `force`). Returns True if it ran.

    Raises the core's exceptions; on error the previous plan and path objects stay."""
    plan, digest = path_inputs(job)
    if not force and digest == job.PlanDigest and job.PlanJson:
        return False
    result = plan(progress)
    job.PlanJson = result["plan_json"]
    summary = native.plan_summary(job.PlanJson)
    job.PlanLayerCount = int(summary["layers"])
    job.PathCount = int(summary["paths"])
    job.PathPointCount = int(summary["points"])
    stats = result["stats"]
    job.PlanStats = json.dumps({k: v for k, v in stats.items()}, sort_keys=True)
    _store_coverage(job, summary)
    draw_paths(job, prune=prune)
    job.PlanDigest = digest  # last: the view provider restyles the drawn paths on this change
    return True


def _store_coverage(job, summary):
    """The plan's coverage in the Job's results (percent) and CoverageReport (JSON)."""
    totals = summary["coverage"]
    measured = totals["measured_layers"] > 0
    job.VoidShare = 100.0 * totals["void_share"] if measured else 0.0
    job.OverlapShare = 100.0 * totals["overlap_share"] if measured else 0.0
    job.ArcStarts = int(totals["arc_starts"])
    layers = [{"layer": layer["index"] + 1, "coverage": layer["coverage"]}
              for layer in summary["per_layer"] if layer["coverage"] is not None]
    job.CoverageReport = json.dumps({"totals": totals, "layers": layers}, sort_keys=True)


def ensure_paths_group(job):
    return ensure_group(job, "PathsGroup", "Paths", "paths")


def path_objects(job):
    """Part features of the plan layers (LayerIndex > 0), in layer order."""
    return [o for o in group_members(job.PathsGroup)
            if "LayerIndex" in o.PropertiesList and o.LayerIndex > 0]


def travel_object(job):
    for o in group_members(job.PathsGroup):
        if "TravelMoves" in o.PropertiesList:
            return o
    return None


def _wire(points, closed, display):
    import Part

    vectors = [FreeCAD.Vector(*p) for p in points]
    if closed and (vectors[0] - vectors[-1]).Length > 1e-9:
        vectors.append(vectors[0])
    if display == "BSpline" and len(vectors) >= 4:
        curve = Part.BSplineCurve()
        if closed:
            curve.interpolate(vectors[:-1], PeriodicFlag=True)
        else:
            curve.interpolate(vectors)
        return Part.Wire([curve.toShape()])
    return Part.makePolygon(vectors)


def _add_path_properties(feature):
    """Adds the properties a path layer lacks (a new feature, or one of an older document)."""
    for (ptype, name, pgroup, tooltip) in PATH_PROPERTIES:
        if name not in feature.PropertiesList:
            feature.addProperty(ptype, name, pgroup, tooltip)
            feature.setEditorMode(name, 1)


def _set_layer_coverage(feature, coverage, paths):
    feature.CoverageMeasured = coverage is not None
    feature.VoidShare = 100.0 * coverage["void_share"] if coverage else 0.0
    feature.OverlapShare = 100.0 * coverage["overlap_share"] if coverage else 0.0
    feature.ArcStarts = int(coverage["arc_starts"]) if coverage else paths
    feature.Voids = ["%.3g mm2 at (%.1f, %.1f, %.1f) mm, %.3g mm across"
                     % ((v["area_mm2"],) + tuple(v["centre_mm"]) + (v["size_mm"],))
                     for v in (coverage["voids"] if coverage else [])]


def draw_paths(job, prune=True):
    """(Re)builds the path features from job.PlanJson: one per plan layer, and the travel."""
    import Part

    doc = job.Document
    group = ensure_paths_group(job)
    existing = [o for o in group_members(group) if "LayerIndex" in o.PropertiesList]
    paths = native.plan_paths(job.PlanJson) if job.PlanJson else []
    summary = native.plan_summary(job.PlanJson) if job.PlanJson else {"per_layer": []}
    by_layer = {}
    for (layer, index, closed, points, _normals, _dep) in paths:
        by_layer.setdefault(layer, []).append((closed, points.tolist()))
    travel = []
    previous_end = None
    for (layer, index, closed, points, _normals, _dep) in paths:
        start = tuple(points[0].tolist())
        if previous_end is not None and previous_end != start:
            travel.append(Part.LineSegment(FreeCAD.Vector(*previous_end),
                                           FreeCAD.Vector(*start)).toShape())
        previous_end = start if closed else tuple(points[-1].tolist())
    layers = summary["per_layer"]
    for i, layer in enumerate(layers):
        if i < len(existing):
            feature = existing[i]
        else:
            feature = doc.addObject("Part::Feature", "PathLayer")
            group.addObject(feature)
        _add_path_properties(feature)
        wires = [_wire(points, closed, job.PathDisplay)
                 for (closed, points) in by_layer.get(layer["index"], [])]
        # A layer without paths gets a null shape: an empty compound has no bounding box, and
        # the 3D view reports it ("Cannot compute Inventor representation … Bnd_Box is void").
        feature.Shape = Part.makeCompound(wires) if wires else Part.Shape()
        feature.Label = "%s paths %03d" % (job.Label, layer["index"] + 1)
        feature.LayerIndex = int(layer["index"]) + 1
        feature.PathCount = int(layer["paths"])
        feature.Height = float(layer["height"])
        _set_layer_coverage(feature, layer["coverage"], len(by_layer.get(layer["index"], [])))
        feature.Visibility = True
        feature.purgeTouched()
    retire_features(group, existing[len(layers):], prune,
                    lambda f: setattr(f, "Shape", Part.Shape()), "%s unused paths" % job.Label)
    moves = travel_object(job)
    if moves is None:
        moves = doc.addObject("Part::Feature", "Travel")
        moves.addProperty("App::PropertyInteger", "TravelMoves", "Paths",
                          "Arc-off moves between consecutive paths")
        moves.setEditorMode("TravelMoves", 1)
        group.addObject(moves)
    moves.Shape = Part.makeCompound(travel) if travel else Part.Shape()
    moves.TravelMoves = len(travel)
    moves.Label = "%s travel (arc off)" % job.Label
    moves.purgeTouched()
    group.purgeTouched()
    from .voids import refresh_voids  # here: voids.py draws on the path features

    refresh_voids(job, prune=prune)


def prune_unused_paths(job):
    """Removes path features a smaller plan emptied inside a recompute."""
    prune_unused_features(job.PathsGroup)


def bead_parts(points, closed):
    """The beads of one planned path as [(points (k,3), ring)]: a path joined from rings
    (connected insets, paths/connected_insets.hpp) splits into its ring parts, each from a point
    to the next exact repeat of it (repeat included), and the links between them are left out;
    any other path is one bead (ring = closed)."""
    if closed:
        return [(points, True)]
    n = len(points)
    following, seen = [None] * n, {}
    for i in range(n - 1, -1, -1):
        key = tuple(points[i])
        following[i] = seen.get(key)
        seen[key] = i

    def repeat_of(i):
        return following[i]

    parts, i = [], 0
    while i + 1 < n:
        end = repeat_of(i)
        if end is None:
            if not parts:
                parts.append((points[i:], False))
            break
        parts.append((points[i:end + 1], True))
        i = next((k for k in range(end + 1, n) if repeat_of(k) is not None), n)
    return parts


def plan_beads(job):
    """The beads of the stored plan as [(layer, points (k,3), ring)] (see bead_parts)."""
    return [(path[0], points, ring) for path in native.plan_paths(job.PlanJson)
            for points, ring in bead_parts(path[3], path[2])]


def plan_spacing(job):
    """Distances between neighbouring beads measured on the stored plan (mm): thin wall, the
    median distance of each bead's points to the previous bead; curved layers, per bead (a ring
    part of a joined path counts as a bead of its own, see bead_parts) the smallest median
    distance of its points to another bead of the same layer."""
    import numpy as np

    paths = [(layer, None, None, points) for layer, points, _ in plan_beads(job)]
    result = []

    def distance_to_polyline(points, line):
        a, b = line[:-1], line[1:]
        ab = b - a
        denom = np.maximum((ab * ab).sum(axis=1), 1e-300)
        best = np.full(len(points), np.inf)
        for p_i, p in enumerate(points):
            t = np.clip(((p - a) * ab).sum(axis=1) / denom, 0.0, 1.0)
            d = np.linalg.norm(a + t[:, None] * ab - p, axis=1)
            best[p_i] = d.min()
        return best

    if job.PlanKind == "ThinWall":
        for first, second in zip(paths, paths[1:]):
            result.append(float(np.median(distance_to_polyline(second[3], first[3]))))
        return result
    for i, path in enumerate(paths):
        others = [q for j, q in enumerate(paths) if j != i and q[0] == path[0]]
        if others:
            result.append(min(float(np.median(distance_to_polyline(path[3], q[3])))
                              for q in others))
    return result
