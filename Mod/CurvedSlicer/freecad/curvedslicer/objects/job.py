"""The CurvedSlicer Job: a document object holding a solid, a start surface and the slicing,
path and cell parameters, and its children: a "Layers" group (one Mesh feature per curved layer
and the hidden start-surface mesh), a "Paths" group (one Part feature of bead wires per plan
layer and the arc-off travel) and a "Poses" group (the positioner model carrying the part).

This module is the thin proxy: the property list, persistence and migration, and ``execute``,
which calls the stages (stages/: layers, paths, poses; each reruns only when the digest of its
inputs changed). Layers are stored as Mesh features, the plan as its versioned JSON text
(``PlanJson``), both saved in the .FCStd, so a reopened document needs no recompute and
re-exports byte-identical programs. Errors of the core or of the input are shown in ``Status``
(layers) or ``PathsStatus`` (paths, poses) and the Report view, and put the Job in FreeCAD's
error state (``execute`` raises JobFailed; api.run raises the core's error and marks the Job
the same way). Result features a recompute emptied are removed once the recompute is over (a
document observer). App side: no GUI imports (the view provider is
attached through hooks.py, see docs/WORKBENCH.md).
"""

import FreeCAD

from .. import SCHEMA_VERSION, defaults, hooks, preferences, stages
from ..core import CurvedSlicerError
from ..stages import layers, paths, poses

JOB_TYPE = "CurvedSlicer::Job"

