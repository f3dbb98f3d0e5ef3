"""Positioner poses of a Job (paper §3.2, eq. 16): a schematic two-axis positioner — base,
tilting cradle, rotary table — built from the cell (robot/cell.hpp), carrying the part (an
App::Link to the Job's solid), placed at the planned angles (robot/motion.hpp planMotion: a1 tilt,
a2 rotation) of the motion point ``PosePoint``, with the torch, the robot and the deposit up to
that point (stages/simulation.py).

Shapes are built once in the table-zero frame T0 (x axis the tilt axis, z axis the rotation
axis, origin on the table) and carried by placements: base T0, cradle T_cradle(a1) = T_table(a1,
0), table T_table(a1, a2), part T_part(a1, a2). Sizes follow the part's extent
(table radius at least 1.2 × the part's radius); they illustrate the motion and are not a
collision model. The part sits on the table where the motion placed it (the Job's
``PartPlacement``: the motion's ``table_to_part``). The motion is planned with the Job's Robot
options (``motion_options``: Clearance, AllowCollisions, AddHome, MergeTolerance, MaxA2Step,
PartPlacement, ToolAlongTravel) and unreachable robot points kept (warnings and notes go to
``MotionWarnings``), cached per plan, cell and options for stepping. App side: no GUI imports
(the view provider colours the parts).
"""

import hashlib
import math

import FreeCAD

from .. import defaults
from ..core import InvalidInput, native
from ..messages import for_workbench
from . import deviations
from .features import ensure_group, group_members
from .pose_placement import part_placement
from .simulation import update_simulation

POSE_PARTS = ["PositionerBase", "PositionerCradle", "PositionerTable", "PosePart"]

#: PartPlacement property values, the core's default first; name -> MotionOptions.placement.
_PLACEMENT_NAMES = {"Rest": "rest", "Cell": "cell", "Auto": "auto"}
PART_PLACEMENTS = sorted(_PLACEMENT_NAMES, key=lambda n: _PLACEMENT_NAMES[n]
                         != defaults.PART_PLACEMENT)

_motion_cache = {}  # (document name, job name) -> (digest, motion dict)


def cell_json(job):
    """The Job's cell as canonical JSON: CellFile, or the paper's cell when CellFile is empty."""
    path = job.CellFile
    if not path:
        return native.default_cell_json()
    return native.read_cell_json(path)


def _digest(*parts):
    h = hashlib.sha256()
    for p in parts:
        h.update(p.encode("utf-8") if isinstance(p, str) else repr(p).encode("utf-8"))
        h.update(b"\0")
    return h.hexdigest()


def _quantity(job, name, unit, default):
    """A Length / Angle property in `unit` (the default for a Job without it)."""
    if name not in job.PropertiesList:
        return float(default)
    return float(FreeCAD.Units.Quantity(getattr(job, name)).getValueAs(unit))


def motion_options(job, **overrides):
    """native.MotionOptions from the Job's Robot properties (a Job saved before one existed
    uses the core's default), then `overrides` (e.g. unreachable="warn")."""
    def prop(name, default):
        return getattr(job, name) if name in job.PropertiesList else default

    placement = prop("PartPlacement", PART_PLACEMENTS[0])
    values = dict(
        tool_along_travel=bool(prop("ToolAlongTravel", False)),
        clearance=_quantity(job, "Clearance", "mm", defaults.CLEARANCE),
        allow_collisions=bool(prop("AllowCollisions", defaults.ALLOW_COLLISIONS)),
        add_home=bool(prop("AddHome", defaults.ADD_HOME)),
        merge_tolerance=_quantity(job, "MergeTolerance", "mm", defaults.MERGE_TOLERANCE),
        max_a2_step=math.radians(_quantity(job, "MaxA2Step", "deg", defaults.MAX_A2_STEP)),
        placement=_PLACEMENT_NAMES[placement],
    )
    values.update(overrides)
    return native.MotionOptions(**values)


def motion_digest(job, cell=None, options=None):
    """Digest of what the Job's motion is planned from: its plan, its cell (CellFile), its robot
    options."""
    cell = cell_json(job) if cell is None else cell
    options = motion_options(job, unreachable="warn") if options is None else options
    return _digest(job.PlanJson, cell, repr(options))


