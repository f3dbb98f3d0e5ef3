"""Commands: create a Job from the selection, edit it, run it (progress + Cancel; then the
results shown and the solid hidden), show a layer range, inspect one layer (surface, paths,
coverage, warnings), show/hide the cell, simulate the poses (torch, robot, deposit), export
the robot program (a dialog with file, format, program name and G-code mode; the document's
folder by default), step and animate the positioner poses, and preferences.

Document changes are made by running the macro API's own lines through FreeCADGui.doCommand
(each after its own "import freecad.curvedslicer.api" line, so a macro recorded after the API was
first loaded still imports it; objects of the active document through App.ActiveDocument, so it
replays into a document of another name), so a recorded macro holds exactly the calls that ran — ``freecad.curvedslicer.api.run(...)``, ``...export(...)``, ``...set_pose(...)``
— and replays them; errors are shown in a message box saying what to do, never as a crash."""

import os

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from .. import icon_path
from ..core import Cancelled, CurvedSlicerError
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


API = "freecad.curvedslicer.api"


def do_api(call):
    """Runs `call` (an expression on freecad.curvedslicer.api, e.g. "run(<job>)") in FreeCAD's
    console namespace: recorded in the macro as the real line, echoed to the Python console.
    Exceptions of the call propagate to the caller."""
    FreeCADGui.doCommand("import " + API)
    FreeCADGui.doCommand("%s.%s" % (API, call))


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
    from ..taskpanels.job_fields import object_ref

    return object_ref(obj.Document.Name, obj.Name)


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
        FreeCADGui.doCommand("import " + API)
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
        edit_job(selected_job())


def edit_job(job):
    """Opens the Job's task panel, recorded as Gui.getDocument(...).setEdit(...)."""
    from ..taskpanels.job_fields import document_ref

    FreeCADGui.doCommand("%s.setEdit(%r)" % (document_ref(job.Document.Name, "Gui"), job.Name))


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
    """Runs a Job with the progress dialog (recorded as freecad.curvedslicer.api.run); returns
    True on success (errors shown)."""
    job = job or selected_job()
    if job is None:
        return False
    doc = job.Document
    doc.openTransaction("Run CurvedSlicer Job")
    try:
        do_api("run(%s)" % _ref(job))
    except Cancelled:
        doc.commitTransaction()
        FreeCAD.Console.PrintWarning("CurvedSlicer: run of %s cancelled; the previous layers are "
                                     "kept\n" % job.Label)
        return False
    except CurvedSlicerError as error:
        doc.commitTransaction()
        show_error("the Job could not run", error)
        return False
    do_api("show_results(%s)" % _ref(job))
    doc.commitTransaction()
    fit_view()
    return True


def fit_view():
    """Fit All in the active 3D view (after the shown objects changed)."""
    FreeCADGui.updateGui()
    if FreeCADGui.ActiveDocument is not None:
        FreeCADGui.SendMsgToActiveView("ViewFit")


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


class InspectLayers:
    def GetResources(self):
        return {"Pixmap": icon_path("Layers"), "MenuText": "Inspect layers…",
                "ToolTip": "Show one layer's surface and paths at a time, with its height, "
                           "coverage and warnings"}

    def IsActive(self):
        job = selected_job()
        return job is not None and bool(job.PlanJson)

    def Activated(self):
        from ..taskpanels.layer_dialog import LayerDialog

        dialog = LayerDialog(selected_job(), _main_window())
        dialog.show()
        fit_view()
        return dialog


class ToggleCell:
    """Shows or hides the cell at the pose (positioner with the part, robot, torch, deposit):
    it sits in cell coordinates, so Fit All frames the part only without it."""

    def GetResources(self):
        return {"Pixmap": icon_path("Cell"), "MenuText": "Show/hide the cell",
                "ToolTip": "Show or hide the positioner, robot and torch at the pose (hidden, "
                           "Fit All frames the part)"}

    def IsActive(self):
        job = selected_job()
        return job is not None and job.PosesGroup is not None

    def Activated(self):
        from .. import api

        job = selected_job()
        do_api("show_cell(%s, %r)" % (_ref(job), not api.cell_shown(job)))
        fit_view()


