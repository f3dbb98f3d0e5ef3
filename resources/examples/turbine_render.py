"""Renders the turbine document (turbine_job.py) in the FreeCAD GUI: run under a display, e.g.

    CURVEDSLICER_DOCUMENT=out/example/turbine.FCStd QTWEBENGINE_DISABLE_SANDBOX=1 \
        xvfb-run -a -s "-screen 0 1280x1024x24" freecad resources/examples/turbine_render.py

Writes next to the document turbine.png (the part: blade layers coloured by height, base and
blade paths, travel dashed; the solids hidden), turbine_pose.png (the positioner carrying the
blades, seen through, at the saved pose: the torch at the motion point, the deposit up to it)
and turbine_cell.png (the same with the robot), then quits FreeCAD with exit code 0 (1 on
failure).
"""

import os
import sys
import traceback

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui


def check_pose(job, cell):
    """The saved pose shows the torch tip on the motion point, carried by the part on the table
    (raises AssertionError otherwise)."""
    from freecad.curvedslicer import api

    motion = api.motion(job)
    index = job.PosePoint
    point = FreeCAD.Vector(*motion["position"][index].tolist())
    on_part = cell["PosePart"].Placement.multVec(point)
    gap = (cell["Torch"].Placement.Base - on_part).Length
    assert gap < 1e-6, "the torch tip is %.3g mm from the motion point" % gap
    print("turbine_render: pose at motion point %d (layer %d, path %d, %d welded moves "
          "deposited), the torch tip on the part's point (%.1e mm)"
          % (index, job.PoseLayer, job.PosePath, cell["Deposit"].DepositMoves, gap))


def render():
    path = os.path.abspath(os.environ.get("CURVEDSLICER_DOCUMENT",
                                          os.path.join("out", "example", "turbine.FCStd")))
    folder = os.path.dirname(path)
    doc = FreeCAD.openDocument(path)
    QtGui.QApplication.processEvents()
    from freecad.curvedslicer import api
    from freecad.curvedslicer.stages import poses
    from freecad.curvedslicer.viewproviders import view_job

    jobs = [o for o in doc.Objects if api.is_job(o)]
    pose_parts = set()
    for job in jobs:
        view_job.color_layers(job)
        view_job.style_paths(job)
        if job.PosesGroup is not None:
            pose_parts.update(o.Name for o in job.PosesGroup.Group)
    # The pose shown is the blades' (curved layers; the base's positioner would sit on it).
    posed = next((j for j in jobs if j.PlanKind == "CurvedLayers"), jobs[-1])
    cell = poses.pose_objects(posed)
    check_pose(posed, cell)
    view = FreeCADGui.getDocument(doc.Name).activeView()
    # 1: the part with layers and paths.
    for obj in doc.Objects:
        vobj = obj.ViewObject
        if vobj is None:
            continue
        if obj.Name in pose_parts or obj.Name in ("Base", "Blades", "BaseOuterSurface"):
            vobj.Visibility = False
        elif "LayerIndex" in obj.PropertiesList:  # layer meshes and path layers
            vobj.Visibility = obj.LayerIndex > 0
        elif "TravelMoves" in obj.PropertiesList:
            vobj.Visibility = True
    view.viewIsometric()
    view.fitAll()
    QtGui.QApplication.processEvents()
    part_png = os.path.join(folder, "turbine.png")
    view.saveImage(part_png, 1600, 1200, "White")
    # 2: the positioner carrying the part (seen through) at the saved pose, the torch at the
    # motion point and the deposit up to it; then the whole cell with the robot.
    shown = {o.Name for role, o in cell.items() if role != "Robot"}
    for obj in doc.Objects:
        if obj.ViewObject is not None:
            obj.ViewObject.Visibility = obj.Name in shown
    view_job.see_through(cell["PosePart"])
    view.viewIsometric()
    view.fitAll()
    QtGui.QApplication.processEvents()
    pose_png = os.path.join(folder, "turbine_pose.png")
    view.saveImage(pose_png, 1600, 1200, "White")
    cell["Robot"].ViewObject.Visibility = True
    view.fitAll()
    QtGui.QApplication.processEvents()
    cell_png = os.path.join(folder, "turbine_cell.png")
    view.saveImage(cell_png, 1600, 1200, "White")
    for png in (part_png, pose_png, cell_png):
        print("turbine_render: wrote %s (%d bytes)" % (png, os.path.getsize(png)))
    return 0


def run():
    try:
        code = render()
    except Exception:
        traceback.print_exc()
        code = 1
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


QtCore.QTimer.singleShot(500, run)
