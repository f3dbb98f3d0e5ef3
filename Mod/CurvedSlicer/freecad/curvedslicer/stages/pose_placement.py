"""Where the part sits on the positioner table at a motion point: the one place that decides the
part's placement for the pose view (stages/poses.py), which shows the part on the table at the
pose. App side: no GUI imports.

The part frame in world at tilt a1, rotation a2 is T_table(a1, a2) · tableToPart. Today
tableToPart is the cell's ``positioner.table_to_part`` (what ``native.positioner_frames`` puts in
its "part" frame). The motion planner gains a placement rule (MotionPlan::tableToPart):
once ``native.plan_motion`` returns it as ``table_to_part`` (a 4x4 matrix, mm), it is used
instead — no other code changes.
"""

import FreeCAD


def _matrix(rows):
    return FreeCAD.Matrix(*[float(v) for row in rows for v in row])


def table_to_part(motion, frames):
    """The part frame in the table frame (FreeCAD.Matrix): the motion's placement rule when the
    motion carries one, else the cell's table_to_part (frames of native.positioner_frames)."""
    rule = motion.get("table_to_part") if hasattr(motion, "get") else None
    if rule is not None:
        return _matrix(rule)
    return _matrix(frames["table"]).inverse().multiply(_matrix(frames["part"]))


def part_placement(motion, frames):
    """The part's placement in world at the pose of `frames` (FreeCAD.Placement): the table's
    frame at that pose times table_to_part."""
    rule = motion.get("table_to_part") if hasattr(motion, "get") else None
    if rule is None:
        return FreeCAD.Placement(_matrix(frames["part"]))  # the cell's rule, as the core has it
    return FreeCAD.Placement(_matrix(frames["table"]).multiply(_matrix(rule)))