class ToggleVoids:
    """Shows or hides the uncovered regions (the plan's largest voids per layer) as red discs on
    the layers whose paths are shown."""

    def GetResources(self):
        return {"Pixmap": icon_path("Layers"), "MenuText": "Show uncovered regions",
                "ToolTip": "Show or hide a red disc on each of the largest voids of every shown "
                           "layer (area and centre from the plan's coverage)"}

    def IsActive(self):
        job = selected_job()
        return job is not None and bool(job.PlanJson)

    def Activated(self):
        from .. import api

        job = selected_job()
        toggle_voids(job, not api.voids_shown(job))


def toggle_voids(job, visible):
    """Shows or hides the Job's uncovered regions (recorded in macros) and colours them."""
    from ..viewproviders.view_job import style_voids

    try:
        do_api("show_voids(%s, %r)" % (_ref(job), bool(visible)))
    except CurvedSlicerError as error:
        show_error("the uncovered regions cannot be shown", error)
        return
    style_voids(job)


class Simulate:
    """The pose simulation player: play/pause, speed, scrub; joints and flags of the point."""

    def GetResources(self):
        return {"Pixmap": icon_path("Simulate"), "MenuText": "Simulate…",
                "ToolTip": "Play the robot, torch and positioner through the plan, the deposit "
                           "growing (play/pause, speed, scrub)"}

    def IsActive(self):
        job = selected_job()
        return job is not None and bool(job.PlanJson)

    def Activated(self):
        from ..taskpanels.simulation_dialog import SimulationDialog

        job = selected_job()
        try:
            do_api("show_cell(%s, True)" % _ref(job))
            dialog = SimulationDialog(job, _main_window())
        except CurvedSlicerError as error:
            show_error("the simulation cannot start", error)
            return None
        dialog.show()
        fit_view()
        return dialog


class LayerRangeDialog(QtGui.QDialog):
    """Two sliders (first, last layer) with their numbers; the view follows as they move
    (layer surfaces and their paths)."""

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
        self.first_label, self.last_label = QtGui.QLabel(), QtGui.QLabel()
        layout.addRow("First", self.first)
        layout.addRow("", self.first_label)
        layout.addRow("Last", self.last)
        layout.addRow("", self.last_label)
        layout.addRow(self.label)
        self.apply()

    def apply(self, *args):
        first, last = self.first.value(), self.last.value()
        if last < first:
            first, last = last, first
        do_api("set_layer_range(%s, %d, %d)" % (_ref(self.job), first, last))
        heights = {f.LayerIndex: float(f.Height) for f in layer_features(self.job)}
        for label, slider in ((self.first_label, self.first), (self.last_label, self.last)):
            k = slider.value()
            label.setText("layer %d%s" % (k, " · height %.2f mm" % heights[k] if k in heights
                                          else ""))
        self.label.setText("layers %d to %d of %d" % (first, last, self.job.LayerCount))


def layer_features(job):
    from .. import api

    return api.layers(job)


class ExportProgram:
    """Robot program of the selected Job's stored plan: a file dialog whose filters are the
    formats of the exporters; the format follows the chosen filter (or the file's extension)."""

    def GetResources(self):
        return {"Pixmap": icon_path("Export"), "MenuText": "Export robot program…",
                "ToolTip": "Write the robot program (JBI, KRL, RAPID, LS, G-code, CSV, JSON) of "
                           "the selected Job's plan; all files or none"}

    def IsActive(self):
        job = selected_job()
        return job is not None and bool(job.PlanJson)

    def Activated(self):
        export_selected_job()


def export_filters():
    from .. import api

    return [("%s (*%s)" % (name.upper(), ext), name, ext) for (name, ext) in api.export_formats()]


GCODE_MODES = ["tcp", "machine"]  # export/exporter.hpp GcodeMode: Tcp, Machine


def default_export_folder(job):
    """The folder of the Job's document file; the home folder for an unsaved document."""
    name = job.Document.FileName
    return os.path.dirname(name) if name else os.path.expanduser("~")