START_MODES = layers.START_MODES
METHODS = layers.METHODS
ALIGNMENTS = layers.ALIGNMENTS
INITIAL_PATHS = paths.INITIAL_PATHS
PLAN_KINDS = paths.PLAN_KINDS
WALL_EDGES = paths.WALL_EDGES
SURFACE_METHODS = paths.SURFACE_METHODS
NARROW_STRIPS = paths.NARROW_STRIPS
DEPOSITION_DIRECTIONS = paths.DEPOSITION_DIRECTIONS
PATH_DISPLAYS = paths.PATH_DISPLAYS
PART_PLACEMENTS = poses.PART_PLACEMENTS

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
    ("App::PropertyLength", "LayerThickness", "Layers", "Layer thickness h, mm",
     defaults.LAYER_THICKNESS),
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
    ("App::PropertyBool", "SimplifyLayers", "Layers",
     "Simplify each layer surface by edge collapse within 0.05 x VoxelSize of the full-resolution "
     "surface, the rim kept on the part (lighter layers and a faster plan); off keeps the "
     "marching-tetrahedra surfaces (about 4-5 triangles per voxel crossed)",
     defaults.SIMPLIFY_LAYERS),
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
     "wall)", defaults.BEAD_SPACING),
    ("App::PropertyLength", "PointSpacing", "Paths", "Largest distance between robot points, mm",
     defaults.POINT_SPACING),
    ("App::PropertyFloat", "FitTolerance", "Paths", "Spline fit tolerance of the paths, mm",
     defaults.FIT_TOLERANCE),
    ("App::PropertyAngle", "CornerAngle", "Paths",
     "Where a path turns by more than this within 0.2 mm, the spline fit keeps the raw vertex as "
     "an exact corner, degrees in (0, 180]; 180 keeps no corners (every path one smooth spline)",
     defaults.CORNER_ANGLE),
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
    ("App::PropertyEnumeration", "DepositionDirection", "Paths",
     "Deposition direction V of every path point, the direction the positioner turns onto "
     "gravity: Growth keeps the paper's V (towards the nearest deposited point) where it lies "
     "within 30 degrees of the layer's growth direction (against its normal, or the layer "
     "below's mean V where a small layer's normal disagrees with it), else takes that direction; "
     "Nearest keeps the paper's V everywhere, also where the nearest point is a bead beside the "
     "path on the same layer", DEPOSITION_DIRECTIONS),
    ("App::PropertyLength", "MinFeatureWidth", "Paths",
     "Regions narrower than one bead but at least this wide get a single bead on their centre "
     "line (with a note of the shortfall); narrower ones are left out and reported, mm > 0 "
     "(default half the default BeadSpacing)", defaults.MIN_FEATURE_WIDTH),
    ("App::PropertyFloat", "BeadWidthMin", "Paths",
     "Adaptive bead width: smallest bead width as a fraction of BeadSpacing, in (0, 1]; "
     "BeadWidthMin = BeadWidthMax = 1 is a fixed width", defaults.BEAD_WIDTH_MIN),
    ("App::PropertyFloat", "BeadWidthMax", "Paths",
     "Adaptive bead width: largest bead width as a fraction of BeadSpacing, >= 1",
     defaults.BEAD_WIDTH_MAX),
    ("App::PropertyBool", "ConnectInsets", "Paths",
     "Join consecutive rings of one region with a short step-over into one arc-on path (fewer "
     "arc starts)", defaults.CONNECT_INSETS),
    ("App::PropertyBool", "FillGaps", "Paths",
     "Give uncovered strips between beads (at least MinFeatureWidth wide) a bead on their centre "
     "line, and widen the beads beside narrower strips into them", defaults.FILL_GAPS),
    ("App::PropertyFloat", "MinGapArea", "Paths",
     "Gap fill: the smallest uncovered patch that gets a fill bead, mm² > 0 (default the "
     "default BeadSpacing squared); smaller patches stay empty", defaults.MIN_GAP_AREA),
    ("App::PropertyBool", "CornerFill", "Paths",
     "Dip the outer ring toward the layer's acute convex corners so its bead covers the corner "
     "(the bead's edge at most a quarter of BeadSpacing past the part's edge)",
     defaults.CORNER_FILL),
    ("App::PropertyFloat", "CornerFillAngle", "Paths",
     "Corner fill takes corners of the layer boundary sharper than this, degrees in (0, 180) "
     "(default: acute corners)", defaults.CORNER_FILL_ANGLE),
    ("App::PropertyBool", "MeasureCoverage", "Paths",
     "Measure every layer's bead coverage (void and overlap shares, VoidShare / OverlapShare of "
     "the path layers)", defaults.MEASURE_COVERAGE),
    ("App::PropertyEnumeration", "PathDisplay", "Paths",
     "Draw the paths as Polyline (the robot points) or BSpline (interpolated)", PATH_DISPLAYS),
    ("App::PropertyFile", "CellFile", "Robot",
     "Robot cell description (JSON, resources/cells); empty = the paper's cell (Motoman HP20D "
     "with a tilt-rotate positioner)", ""),
    ("App::PropertyBool", "ToolAlongTravel", "Robot",
     "Torch x axis along the travel direction; off keeps the torch orientation fixed while the "
     "positioner turns the part (default; no wrist wind-up on long rings)", False),
    ("App::PropertyLength", "Clearance", "Robot",
     "Arc-off moves leave back up the torch's axis to this height above the part and the "
     "deposit, travel there and approach down the torch's axis, mm", defaults.CLEARANCE),
    ("App::PropertyBool", "AllowCollisions", "Robot",
     "Plan the motion although torch or positioner still collide after re-routing (each "
     "collision a warning in MotionWarnings); off: a collision is an error",
     defaults.ALLOW_COLLISIONS),
    ("App::PropertyBool", "AddHome", "Robot",
     "Start and end the program at the cell's home pose", defaults.ADD_HOME),
    ("App::PropertyLength", "MergeTolerance", "Robot",
     "Consecutive path points closer than this are merged into one, mm",
     defaults.MERGE_TOLERANCE),
    ("App::PropertyAngle", "MaxA2Step", "Robot",
     "Largest turn of the positioner rotation a2 between consecutive points of a weld; points "
     "are inserted where it turns faster, degrees", defaults.MAX_A2_STEP),
    ("App::PropertyEnumeration", "PartPlacement", "Robot",
     "Where the part sits on the table: Rest (the cell's table_to_part rotation and xy, moved "
     "along the table z so the lowest bead bottom lies on the fixture's top, the cell's riser "
     "and substrate plate, or on the table top without one), Cell (the cell's table_to_part as "
     "given) or Auto (Rest, on the lowest riser that keeps the torch clear of the table on "
     "every move); a weld point below the fixture's top or outside the working volume is an "
     "error", PART_PLACEMENTS),
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
    ("App::PropertyFloat", "VoidShare", "Results",
     "Share of the layers' area no bead covers, area-weighted over the measured layers, %", 0.0),
    ("App::PropertyFloat", "OverlapShare", "Results",
     "Share of the layers' area two or more beads cover, area-weighted, %", 0.0),
    ("App::PropertyInteger", "ArcStarts", "Results", "Arc starts of the plan (its paths)", 0),
    ("App::PropertyString", "CoverageReport", "Results",
     "Bead coverage: totals, the layers with the largest void share and each layer's largest "
     "voids (JSON)", ""),
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
    ("App::PropertyFloat", "PoseTorchAngle", "Results",
     "Angle of the torch off gravity at PosePoint (tilted to clear the deposit, the table or the "
     "fixture), degrees", 0.0),
    ("App::PropertyFloat", "MaxTorchAngle", "Results",
     "Largest angle of the torch off gravity over the motion, degrees", 0.0),
    ("App::PropertyFloat", "MaxGravityDeviation", "Results",
     "Largest angle between the turned deposition direction and gravity over the motion, "
     "degrees", 0.0),
    ("App::PropertyInteger", "CollisionCount", "Results",
     "Moves on which the torch still hits the deposit, the table or the fixture (only with "
     "AllowCollisions; otherwise planning stops at the first)", 0),
    ("App::PropertyStringList", "MotionWarnings", "Results",
     "Warnings of the motion planning (limits, unreachable points)", []),
    ("App::PropertyString", "InputsDigest", "Internal",
     "SHA-256 of the inputs the current layers were computed from", ""),
    ("App::PropertyString", "PlanDigest", "Internal",
     "SHA-256 of the inputs the current plan was computed from", ""),
    ("App::PropertyString", "MotionDigest", "Internal",
     "SHA-256 of the plan, cell and robot options the shown motion was planned with", ""),
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


