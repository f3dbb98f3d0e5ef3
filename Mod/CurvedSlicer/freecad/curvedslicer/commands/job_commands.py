"""Commands: create a Job from the selection, edit it, run it (progress + Cancel), show a layer
range, export (not available yet) and preferences. Document changes go through the macro API
(api.py) and are echoed with FreeCADGui.doCommand / doCommandSkip so macro recording captures
them; errors are shown in a message box saying what to do, never as a crash."""

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from .. import icon_path
from ..core import PATHS_NOT_WIRED, Cancelled, CurvedSlicerError
from ..objects.job import is_job


def _main_window():
    return FreeCADGui.getMainWindow()


def show_error(title, error):
    """A non-blocking-for-tests message box (also printed to the Report view)."""
    FreeCAD.Console.PrintError("CurvedSlicer: %s: %s\n" % (title, error))
    box = QtGui.QMessageBox(QtGui.QMessageBox.Warning, "CurvedSlicer: " + title, str(error),
                            QtGui.QMessageBox.Ok, _main_window())
    box.setObjectName("CurvedSlicerError")
    box.setAttribute(QtCore.Qt.WA_DeleteOnClose)
    box.show()
    return box


def _record(line):
    """Echoes `line` to the console and the macro recorder without running it."""
    skip = getattr(FreeCADGui, "doCommandSkip", None)
    if skip is not None:
        skip(line)
    else:
        FreeCADGui.doCommand("# " + line)


def selected_job():
    for obj in FreeCADGui.Selection.getSelection():
        if is_job(obj):
            return obj
        for parent in obj.InList:
            if is_job(parent):
                return parent
    doc = FreeCAD.ActiveDocument
    jobs = [o for o in doc.Objects if is_job(o)] if doc else []
    return jobs[0] if len(jobs) == 1 else None


def _ref(obj):
    return "App.getDocument(%r).getObject(%r)" % (obj.Document.Name, obj.Name)


class CreateJob:
    """Job from the selection: the first object is the solid; faces picked on it are the start
    surface; a second selected object is a start surface of its own (e.g. a curved base)."""

    def GetResources(self):
        return {"Pixmap": icon_path("Job"), "MenuText": "Create Job",
                "ToolTip": "Create a curved-layer Job from the selected solid (and start faces "
                           "or a start-surface object)"}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and bool(FreeCADGui.Selection.getSelection())

    def Activated(self):
        selection = FreeCADGui.Selection.getSelectionEx()
        if not selection:
            return
        solid = selection[0].Object
        faces = [n for n in selection[0].SubElementNames if n.startswith("Face")]
        start = "None"
        if faces:
            start = "(%s, %r)" % (_ref(solid), faces)
        elif len(selection) > 1:
            other = selection[1]
            start = "(%s, %r)" % (_ref(other.Object), list(other.SubElementNames))
        from .. import geometry

        try:
            if not geometry.is_mesh_object(solid):
                geometry.solid_shape(solid)
        except CurvedSlicerError as error:
            show_error("cannot create a Job", error)
            return
        FreeCAD.ActiveDocument.openTransaction("Create CurvedSlicer Job")
        FreeCADGui.addModule("freecad.curvedslicer.api")
        FreeCADGui.doCommand("job = freecad.curvedslicer.api.make_job(App.ActiveDocument, %s, "
                             "start=%s)" % (_ref(solid), start))
        FreeCAD.ActiveDocument.commitTransaction()
        FreeCADGui.doCommand("Gui.ActiveDocument.setEdit(job.Name)")


class EditJob:
    def GetResources(self):
        return {"Pixmap": icon_path("Edit"), "MenuText": "Edit Job",
                "ToolTip": "Edit the parameters of the selected Job (with a voxel and memory "
                           "estimate)"}

    def IsActive(self):
        return selected_job() is not None

    def Activated(self):
        job = selected_job()
        FreeCADGui.ActiveDocument.setEdit(job.Name)


