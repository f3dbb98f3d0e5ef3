"""GUI test under xvfb-run (freecad script): the workbench activates, its commands exist, the
task panel opens and applies values, a run started from the GUI completes, a screenshot of the 3D
view shows the coloured layers (pixel statistics, compared with the same view without them), and
a non-solid selection gives a message box instead of an exception. Exits with os._exit."""

import os
import sys
import traceback

import FreeCAD
import FreeCADGui
from PySide import QtGui

MARKER = "CURVEDSLICER-TESTS-OK"
TMP = os.environ.get("CURVEDSLICER_TEST_TMP", "/tmp")
failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what)
    if not condition:
        failures.append(what)


def colored_pixels(path):
    """Pixels with a strong hue (max - min channel > 90): the height-coloured layers; the grey
    part, white background and black lines do not count."""
    image = QtGui.QImage(path)
    count = 0
    for y in range(0, image.height(), 2):
        for x in range(0, image.width(), 2):
            c = QtGui.QColor(image.pixel(x, y))
            r, g, b = c.red(), c.green(), c.blue()
            if max(r, g, b) - min(r, g, b) > 90:
                count += 1
    return count, (image.width() // 2) * (image.height() // 2)


def process_events():
    for _ in range(5):
        QtGui.QApplication.processEvents()
        FreeCADGui.updateGui()


def run():
    FreeCADGui.showMainWindow() if hasattr(FreeCADGui, "showMainWindow") else None
    FreeCADGui.activateWorkbench("CurvedSlicerWorkbench")
    check(FreeCADGui.activeWorkbench().name() == "CurvedSlicerWorkbench",
          "workbench activates")
    commands = FreeCADGui.listCommands()
    for name in ("CurvedSlicer_CreateJob", "CurvedSlicer_EditJob", "CurvedSlicer_RunJob",
                 "CurvedSlicer_LayerRange", "CurvedSlicer_Export", "CurvedSlicer_StepPose",
                 "CurvedSlicer_AnimatePoses", "CurvedSlicer_Preferences"):
        check(name in commands, "command %s exists" % name)

    from freecad.curvedslicer import api
    from freecad.curvedslicer.commands import job_commands
    from freecad.curvedslicer.taskpanels.task_job import TaskPanelJob

    doc = FreeCAD.newDocument("GuiTest")
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 30, 20, 12
    doc.recompute()

    # Bad input: a non-solid selection gives a message box, no exception, no Job.
    plane = doc.addObject("Part::Plane", "Plane")
    plane.Length = plane.Width = 10
    plane.Placement.Base = FreeCAD.Vector(0, 40, 0)
    doc.recompute()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, "Plane")
    FreeCADGui.runCommand("CurvedSlicer_CreateJob")
    process_events()
    boxes = [w for w in QtGui.QApplication.topLevelWidgets()
             if w.objectName() == "CurvedSlicerError" and w.isVisible()]
    check(len(boxes) == 1 and "not a solid" in boxes[0].text(), "non-solid selection: message")
    for w in boxes:
        w.close()
    check(not [o for o in doc.Objects if api.is_job(o)], "non-solid selection: no Job")
    doc.removeObject("Plane")

    # Create from the selection: the box with its bottom face picked.
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, "Box", "Face5")
    FreeCADGui.runCommand("CurvedSlicer_CreateJob")
    process_events()
    jobs = [o for o in doc.Objects if api.is_job(o)]
    check(len(jobs) == 1, "Create Job made one Job")
    job = jobs[0]
    check(job.StartMode == "Faces" and job.StartFaces[0][1] == ("Face5",), "start face picked")
    check(FreeCADGui.Control.activeDialog(), "task panel opened by Create Job")
    FreeCADGui.Control.closeDialog()
    FreeCADGui.ActiveDocument.resetEdit()
    process_events()

    # The task panel applies its values.
    panel = TaskPanelJob(job)
    FreeCADGui.Control.showDialog(panel)
    panel.layer_thickness.setValue(3.0)
    panel.voxel_size.setValue(0.5)
    panel.bead_spacing.setValue(4.2)
    estimate = panel.update_estimate()
    check(estimate is not None and estimate["fits"] and "cells" in panel.estimate_label.text(),
          "estimate shown: %s" % panel.estimate_label.text())
    check(panel.accept(), "task panel accepted")
    process_events()
    check(abs(float(job.LayerThickness) - 3.0) < 1e-9 and abs(float(job.VoxelSize) - 0.5) < 1e-9
          and abs(float(job.BeadSpacing) - 4.2) < 1e-9, "task panel applied the values")

    # Run from the GUI (progress dialog), then the screenshot.
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, job.Name)
    check(job_commands.run_selected_job(job), "run from the GUI completed")
    process_events()
    check(job.LayerCount == 3, "3 layers of 3 mm in a 12 mm box (got %d)" % job.LayerCount)

    check(job.PathCount > 0 and len(api.path_features(job)) == job.PlanLayerCount,
          "run from the GUI planned paths (%s)" % job.PathsStatus)
    path_views = [o.ViewObject for o in api.path_features(job)]
    check(all(v.Visibility and v.LineWidth == 2.0 for v in path_views), "paths drawn as lines")
    check(len({tuple(v.LineColor[:3]) for v in path_views}) == len(path_views),
          "paths coloured per layer")
    # The layer screenshot shows the layers alone (the positioner sits 1.1 m away).
    for o in job.PathsGroup.Group + job.PosesGroup.Group:
        o.ViewObject.Visibility = False
    view = FreeCADGui.ActiveDocument.ActiveView
    box.ViewObject.Visibility = False
    view.viewIsometric()
    view.fitAll()
    process_events()
    with_layers = os.path.join(TMP, "layers.png")
    view.saveImage(with_layers, 640, 480, "White")
    api.set_layer_range(job, 0, -1)
    process_events()
    without_layers = os.path.join(TMP, "no_layers.png")
    view.saveImage(without_layers, 640, 480, "White")
    shown, total = colored_pixels(with_layers)
    hidden, _ = colored_pixels(without_layers)
    print("coloured pixels: %d of %d with layers, %d without" % (shown, total, hidden))
    check(shown > 0.03 * total, "screenshot shows the coloured layers")
    check(hidden < 0.1 * shown + 10, "hiding the layers removes them from the view")

    # The layer range dialog.
    dialog = job_commands.LayerRangeDialog(job)
    dialog.first.setValue(2)
    dialog.last.setValue(3)
    check([o.Visibility for o in api.layers(job)] == [False, True, True],
          "layer range dialog shows layers 2-3")
    dialog.close()

    # Export from the GUI (the dialog's choice passed in) and the pose step command.
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, job.Name)
    check(job_commands.ExportProgram().IsActive(), "Export is enabled for a planned Job")
    program = os.path.join(TMP, "gui.JBI")
    result = job_commands.export_selected_job(job, path=program, format="jbi")
    check(result is not None and os.path.getsize(program) > 0, "export from the GUI wrote %s"
          % program)
    check(len(job_commands.export_filters()) == 7, "the export dialog offers every format")
    before = job.PosePoint
    FreeCADGui.runCommand("CurvedSlicer_StepPose")
    process_events()
    check(job.PosePoint > before, "step pose moves to a later point (%d -> %d)"
          % (before, job.PosePoint))
    check(job.PoseDeposition.getAngle(FreeCAD.Vector(0, 0, -1)) < 0.02,
          "the pose turns V along gravity")

    # A document made headless (no view provider proxies) gets them on opening in the GUI, with
    # the layers coloured by height.
    import subprocess

    path = os.path.join(TMP, "headless.FCStd")
    script = os.path.join(TMP, "make_headless.py")
    with open(script, "w") as f:
        f.write("import sys, FreeCAD\nfrom freecad.curvedslicer import api\n"
                "doc = FreeCAD.newDocument('Headless')\n"
                "box = doc.addObject('Part::Box', 'Box')\ndoc.recompute()\n"
                "job = api.make_job(doc, box, layer_thickness=3.0, voxel_size=1.0)\n"
                "api.run(job, progress=False)\ndoc.saveAs(%r)\nsys.exit(0)\n" % path)
    subprocess.run([os.environ.get("CURVEDSLICER_FREECADCMD", "freecadcmd"), script],
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=120)
    reopened = FreeCAD.openDocument(path)
    process_events()
    job2 = reopened.getObject("Job")
    check(job2.ViewObject.Proxy is not None, "headless Job gets its view provider in the GUI")
    colors = [tuple(round(c, 2) for c in o.ViewObject.ShapeColor[:3]) for o in api.layers(job2)]
    check(len(colors) == 3 and len(set(colors)) == 3, "reopened layers coloured by height: %s"
          % colors)
    check("Touched" not in job2.State, "reopened Job is not touched")


try:
    run()
except Exception:
    traceback.print_exc()
    failures.append("exception")
sys.stdout.flush()
if not failures:
    print(MARKER)
else:
    print("failures: %s" % failures)
sys.stdout.flush()
sys.stderr.flush()
os._exit(0 if not failures else 1)