def default_voxel_size():
    return preferences.default_voxel_size()


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
    for name in ("InputsDigest", "LayersGroup", "MotionDigest", "PlanDigest", "PlanJson",
                 "PathsGroup", "PosesGroup"):
        obj.setEditorMode(name, 2)  # hidden
    return added


def refresh_enumerations(obj):
    """Gives every choice property of `obj` this version's list of choices (a Job saved by an
    older workbench stores the list it had, e.g. PartPlacement without Auto), keeping its value.
    """
    for (ptype, name, _group, _tooltip, default) in PROPERTIES:
        if ptype != "App::PropertyEnumeration" or name not in obj.PropertiesList:
            continue
        choices = list(default)
        if list(obj.getEnumerationsOfProperty(name)) == choices:
            continue
        value = getattr(obj, name)
        setattr(obj, name, choices)
        setattr(obj, name, value if value in choices else choices[0])


class JobProxy:
    """Proxy of a Job (App::DocumentObjectGroupPython)."""

    Type = JOB_TYPE

    def __init__(self, obj):
        obj.Proxy = self
        self.Type = JOB_TYPE
        add_missing_properties(obj)
        install_observer()

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
        install_observer()
        old = obj.SchemaVersion if "SchemaVersion" in obj.PropertiesList else 0
        added = add_missing_properties(obj)
        refresh_enumerations(obj)
        if "CornerAngle" in added:
            # Planned before the option existed: its fit used the legacy angle.
            obj.CornerAngle = paths.LEGACY_CORNER_ANGLE
        if "NarrowStrips" in added:
            # Planned before the option existed: keep what it planned (overlapping paths).
            obj.NarrowStrips = "Overlap"
        if "DepositionDirection" in added:
            # Planned before the option existed: the paper's V (towards the nearest point).
            obj.DepositionDirection = "Nearest"
        if "ConnectInsets" in added:
            # Planned before the option existed: every ring its own arc-on path.
            obj.ConnectInsets = False
        if "FillGaps" in added:
            # Planned before the option existed: strips between beads stayed empty.
            obj.FillGaps = False
        if "MinGapArea" in added:
            # The core's default for the Job's own bead spacing (what gap fill used before).
            obj.MinGapArea = paths.mm(obj.BeadSpacing) ** 2
        if "CornerFill" in added:
            # Planned before the option existed: the outer rings kept off the corners.
            obj.CornerFill = False
        if "MinFeatureWidth" in added:
            # The core's default for the Job's own bead spacing.
            obj.MinFeatureWidth = 0.5 * paths.mm(obj.BeadSpacing)
        if "SimplifyLayers" in added:
            # Sliced before the option existed: its layers are full resolution.
            obj.SimplifyLayers = False
        if "PartPlacement" in added:
            # Planned before the option existed: the part sat where the cell put it.
            obj.PartPlacement = "Cell"
        if old < SCHEMA_VERSION or added:
            obj.SchemaVersion = SCHEMA_VERSION
            FreeCAD.Console.PrintLog("CurvedSlicer: migrated %s from schema %d (added %s)\n"
                                     % (obj.Label, old, ", ".join(added) or "nothing"))
        # In the GUI: a Job saved headless gets its view provider; the layers are coloured.
        hooks.restore_view(obj)

    def execute(self, obj):
        """Recompute: reruns the layers, the paths and the poses only if their inputs changed.
        An error is reported in Status / PathsStatus and the Report view (by update_job) and
        raised as JobFailed, which puts the Job in FreeCAD's error state (the message in the
        tree's tooltip). A failure of api.run outside a recompute is raised here too
        (mark_failed), without running anything again."""
        failure, self.failure = getattr(self, "failure", None), None
        if failure:
            raise JobFailed(failure)
        progress = hooks.make_progress()
        try:
            stages.update_job(obj, progress=progress, prune=False)
        except CurvedSlicerError as error:
            raise JobFailed("%s: %s" % (type(error).__name__, error)) from None
        finally:
            hooks.close_progress(progress)