class ExportDialog(QtGui.QDialog):
    """File (Browse… in the document's folder), format, program name and G-code mode of an
    export; options() gives export_selected_job's keywords."""

    def __init__(self, job, parent=None):
        super().__init__(parent)
        self.setObjectName("CurvedSlicerExport")
        self.setWindowTitle("Export robot program of %s" % job.Label)
        self.filters = export_filters()
        form = QtGui.QFormLayout(self)
        form.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)
        self.format = QtGui.QComboBox()
        self.format.addItems(["%s (%s)" % (name.upper(), ext) for (_, name, ext) in self.filters])
        self.format.currentIndexChanged.connect(self._format_changed)
        form.addRow("Format", self.format)
        self.path = QtGui.QLineEdit(os.path.join(default_export_folder(job),
                                                 job.Label + self.filters[0][2]))
        browse = QtGui.QPushButton("Browse…")
        browse.clicked.connect(self.browse)
        row = QtGui.QHBoxLayout()
        row.addWidget(self.path)
        row.addWidget(browse)
        form.addRow("File", row)
        self.program_name = QtGui.QLineEdit("")
        self.program_name.setPlaceholderText("the file's name")
        self.program_name.setToolTip("Program / job name in the file; empty = the file's name "
                                     "(each format cuts it to its controller's limit; the "
                                     "file must carry the program's name)")
        form.addRow("Program name", self.program_name)
        self.gcode_mode = QtGui.QComboBox()
        self.gcode_mode.addItems(GCODE_MODES)
        self.gcode_mode.setToolTip("tcp: part-frame X Y Z with the table angles A C (the "
                                   "controller does the kinematics); machine: X Y Z through "
                                   "the table's kinematics")
        form.addRow("G-code mode", self.gcode_mode)
        self.allow_foreign_cell = QtGui.QCheckBox("Write it for another vendor's cell")
        self.allow_foreign_cell.setToolTip(
            "JBI is for Yaskawa, KRL for KUKA, RAPID for ABB and LS for Fanuc cells (the cell's "
            "\"vendor\"); by default an export in another vendor's language is refused")
        form.addRow("Foreign cell", self.allow_foreign_cell)
        buttons = QtGui.QDialogButtonBox(QtGui.QDialogButtonBox.Ok |
                                         QtGui.QDialogButtonBox.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)
        self._format_changed()

    def _format_changed(self, *args):
        name, ext = self.filters[self.format.currentIndex()][1:]
        self.gcode_mode.setEnabled(name == "gcode")
        path = self.path.text()
        if path:
            self.path.setText(os.path.splitext(path)[0] + ext)

    def browse(self):
        _, name, ext = self.filters[self.format.currentIndex()]
        chosen = QtGui.QFileDialog.getSaveFileName(
            self, "Export robot program", self.path.text(), "%s (*%s)" % (name.upper(), ext))
        path = chosen[0] if isinstance(chosen, (tuple, list)) else chosen
        if path:
            self.path.setText(path)
        return path

    def options(self):
        name = self.filters[self.format.currentIndex()][1]
        return {"path": self.path.text().strip(), "format": name,
                "program_name": self.program_name.text().strip(),
                "gcode_mode": self.gcode_mode.currentText() if name == "gcode" else "tcp",
                "allow_foreign_cell": self.allow_foreign_cell.isChecked()}


def export_selected_job(job=None, path=None, format=None, program_name="", gcode_mode="tcp",
                        allow_foreign_cell=False):
    """Exports through the macro API, recorded as freecad.curvedslicer.api.export(...); returns
    {files, motion_count, ...} or None. Without `path` the export dialog asks."""
    job = job or selected_job()
    if job is None:
        return None
    if path is None:
        dialog = ExportDialog(job, _main_window())
        if not (getattr(dialog, "exec", None) or dialog.exec_)():
            return None
        options = dialog.options()
        path, format = options["path"], options["format"]
        program_name, gcode_mode = options["program_name"], options["gcode_mode"]
        allow_foreign_cell = options["allow_foreign_cell"]
    if format is None:
        format = next((f[1] for f in export_filters() if path.lower().endswith(f[2].lower())),
                      "jbi")
    extras = "".join(", %s=%r" % (k, v) for (k, v, default) in (
        ("program_name", program_name, ""), ("gcode_mode", gcode_mode, "tcp"),
        ("allow_foreign_cell", bool(allow_foreign_cell), False)) if v != default)
    try:
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            do_api("export(%s, %r, format=%r%s)" % (_ref(job), path, format, extras))
        finally:
            QtGui.QApplication.restoreOverrideCursor()
    except CurvedSlicerError as error:
        show_error("export failed", error)
        return None
    FreeCAD.Console.PrintMessage("CurvedSlicer: wrote %s\n" % path)
    return {"path": path, "format": format}


