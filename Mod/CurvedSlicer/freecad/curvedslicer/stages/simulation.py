"""Pose simulation of a Job: at motion point ``PosePoint`` the Poses group
shows, besides the positioner carrying the part (stages/poses.py),

- the torch: the cell's torch envelope (a truncated cone on the tool z axis, the wire stick-out
  below it) placed at the point's TCP pose in world (``tool_in_world`` of native.plan_motion),
  so its tip is the motion point's TCP;
- the robot: a stick model of the cell's arm from forward kinematics of the point's joints
  (native.robot_arm_points: base, shoulder, elbow, wrist centre, flange, then the TCP);
- the deposit: the welded moves up to the point (arc-on moves of native.plan_motion's points in
  execution order), in the part frame and carried by the part's placement, so it grows on the
  part as the point advances. ``DepositMoves`` counts them.

Shapes are illustrations, not collision models. App side: no GUI imports (the view provider
colours them).
"""

import json

import FreeCAD

from ..core import native

SIMULATION_PARTS = ["Torch", "Robot", "Deposit"]

#: Properties of the simulation features (besides PoseRole): name, type, tooltip.
_PROPERTIES = {
    "Deposit": [("App::PropertyInteger", "DepositMoves",
                 "Welded moves deposited up to the shown motion point")],
    "Torch": [("App::PropertyString", "ShapeDigest", "Torch envelope the shape was built for")],
    "Robot": [],
}


def _matrix(rows):
    return FreeCAD.Matrix(*[float(v) for row in rows for v in row])


def torch_envelope(cell):
    """(stickout, radius, top radius, length) in mm of the cell's torch (the core's defaults for
    a cell without an envelope, robot/cell.hpp TorchEnvelope)."""
    envelope = json.loads(cell).get("tool", {}).get("envelope", {})
    return (float(envelope.get("stickout_mm", 15.0)), float(envelope.get("radius_mm", 12.5)),
            float(envelope.get("top_radius_mm", 25.0)), float(envelope.get("length_mm", 385.0)))


def torch_shape(cell):
    """The torch in the tool frame: TCP at the origin, the torch body up -z (mm)."""
    import Part

    stickout, radius, top_radius, length = torch_envelope(cell)
    down = FreeCAD.Vector(0, 0, -1)
    body = Part.makeCone(radius, top_radius, length, FreeCAD.Vector(0, 0, -stickout), down)
    parts = [body]
    if stickout > 0:
        parts.append(Part.makeCylinder(min(0.6, radius), stickout, FreeCAD.Vector(), down))
    return Part.makeCompound(parts)


def tool_placement(motion, index):
    """The TCP pose in world at motion point `index` (FreeCAD.Placement)."""
    return FreeCAD.Placement(_matrix(motion["tool_in_world"][index]))


def robot_shape(cell, joints):
    """The arm as cylinders between its joint points and spheres at the joints (world, mm)."""
    import Part

    arm = native.robot_arm_points(cell, [float(j) for j in joints])
    names = ["base", "shoulder", "elbow", "wrist", "flange"]
    points = [FreeCAD.Vector(*arm[n]) for n in names]
    radii = [70.0, 55.0, 40.0, 25.0]  # mm, links base-shoulder, upper arm, forearm, wrist
    shapes = [Part.makeCylinder(160.0, 120.0, points[0], FreeCAD.Vector(0, 0, 1))]
    for (a, b, r) in zip(points[:4], points[1:5], radii):
        if (b - a).Length > 1e-6:
            shapes.append(Part.makeCylinder(r, (b - a).Length, a, b - a))
        shapes.append(Part.makeSphere(r * 1.15, b))  # the joint at the link's end
    return Part.makeCompound(shapes)


def deposit_moves(motion, index):
    """Welded moves of the motion up to and including point `index`."""
    return int(motion["arc_on"][:index + 1].sum())


def _path_wire(motion, begin, end):
    """Polyline of points begin..end-1 (part frame), or None when shorter than one move."""
    import Part

    if end - begin < 2:
        return None
    points = [FreeCAD.Vector(*p) for p in motion["position"][begin:end].tolist()]
    return Part.makePolygon(points)


