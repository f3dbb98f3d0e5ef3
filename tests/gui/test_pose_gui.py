"""GUI test under xvfb-run (freecad script): the part sits on the positioner table at the pose.
A 30 x 20 x 12 mm box, layered from a side face (so the table tilts), is run and
stepped to three motion points; at each, the part
shown (PosePart) is placed by the part placement (stages/pose_placement.py: the table's frame at
the pose times table_to_part): its lowest point lies on the table's top face and its footprint
inside the table disc. A cell whose table_to_part lifts the part by 20 mm shows it 20 mm above
the table. Screenshots of the pose go to the test's folder under the build tree."""

import json
import os
import sys

import FreeCAD
import FreeCADGui

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))
from gui_testing import TMP, check, finish, process_events  # noqa: E402


def part_in_table_frame(job):
    """(lowest z, largest radius) of the shown part's vertices in the table's frame (mm)."""
    from freecad.curvedslicer.stages import poses

    objects = poses.pose_objects(job)
    table = objects["PositionerTable"]
    part = objects["PosePart"]
    to_table = table.Placement.toMatrix().inverse().multiply(part.Placement.toMatrix()).multiply(
        job.Solid.Placement.toMatrix())
    points = [to_table.multiply(v.Point) for v in job.Solid.Shape.Vertexes]
    return min(p.z for p in points), max((p.x ** 2 + p.y ** 2) ** 0.5 for p in points)


def table_radius(job):
    from freecad.curvedslicer.stages import poses

    shape = poses.pose_objects(job)["PositionerTable"].Shape.copy()
    shape.Placement = FreeCAD.Placement()  # the disc in its own (table) frame
    return shape.BoundBox.XMax


def show_pose(job, name):
    """Only the positioner and the part, fitted; a screenshot of the 3D view."""
    doc = job.Document
    for o in doc.Objects:
        if o.ViewObject is not None:
            o.ViewObject.Visibility = False
    for o in job.PosesGroup.Group:
        o.ViewObject.Visibility = True
    from freecad.curvedslicer.stages import poses

    # Looking at the table's top face, slightly from the side.
    table = poses.pose_objects(job)["PositionerTable"]
    normal = table.Placement.Rotation.multVec(FreeCAD.Vector(0, 0, 1))
    side = table.Placement.Rotation.multVec(FreeCAD.Vector(1, 1, 0))
    view = FreeCADGui.ActiveDocument.ActiveView
    view.setViewDirection(tuple(-normal - 0.6 * side))
    view.fitAll()
    process_events(0.2)
    path = os.path.join(TMP, name + ".png")
    view.saveImage(path, 800, 600, "White")
    print("screenshot: %s" % path, flush=True)


def run():
    FreeCADGui.showMainWindow() if hasattr(FreeCADGui, "showMainWindow") else None
    FreeCADGui.activateWorkbench("CurvedSlicerWorkbench")
    from freecad.curvedslicer import api
    from freecad.curvedslicer.core import native

    doc = FreeCAD.newDocument("PoseTest")
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 30, 20, 12
    box.Placement.Base = FreeCAD.Vector(-15, -10, 0)  # centred on the table axis
    doc.recompute()
    # Layers grow from the side face x = -15 along +x: the positioner tilts the part over.
    job = api.make_job(doc, box, start=(box, ["Face1"]), layer_thickness=5.0, voxel_size=1.0)
    # The cell's placement (table_to_part as given): the box's bottom face exactly on the table.
    # (The default Rest derives it from the beads, to within the paths' accuracy: test_motion_options.)
    job.PartPlacement = "Cell"
    # The box lies on its side with layers growing sideways: the torch really reaches the table
    # while the first layers are welded (the collision check); this test is about the display.
    job.AllowCollisions = True
    api.run(job)
    process_events()
    count = api.pose_count(job)
    check(count > 10, "the plan has motion points (%d)" % count)
    radius = table_radius(job)
    kinds = api.motion(job)["kind"]
    welds = [i for i in range(count) if int(kinds[i]) == 0]  # not the home poses at both ends
    tilts = []
    for index in (welds[0], welds[len(welds) // 2], welds[-1]):
        api.set_pose(job, index)
        process_events()
        tilts.append(abs(job.PoseA1))
        low, reach = part_in_table_frame(job)
        check(abs(low) < 1e-6, "point %d (a1 %.1f°, a2 %.1f°): the part's lowest point is on "
              "the table top (%.2e mm)" % (index, job.PoseA1, job.PoseA2, low))
        check(reach <= radius, "point %d: the part's footprint (%.1f mm) is inside the table "
              "disc (%.1f mm)" % (index, reach, radius))
    check(min(tilts) > 45.0, "the poses tilt the table (|a1| %s°)" % [round(t, 1) for t in tilts])
    show_pose(job, "pose_on_table")

    cell = json.loads(native.default_cell_json())
    cell["positioner"]["table_to_part"]["xyz_mm"] = [0, 0, 20]
    lifted = os.path.join(TMP, "lifted_cell.json")
    with open(lifted, "w") as f:
        json.dump(cell, f)
    job.CellFile = lifted
    api.run(job)
    api.set_pose(job, count // 2)
    process_events()
    low, _ = part_in_table_frame(job)
    check(abs(low - 20.0) < 1e-6, "a cell's table_to_part 20 mm up shows the part 20 mm above "
          "the table (%.6f mm)" % low)
    show_pose(job, "pose_lifted")
    FreeCAD.closeDocument(doc.Name)


finish(run)