class StepPose:
    """Shows the positioner at the next motion point (a tenth of a path's points further)."""

    def GetResources(self):
        return {"Pixmap": icon_path("Run"), "MenuText": "Step positioner pose",
                "ToolTip": "Move the positioner model to the next path point of the plan"}

    def IsActive(self):
        job = selected_job()
        return job is not None and bool(job.PlanJson)

    def Activated(self):
        from .. import api

        job = selected_job()
        count = api.pose_count(job)
        step = max(1, count // 200)
        index = (job.PosePoint + step) % max(count, 1)
        try:
            do_api("set_pose(%s, %d)" % (_ref(job), index))
        except CurvedSlicerError as error:
            show_error("the pose cannot be shown", error)
        FreeCADGui.updateGui()


class AnimatePoses:
    """Plays the positioner through the plan (about 200 poses; run again to stop)."""

    def __init__(self):
        self.timer = None
        self.job = None

    def GetResources(self):
        return {"Pixmap": icon_path("Layers"), "MenuText": "Animate positioner poses",
                "ToolTip": "Step the positioner model through the plan's points (again: stop)"}

    def IsActive(self):
        job = selected_job()
        return job is not None and bool(job.PlanJson)

    def Activated(self):
        from .. import api

        if self.timer is not None:
            self.stop()
            return
        job = selected_job()
        count = api.pose_count(job)
        step = max(1, count // 200)
        state = {"index": 0}

        def tick():
            if job.Document is None or state["index"] >= count:
                self.stop()
                return
            try:
                api.set_pose(job, state["index"])
            except CurvedSlicerError as error:
                self.stop()
                show_error("animation stopped", error)
                return
            state["index"] += step

        self.job = job
        self.timer = QtCore.QTimer()
        self.timer.timeout.connect(tick)
        self.timer.start(50)

    def stop(self):
        """Stops the animation; the pose it stopped at is recorded (set_pose) for macros."""
        self.timer.stop()
        self.timer = None
        job, self.job = self.job, None
        if job is not None and job.Document is not None:
            try:
                do_api("set_pose(%s, %d)" % (_ref(job), job.PosePoint))
            except CurvedSlicerError as error:
                show_error("the pose cannot be shown", error)


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
    "CurvedSlicer_StepPose": StepPose,
    "CurvedSlicer_AnimatePoses": AnimatePoses,
    "CurvedSlicer_InspectLayers": InspectLayers,
    "CurvedSlicer_ToggleCell": ToggleCell,
    "CurvedSlicer_ToggleVoids": ToggleVoids,
    "CurvedSlicer_Simulate": Simulate,
    "CurvedSlicer_Preferences": Preferences,
}


# FreeCADGui.addCommand takes the file name of its Python caller as the command's module, and
# the macro recorder writes "import <that name>" at the top of every macro that runs the
# command: called from here, "import job_commands", which fails on replay. The call is made from
# a frame labelled ".../Mod/CurvedSlicer/FreeCADGui": the macro imports FreeCADGui (always
# importable in the GUI) and the commands' group stays "CurvedSlicer".
_ADD_COMMAND = compile("FreeCADGui.addCommand(name, command)", "/Mod/CurvedSlicer/FreeCADGui",
                       "exec")


#: The toolbar: the everyday commands (the menu has them all).
TOOLBAR = ["CurvedSlicer_CreateJob", "CurvedSlicer_EditJob", "CurvedSlicer_RunJob",
           "CurvedSlicer_LayerRange", "CurvedSlicer_InspectLayers", "CurvedSlicer_ToggleCell",
           "CurvedSlicer_Simulate"]


def register():
    for name, cls in COMMANDS.items():
        exec(_ADD_COMMAND, {"FreeCADGui": FreeCADGui, "name": name, "command": cls()})
    return list(COMMANDS)