def deposit_shape(motion, index):
    """The beads welded up to point `index` in the part frame: one polyline per path, the
    current path up to the point. Whole paths are built once per motion (cached in it)."""
    import Part

    cache = motion.setdefault("_deposit_wires", {})
    wires = []
    for span in motion["paths"]:
        begin, end = int(span["begin"]), int(span["end"])
        if begin > index:
            break
        if end <= index + 1:
            if (begin, end) not in cache:
                cache[(begin, end)] = _path_wire(motion, begin, end)
            wire = cache[(begin, end)]
        else:
            wire = _path_wire(motion, begin, index + 1)
        if wire is not None:
            wires.append(wire)
    return Part.makeCompound(wires) if wires else Part.Shape()


def _feature(job, group, objects, role):
    obj = objects.get(role)
    if obj is None:
        obj = job.Document.addObject("Part::Feature", role)
        obj.addProperty("App::PropertyString", "PoseRole", "Pose", "Part of the simulation")
        obj.PoseRole = role
        obj.setEditorMode("PoseRole", 2)
        for (ptype, name, tooltip) in _PROPERTIES[role]:
            obj.addProperty(ptype, name, "Pose", tooltip)
            obj.setEditorMode(name, 1 if name == "DepositMoves" else 2)
        group.addObject(obj)
    return obj


def update_simulation(job, group, objects, motion, index, part_placement):
    """Places the torch, the robot and the deposit of motion point `index`; `objects` are the
    Poses group's {role: object} (stages/poses.pose_objects), `part_placement` the part's
    placement in world at the point."""
    cell = motion["cell_json"]
    torch = _feature(job, group, objects, "Torch")
    digest = repr(torch_envelope(cell))
    if torch.ShapeDigest != digest:
        torch.Shape = torch_shape(cell)
        torch.ShapeDigest = digest
    torch.Placement = tool_placement(motion, index)
    robot = _feature(job, group, objects, "Robot")
    robot.Shape = robot_shape(cell, motion["joints"][index])
    deposit = _feature(job, group, objects, "Deposit")
    deposit.Shape = deposit_shape(motion, index)
    deposit.Placement = part_placement
    deposit.DepositMoves = deposit_moves(motion, index)


#: MotionFlag bits (robot/motion.hpp) by name, for display.
MOTION_FLAGS = ["singular", "tilt limited", "rotation limited", "a2 rate limited", "smoothed",
                "configuration change", "wrist singular", "robot limit", "speed reduced",
                "inserted", "near singular", "collision", "torch tilted", "gravity deviated"]
#: IK branch bits of MotionPoint::configuration.
CONFIGURATION_BITS = [(1, "back", "front"), (2, "elbow down", "elbow up"),
                      (4, "wrist flip", "no flip")]


def point_info(motion, index):
    """Motion point `index` (clamped) for display: see api.pose_info."""
    import math

    count = len(motion["a1"])
    index = min(max(int(index), 0), max(count - 1, 0))
    flags = int(motion["flags"][index])
    configuration = int(motion["configuration"][index])
    tcp = tool_placement(motion, index).Base
    return {
        "index": index, "count": count,
        "kind": motion["kind_names"][int(motion["kind"][index])],
        "layer": int(motion["layer"][index]) + 1, "path": int(motion["path"][index]) + 1,
        "a1": math.degrees(float(motion["a1"][index])),
        "a2": math.degrees(float(motion["a2"][index])),
        "joints": [math.degrees(float(j)) for j in motion["joints"][index]],
        "configuration": [on if configuration & bit else off
                          for (bit, on, off) in CONFIGURATION_BITS],
        "flags": [name for bit, name in enumerate(MOTION_FLAGS) if flags & (1 << bit)],
        "tcp": (tcp.x, tcp.y, tcp.z),
        "time": float(motion["time"][index]), "speed": float(motion["speed"][index]),
        "arc_on": bool(motion["arc_on"][index]),
        "deposit_moves": deposit_moves(motion, index),
    }