class RunJob:
    def GetResources(self):
        return {"Pixmap": icon_path("Run"), "MenuText": "Run Job",
                "ToolTip": "Compute the curved layers of the selected Job (progress with "
                           "Cancel)"}

    def IsActive(self):
        return selected_job() is not None and FreeCADGui.Control.activeDialog() is False

    def Activated(self):
        run_selected_job()


def run_selected_job(job=None):
    """Runs a Job with the progress dialog; returns True on success (errors shown)."""
    from .. import api

    job = job or selected_job()
    if job is None:
        return False
    FreeCADGui.addModule("freecad.curvedslicer.api")
    _record("freecad.curvedslicer.api.run(%s)" % _ref(job))
    doc = job.Document
    doc.openTransaction("Run CurvedSlicer Job")
    try:
        api.run(job)
    except Cancelled:
        doc.commitTransaction()
        FreeCAD.Console.PrintWarning("CurvedSlicer: run of %s cancelled; the previous layers are "
                                     "kept\n" % job.Label)
        return False
    except CurvedSlicerError as error:
        doc.commitTransaction()
        show_error("the Job could not run", error)
        return False
    doc.commitTransaction()
    FreeCADGui.updateGui()
    return True


class LayerRange:
    def GetResources(self):
        return {"Pixmap": icon_path("Layers"), "MenuText": "Show layer range",
                "ToolTip": "Show only a range of the Job's layers"}

    def IsActive(self):
        job = selected_job()
        return job is not None and job.LayerCount > 0

    def Activated(self):
        dialog = LayerRangeDialog(selected_job(), _main_window())
        dialog.show()


class LayerRangeDialog(QtGui.QDialog):
    """Two sliders (first, last layer); the view follows as they move."""

    def __init__(self, job, parent=None):
        super().__init__(parent)
        self.job = job
        self.setObjectName("CurvedSlicerLayerRange")
        self.setWindowTitle("Layers of %s" % job.Label)
        layout = QtGui.QFormLayout(self)
        n = job.LayerCount
        self.first = QtGui.QSlider(QtCore.Qt.Horizontal)
        self.last = QtGui.QSlider(QtCore.Qt.Horizontal)
        for s, v in ((self.first, 1), (self.last, n)):
            s.setRange(1, n)
            s.setValue(v)
            s.valueChanged.connect(self.apply)
        self.label = QtGui.QLabel()
        layout.addRow("First", self.first)
        layout.addRow("Last", self.last)
        layout.addRow(self.label)
        self.apply()

    def apply(self, *args):
        from .. import api

        first, last = self.first.value(), self.last.value()
        if last < first:
            first, last = last, first
        api.set_layer_range(self.job, first, last)
        self.label.setText("layers %d to %d of %d" % (first, last, self.job.LayerCount))


class ExportProgram:
    def GetResources(self):
        return {"Pixmap": icon_path("Export"), "MenuText": "Export robot program (next version)",
                "ToolTip": PATHS_NOT_WIRED}

    def IsActive(self):
        return selected_job() is not None

    def Activated(self):
        QtGui.QMessageBox.information(_main_window(), "CurvedSlicer", PATHS_NOT_WIRED)


class Preferences:
    def GetResources(self):
        return {"Pixmap": icon_path("Workbench"), "MenuText": "Preferences…",
                "ToolTip": "Default voxel size and robot cell of new Jobs"}

    def IsActive(self):
        return True

    def Activated(self):
        FreeCADGui.showPreferences("CurvedSlicer")


COMMANDS = {
    "CurvedSlicer_CreateJob": CreateJob,
    "CurvedSlicer_EditJob": EditJob,
    "CurvedSlicer_RunJob": RunJob,
    "CurvedSlicer_LayerRange": LayerRange,
    "CurvedSlicer_Export": ExportProgram,
    "CurvedSlicer_Preferences": Preferences,
}


def register():
    for name, cls in COMMANDS.items():
        FreeCADGui.addCommand(name, cls())
    return list(COMMANDS)
