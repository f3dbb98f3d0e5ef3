"""GUI test under xvfb-run (freecad script): undo and redo of a Job's run and of a recompute print
no traceback. A Job is made and run from the GUI (one transaction each), the run is undone (no
layers, no paths) and redone (layers and styled paths back); a path parameter is changed and the
document recomputed (Std_Refresh, in a transaction), the recompute undone (the run's paths back)
and redone, then twice undone and redone. After each step the events
are processed (the view provider restyles from the event loop) and the Report view and the
log must hold no "Traceback" and no Python error. Exits with os._exit."""

import ctypes
import os
import re
import sys
import traceback

import FreeCAD
import FreeCADGui
from PySide import QtGui

MARKER = "CURVEDSLICER-TESTS-OK"
failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        failures.append(what)


def process_events():
    for _ in range(5):
        QtGui.QApplication.processEvents()
        FreeCADGui.updateGui()


def report_view():
    """FreeCAD's Report view (a QTextEdit), where errors of callbacks (view providers, proxies)
    are printed in the GUI."""
    window = FreeCADGui.getMainWindow()
    for widget in window.findChildren(QtGui.QTextEdit):
        if widget.objectName() == "Report view":
            return widget
    return None


OWN_LINES = re.compile(r"^(\S+\s+)?(ok   |FAIL |step: |undo stack: )")


def problems(text):
    """Lines of `text` that show a traceback or a Python exception (this test's own lines, which
    the Report view shows too, excepted)."""
    markers = ("Traceback", "Error: ", "Exception")
    return [line for line in text.splitlines()
            if any(m in line for m in markers) and not OWN_LINES.match(line)]


def activate_view(doc):
    """Makes the document's 3D view the main window's active view, as the user's click on it
    would: under Xvfb without a window manager, FreeCAD 1.1 leaves its Start page active, and
    Std_Undo/Std_Redo (which ask the active view) stay disabled."""
    mdi = FreeCADGui.getMainWindow().findChild(QtGui.QMdiArea)
    for window in mdi.subWindowList() if mdi is not None else []:
        if window.windowTitle().startswith(doc.Label + " :"):
            mdi.setActiveSubWindow(window)
    process_events()


def step(what, action, report):
    """Runs `action`, processes events, and checks the Report view gained no error lines."""
    before = report.toPlainText() if report is not None else ""
    print("step: " + what, flush=True)
    action()
    process_events()
    after = report.toPlainText() if report is not None else ""
    new = problems(after[len(before):] if after.startswith(before) else after)
    check(not new, "%s: no traceback in the Report view %s" % (what, new[:6]))


def run():
    FreeCADGui.showMainWindow() if hasattr(FreeCADGui, "showMainWindow") else None
    FreeCADGui.activateWorkbench("CurvedSlicerWorkbench")
    report = report_view()
    check(report is not None, "the Report view exists")
    # Errors must reach the Report view for this test to see them.
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/OutputWindow").SetBool("checkError",
                                                                                True)

    from freecad.curvedslicer import api
    from freecad.curvedslicer.commands import job_commands

    doc = FreeCAD.newDocument("UndoTest")
    doc.UndoMode = 1
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 30, 20, 12
    doc.recompute()
    doc.openTransaction("Create Job")
    job = api.make_job(doc, box, start=(box, ["Face5"]), layer_thickness=3.0, voxel_size=1.0)
    doc.commitTransaction()
    process_events()
    activate_view(doc)
    check(FreeCADGui.Command.get("Std_Undo").isActive(), "Std_Undo is active")

    def run_job():
        check(job_commands.run_selected_job(job), "run from the GUI completed")

    def planned(what):
        views = [o.ViewObject for o in api.path_features(job)]
        check(job.LayerCount == 3 and len(api.layers(job)) == 3 and job.PathCount > 0
              and len(views) == job.PlanLayerCount,
              "%s: 3 layers and the paths (%s)" % (what, job.PathsStatus))
        check(views and all(v.LineWidth == 2.0 for v in views), "%s: paths styled" % what)

    step("run", run_job, report)
    planned("after the run")
    paths_after_run = job.PathCount

    step("undo the run", lambda: FreeCADGui.runCommand("Std_Undo"), report)
    check(job.LayerCount == 0 and not api.layers(job) and not api.path_features(job),
          "undo removed the layers and paths (LayerCount %d)" % job.LayerCount)
    step("redo the run", lambda: FreeCADGui.runCommand("Std_Redo"), report)
    planned("after redo")

    def change_spacing():
        doc.openTransaction("Bead spacing")
        job.BeadSpacing = 5.0
        doc.commitTransaction()

    def recompute():
        # FreeCAD 0.20's Std_Refresh records no transaction of its own: one around it makes the
        # recompute's results undoable.
        doc.openTransaction("Recompute")
        FreeCADGui.runCommand("Std_Refresh")
        doc.commitTransaction()

    step("change a path parameter", change_spacing, report)
    step("recompute", recompute, report)
    check(job.PathsStatus.startswith("Planned") and job.RunCount == 1,
          "the recompute replanned the paths only (%s, runs %d)" % (job.PathsStatus,
                                                                     job.RunCount))
    paths_after_recompute = job.PathCount
    check(paths_after_recompute != paths_after_run, "wider spacing, other paths (%d -> %d)"
          % (paths_after_run, paths_after_recompute))
    step("undo the recompute", lambda: FreeCADGui.runCommand("Std_Undo"), report)
    check(job.PathCount == paths_after_run and abs(float(job.BeadSpacing) - 5.0) < 1e-9,
          "undo restored the paths of the run, the spacing stays (%d paths, %s)"
          % (job.PathCount, job.BeadSpacing))
    step("redo the recompute", lambda: FreeCADGui.runCommand("Std_Redo"), report)
    check(job.PathCount == paths_after_recompute, "redo restored the recomputed paths (%d)"
          % job.PathCount)
    planned("after redo of the recompute")
    for _ in range(2):
        step("undo again", lambda: FreeCADGui.runCommand("Std_Undo"), report)
    step("redo twice", lambda: (FreeCADGui.runCommand("Std_Redo"),
                                FreeCADGui.runCommand("Std_Redo")), report)
    FreeCAD.closeDocument(doc.Name)
    process_events()
    whole = report.toPlainText() if report is not None else ""
    check(not problems(whole), "the whole Report view is free of tracebacks")


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
# FreeCAD 1.1's GUI sends print() to a buffered C stdout that os._exit would discard.
ctypes.CDLL(None).fflush(None)
os._exit(0 if not failures else 1)