class JobFailed(Exception):
    """A Job's recompute failed (raised out of JobProxy.execute: FreeCAD's error state)."""


def mark_failed(job, error):
    """After api.run failed outside a recompute: puts the Job in FreeCAD's error state with the
    error's message, through a recompute of the Job whose execute raises it (nothing reruns)."""
    job.Proxy.failure = "%s: %s" % (type(error).__name__, error)
    job.touch()
    job.Document.recompute([job])
    job.Proxy.failure = None


def clear_failed(job):
    """After api.run succeeded: a Job still in the error state of an earlier failure is
    recomputed (its inputs are unchanged, so nothing reruns) to clear it."""
    if "Invalid" in job.State:
        job.touch()
        job.Document.recompute([job])


class _RecomputeObserver:
    """Removes the result features a recompute emptied (a smaller result: fewer layers, fewer
    paths) once the document's recompute is over, so no "unused" objects stay in the tree."""

    def slotRecomputedDocument(self, doc):
        for job in [o for o in doc.Objects if is_job(o)]:
            stages.prune_unused(job)


_observer = None


def install_observer():
    """Registers the recompute observer once per session (on the first Job made or loaded)."""
    global _observer
    if _observer is None:
        _observer = _RecomputeObserver()
        FreeCAD.addDocumentObserver(_observer)


def is_job(obj):
    proxy = getattr(obj, "Proxy", None)
    return proxy is not None and getattr(proxy, "Type", None) == JOB_TYPE