def motion(job, progress=None):
    """planMotion of the Job's plan in its cell (cached): dict of columns (see plan_motion)."""
    if not job.PlanJson:
        raise InvalidInput("no plan: %s has no paths yet; run the Job first" % job.Label)
    cell = cell_json(job)
    options = motion_options(job, unreachable="warn")
    digest = motion_digest(job, cell, options)
    key = (job.Document.Name, job.Name)
    cached = _motion_cache.get(key)
    if cached is not None and cached[0] == digest:
        return cached[1]
    result = native.plan_motion(job.PlanJson, cell, options=options, progress=progress)
    result["cell_json"] = cell
    _motion_cache[key] = (digest, result)
    return result


def placement(matrix):
    m = FreeCAD.Matrix(*[float(v) for row in matrix for v in row])
    return FreeCAD.Placement(m)


def _matrix(matrix):
    return FreeCAD.Matrix(*[float(v) for row in matrix for v in row])


def _box(x0, x1, y0, y1, z0, z1):
    import Part

    return Part.makeBox(x1 - x0, y1 - y0, z1 - z0, FreeCAD.Vector(x0, y0, z0))


def fixture_shape(fixture):
    """The riser (a cylinder on the table top) and the substrate plate (a square box on it) of a
    motion's ``fixture`` dict, in the table frame (mm); None without either."""
    import Part

    shape = None
    height = float(fixture.get("riser_height_mm", 0.0))
    thickness = float(fixture.get("substrate_thickness_mm", 0.0))
    if height > 0.0:
        shape = Part.makeCylinder(0.5 * float(fixture["riser_diameter_mm"]), height)
    if thickness > 0.0:
        half = 0.5 * float(fixture["substrate_size_mm"])
        plate = _box(-half, half, -half, half, height, height + thickness)
        shape = plate if shape is None else shape.fuse(plate)
    return shape


def positioner_shapes(cell, part_radius, fixture=None):
    """Base, cradle and table shapes in the table-zero frame (mm): placed by T0 (base), the
    cradle frame T_cradle(a1) and the table frame T_table(a1, a2). The table carries the
    fixture (riser and substrate plate) of the motion's ``fixture`` dict, if any."""
    import Part

    frames = native.positioner_frames(cell, 0.0, 0.0)
    t0 = _matrix(frames["table_zero"])
    inverse = t0.inverse()
    # Tilt axis and floor in the table-zero frame.
    import json

    description = json.loads(cell)["positioner"]
    base = _matrix(frames["base"])
    tilt_point = base.multiply(FreeCAD.Vector(*description["tilt_axis"]["point_mm"]))
    tz = inverse.multiply(tilt_point).z
    floor = inverse.multiply(base.multiply(FreeCAD.Vector(0, 0, 0))).z
    r = max(150.0, 1.2 * part_radius)
    w = r + 70.0  # half width of the cradle plate
    table = Part.makeCylinder(r, 30.0, FreeCAD.Vector(0, 0, -30.0))
    on_table = fixture_shape(fixture or {})
    if on_table is not None:
        table = table.fuse(on_table)
    cradle = _box(-w, w, -0.8 * r, 0.8 * r, -70.0, -30.0)
    for sign in (1, -1):
        x0, x1 = sorted((sign * w, sign * (w + 40.0)))
        cradle = cradle.fuse(_box(x0, x1, -60.0, 60.0, min(tz - 60.0, -70.0), -30.0))
    base_shape = _box(-(w + 110.0), w + 110.0, -0.9 * r, 0.9 * r, floor, floor + 60.0)
    for sign in (1, -1):
        x0, x1 = sorted((sign * (w + 50.0), sign * (w + 110.0)))
        base_shape = base_shape.fuse(_box(x0, x1, -80.0, 80.0, floor, tz + 60.0))
    return base_shape, cradle, table


def ensure_poses_group(job):
    return ensure_group(job, "PosesGroup", "Poses", "poses")


def pose_objects(job):
    """{role: object} of the Poses group (roles POSE_PARTS)."""
    found = {}
    for o in group_members(job.PosesGroup):
        if "PoseRole" in o.PropertiesList:
            found[o.PoseRole] = o
    return found


