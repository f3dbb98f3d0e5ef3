"""Renders the turbine document (turbine_job.py) in the FreeCAD GUI: run under a display, e.g.

    CURVEDSLICER_DOCUMENT=out/example/turbine.FCStd QTWEBENGINE_DISABLE_SANDBOX=1 \
        xvfb-run -a -s "-screen 0 1280x1024x24" freecad resources/examples/turbine_render.py

Writes next to the document turbine.png (the part: blade layers coloured by height, base and
blade paths, travel dashed; the solids hidden) and turbine_pose.png (the positioner model
carrying the blades at the saved pose), then quits FreeCAD with exit code 0 (1 on failure).
"""

import os
import sys
import traceback

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui


def render():
    path = os.path.abspath(os.environ.get("CURVEDSLICER_DOCUMENT",
                                          os.path.join("out", "example", "turbine.FCStd")))
    folder = os.path.dirname(path)
    doc = FreeCAD.openDocument(path)
    QtGui.QApplication.processEvents()
    from freecad.curvedslicer import api
    from freecad.curvedslicer.viewproviders import view_job

    jobs = [o for o in doc.Objects if api.is_job(o)]
    pose_parts = set()
    for job in jobs:
        view_job.color_layers(job)
        view_job.style_paths(job)
        if job.PosesGroup is not None:
            pose_parts.update(o.Name for o in job.PosesGroup.Group)
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
    # 2: the positioner carrying the part at the saved pose.
    for obj in doc.Objects:
        if obj.ViewObject is not None:
            obj.ViewObject.Visibility = obj.Name in pose_parts
    view.viewIsometric()
    view.fitAll()
    QtGui.QApplication.processEvents()
    pose_png = os.path.join(folder, "turbine_pose.png")
    view.saveImage(pose_png, 1600, 1200, "White")
    for png in (part_png, pose_png):
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
