"""GUI test under xvfb-run (freecad script): the part sits on the positioner table at the pose.
A 30 x 20 x 12 mm box, layered from a side face (so the table tilts), is run and
stepped to three motion points; at each, the part
shown (PosePart) is placed by the part placement (stages/pose_placement.py: the table's frame at
the pose times table_to_part): its lowest point lies on the table's top face and its footprint
inside the table disc. A cell whose table_to_part lifts the part by 20 mm shows it 20 mm above
the table. A hemispherical shell standing on its rim, placement Auto, goes on a riser and rests
on its top. Screenshots of the pose go to the test's folder under the build tree."""

import json
import os
import sys

import FreeCAD
import FreeCADGui
import Part

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))
from gui_testing import TMP, check, finish, process_events  # noqa: E402


def part_in_table_frame(job):
    """(lowest z, largest radius) of the shown part's vertices in the table's frame (mm)."""
    from freecad.curvedslicer.stages import poses

    objects = poses.pose_objects(job)
    table = objects["PositionerTable"]
    part = objects["PosePart"]
    # the link shows the solid's own shape (its vertices already in the part frame) carried by
    # the link's placement
    to_table = table.Placement.toMatrix().inverse().multiply(part.Placement.toMatrix())
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
    # Layers grow from the side face x = -15 along +x: the positioner tilts the part over. The
    # cell's placement (table_to_part as given), 150 mm above the table (as on a riser): the box
    # stays on its side, so the table tilts far over while the torch stays clear of it.
    cell = json.loads(native.default_cell_json())
    cell["positioner"]["table_to_part"]["xyz_mm"] = [0, 0, 150]
    lifted = os.path.join(TMP, "lifted_cell.json")
    with open(lifted, "w") as f:
        json.dump(cell, f)
    job = api.make_job(doc, box, start=(box, ["Face1"]), layer_thickness=5.0, voxel_size=1.0,
                       cell_file=lifted)
    job.PartPlacement = "Cell"
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
        check(abs(low - 150.0) < 1e-6, "point %d (a1 %.1f°, a2 %.1f°): the part's lowest point "
              "is 150 mm above the table top (%.6f mm)" % (index, job.PoseA1, job.PoseA2, low))
        check(reach <= radius, "point %d: the part's footprint (%.1f mm) is inside the table "
              "disc (%.1f mm)" % (index, reach, radius))
    check(min(tilts) > 45.0, "the poses tilt the table (|a1| %s°)" % [round(t, 1) for t in tilts])
    show_pose(job, "pose_lifted")

    # The default cell, placement Auto: a hemispherical shell (radii 30 and 40 mm) grown from its
    # inner hemisphere, its rim on the table. The first layers grow outwards along the table, so
    # on the bare table the torch would reach the table while they are welded; the part goes on
    # the lowest riser that clears, and the rest on it is derived from the beads, to within the
    # paths' accuracy (test_motion_options).
    shell = doc.addObject("Part::Feature", "Shell")
    half = Part.makeBox(100, 100, 50, FreeCAD.Vector(-50, -50, 0))
    shell.Shape = Part.makeSphere(40).cut(Part.makeSphere(30)).common(half)
    inner = [i for i, f in enumerate(shell.Shape.Faces, 1)
             if f.Surface.__class__.__name__ == "Sphere" and abs(f.Surface.Radius - 30) < 1e-6]
    check(len(inner) == 1, "the shell has one inner spherical face (%s)" % inner)
    doc.recompute()
    job = api.make_job(doc, shell, start=(shell, ["Face%d" % inner[0]]), layer_thickness=1.5,
                       voxel_size=1.0, bead_spacing=3.7)
    job.PartPlacement = "Auto"
    api.run(job)
    riser = api.motion(job)["fixture"]["riser_height_mm"]
    check(riser > 0.0, "placement Auto stands the part on a riser (%.1f mm)" % riser)
    api.set_pose(job, api.pose_count(job) // 2)
    process_events()
    low, _ = part_in_table_frame(job)
    check(abs(low - riser) < 0.5, "the part's lowest point is on the riser's top (%.3f mm, "
          "riser %.3f mm)" % (low, riser))
    show_pose(job, "pose_on_riser")
    FreeCAD.closeDocument(doc.Name)


finish(run)