def _part_radius(job):
    solid = job.Solid
    shape = getattr(solid, "Shape", None) if solid is not None else None
    if shape is None or shape.isNull():
        mesh = getattr(solid, "Mesh", None)
        box = mesh.BoundBox if mesh is not None else None
    else:
        box = shape.BoundBox
    if box is None or not box.isValid():
        return 100.0
    return max(math.hypot(x, y) for x in (box.XMin, box.XMax) for y in (box.YMin, box.YMax))


def update_poses(job, progress=None):
    """Places the positioner model at the angles of motion point job.PosePoint (clamped).
    Returns the motion dict, or None when the Job has no plan."""
    if not job.PlanJson:
        return None
    m = motion(job, progress)
    count = len(m["a1"])
    index = min(max(int(job.PosePoint), 0), max(count - 1, 0))
    if index != job.PosePoint:
        job.PosePoint = index
    a1, a2 = float(m["a1"][index]), float(m["a2"][index])
    cell = m["cell_json"]
    frames = native.positioner_frames(cell, a1, a2)
    doc = job.Document
    group = ensure_poses_group(job)
    objects = pose_objects(job)
    fixture = dict(m.get("fixture", {}))
    shape_digest = _digest("shapes v3", cell, round(_part_radius(job), 3),
                           sorted((k, round(float(v), 6)) for k, v in fixture.items()))
    needs_shapes = any(role not in objects for role in POSE_PARTS[:3]) or \
        objects["PositionerBase"].ShapeDigest != shape_digest
    if needs_shapes:
        shapes = positioner_shapes(cell, _part_radius(job), fixture)
    for role, shape_index in (("PositionerBase", 0), ("PositionerCradle", 1),
                              ("PositionerTable", 2)):
        obj = objects.get(role)
        if obj is None:
            obj = doc.addObject("Part::Feature", role)
            obj.addProperty("App::PropertyString", "PoseRole", "Pose", "Part of the positioner")
            obj.addProperty("App::PropertyString", "ShapeDigest", "Pose",
                            "Cell and part size the shape was built for")
            obj.PoseRole = role
            for name in ("PoseRole", "ShapeDigest"):
                obj.setEditorMode(name, 2)
            group.addObject(obj)
        if needs_shapes:
            obj.Shape = shapes[shape_index]
            obj.ShapeDigest = shape_digest
    objects = pose_objects(job)
    part = objects.get("PosePart")
    if part is None and job.Solid is not None:
        part = doc.addObject("App::Link", "PosePart")
        part.addProperty("App::PropertyString", "PoseRole", "Pose", "Part of the positioner")
        part.PoseRole = "PosePart"
        part.setEditorMode("PoseRole", 2)
        group.addObject(part)
    if part is not None:
        if part.LinkedObject != job.Solid:
            part.LinkedObject = job.Solid
        part.LinkTransform = True
        part.Placement = part_placement(m, frames)
    # Shapes are in the table-zero frame; their placements are the frames that carry them.
    objects["PositionerBase"].Placement = placement(frames["table_zero"])
    objects["PositionerCradle"].Placement = placement(frames["cradle"])
    objects["PositionerTable"].Placement = placement(frames["table"])
    update_simulation(job, group, pose_objects(job), m, index, part_placement(m, frames))
    for o in pose_objects(job).values():
        o.Label = "%s %s" % (job.Label, o.PoseRole)
        o.purgeTouched()
    group.purgeTouched()
    v = m["deposition"][index]
    world_v = part_placement(m, frames).Rotation.multVec(FreeCAD.Vector(*v.tolist()))
    job.PoseCount = count
    job.PoseA1 = math.degrees(a1)
    job.PoseA2 = math.degrees(a2)
    job.PoseResidual = math.degrees(float(m["residual"][index]))
    job.PoseTorchAngle = math.degrees(float(m["torch_angle"][index]))
    job.MaxTorchAngle = math.degrees(float(m["total"]["max_torch_angle"]))
    job.MaxGravityDeviation = math.degrees(float(m["total"]["max_gravity_deviation"]))
    job.CollisionCount = len(m["collisions"])
    job.PoseLayer = int(m["layer"][index]) + 1
    job.PosePath = int(m["path"][index]) + 1
    job.PoseDeposition = world_v
    job.MotionWarnings = [for_workbench(w) for w in m["warnings"]] + \
        ["note: " + for_workbench(n) for n in m["notes"]]
    deviations.draw_deviations(job, m)
    digest = motion_digest(job)
    if job.MotionDigest != digest:
        job.MotionDigest = digest
    return m
