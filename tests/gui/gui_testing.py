"""Helpers of the GUI tests (real FreeCAD under xvfb-run): checks, event processing, the Report
view, the tree item of an object, screenshots into the test's folder under the build tree, and
the exit with the success marker (flushing the C stream that FreeCAD 1.1 buffers)."""

import ctypes
import os
import sys
import time
import traceback

import FreeCADGui
from PySide import QtGui

MARKER = "CURVEDSLICER-TESTS-OK"
TMP = os.environ.get("CURVEDSLICER_TEST_TMP", "/tmp")
failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        failures.append(what)
    return condition


def process_events(seconds=0.0):
    """Lets Qt and FreeCAD handle pending events (for at least `seconds`)."""
    end = time.time() + seconds
    while True:
        for _ in range(5):
            QtGui.QApplication.processEvents()
            FreeCADGui.updateGui()
        if time.time() >= end:
            return
        time.sleep(0.05)


def report_view():
    """FreeCAD's Report view (a QTextEdit)."""
    for widget in FreeCADGui.getMainWindow().findChildren(QtGui.QTextEdit):
        if widget.objectName() == "Report view":
            return widget
    return None


def tree_item(obj):
    """The item of `obj` in the tree view (by its label), or None."""
    from PySide import QtCore

    flags = QtCore.Qt.MatchRecursive | QtCore.Qt.MatchExactly
    for tree in FreeCADGui.getMainWindow().findChildren(QtGui.QTreeWidget):
        for item in tree.findItems(obj.Label, flags, 0):
            return item
    return None


def screenshot(name):
    """The main window as TMP/<name>.png (a test artifact under the build tree)."""
    path = os.path.join(TMP, name + ".png")
    FreeCADGui.getMainWindow().grab().save(path)
    print("screenshot: %s" % path, flush=True)
    return path


def finish(body):
    """Runs `body`, prints the marker or the failures, and leaves FreeCAD with the exit code."""
    try:
        body()
    except Exception:
        traceback.print_exc()
        failures.append("exception")
    sys.stdout.flush()
    sys.stderr.flush()
    ctypes.CDLL(None).fflush(None)
    # The verdict goes straight to the file descriptor: on FreeCAD 1.1 the tail of a long run's
    # printed lines can still sit in a stream the flushes above do not reach when os._exit ends
    # the process (seen: exit code 0 but neither the marker nor the last checks in the log).
    verdict = MARKER if not failures else "failures: %s" % failures
    os.write(1, (verdict + "\n").encode("utf-8"))
    os._exit(0 if not failures else 1)
