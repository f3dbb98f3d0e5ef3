"""GUI test under xvfb-run (freecad script): a macro recorded from GUI actions replays.

FreeCAD's own macro recorder (Macro > Macro recording…, driven through its dialog) records: a
new document, a box (Part_Box), Create Job with a picked start face, lengths typed into the task
panel ("0.1 in", "2*0.5 mm"), the panel's Run button, OK, an export through the export dialog
(JBI, a program name), three pose steps and a layer range. The macro must hold the real
freecad.curvedslicer.api lines (no `import job_commands`, Run and Export not as comments). The
document is closed, the macro is replayed; its export must equal the recorded session's byte for
byte, and the pose and layer range must be the session's."""

import filecmp
import os
import shutil
import sys

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))
from gui_testing import TMP, check, finish, process_events, screenshot  # noqa: E402

MACROS = os.path.join(TMP, "macros")
EXPORT = os.path.join(TMP, "export")


def start_recording(name):
    """Macro > Macro recording…: the dialog gets the name and Record is pressed."""
    params = FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Macro")
    params.SetString("MacroPath", MACROS + os.sep)

    def fill():
        for w in QtGui.QApplication.topLevelWidgets():
            if w.objectName() == "Gui__Dialog__DlgMacroRecord" and w.isVisible():
                w.findChild(QtGui.QLineEdit, "lineEditPath").setText(name)
                w.findChild(QtGui.QLineEdit, "lineEditMacroPath").setText(MACROS + os.sep)
                w.findChild(QtGui.QPushButton, "buttonStart").click()
                return
        QtCore.QTimer.singleShot(200, fill)

    QtCore.QTimer.singleShot(200, fill)
    FreeCADGui.runCommand("Std_DlgMacroRecord")
    process_events()


def gui_session():
    """The user's actions; returns the document."""
    from freecad.curvedslicer import api
    from freecad.curvedslicer.commands import job_commands

    import PartGui  # noqa: F401  (Part_Box, as in the Part workbench)

    FreeCADGui.runCommand("Std_New")
    process_events()
    doc = FreeCAD.ActiveDocument
    FreeCADGui.runCommand("Part_Box")
    process_events()
    box = doc.getObject("Box")
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, box.Name, "Face5")
    FreeCADGui.runCommand("CurvedSlicer_CreateJob")
    process_events()
    job = [o for o in doc.Objects if api.is_job(o)][0]
    panel = job.ViewObject.Proxy.panel
    panel.layer_thickness.set_text("0.1 in")
    panel.voxel_size.set_text("2*0.5 mm")
    panel.bead_spacing.set_text("3 mm")
    panel.run_button.click()
    process_events()
    check(job.LayerCount > 0 and job.PathCount > 0, "the panel's Run ran the Job (%d layers)"
          % job.LayerCount)
    check(panel.accept(), "OK closes the panel")
    process_events()
    dialog = job_commands.ExportDialog(job)
    check(os.path.dirname(dialog.path.text()) == os.path.expanduser("~"),
          "unsaved document: the export dialog starts in the home folder (%s)"
          % dialog.path.text())
    dialog.program_name.setText("MACROTES")
    dialog.path.setText(os.path.join(EXPORT, "MACROTES.JBI"))  # file name = program name
    options = dialog.options()
    check(options["format"] == "jbi" and options["program_name"] == "MACROTES",
          "the export dialog's options: %s" % options)
    check(job_commands.export_selected_job(job, **options) is not None, "export from the GUI")
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, job.Name)
    for _ in range(3):
        FreeCADGui.runCommand("CurvedSlicer_StepPose")
    process_events()
    dialog = job_commands.LayerRangeDialog(job)
    dialog.first.setValue(2)
    dialog.close()
    screenshot("macro_session")
    return doc


def replay(macro):
    """Runs the macro as a fresh FreeCAD's Macro > Macros… > Execute does: in a console namespace
    that holds only FreeCAD's own names (App, Gui), so the macro must import the API itself."""
    namespace = {"__builtins__": __builtins__, "FreeCAD": FreeCAD, "App": FreeCAD,
                 "FreeCADGui": FreeCADGui, "Gui": FreeCADGui}
    with open(macro) as f:
        code = compile(f.read(), macro, "exec")
    exec(code, namespace)
    process_events()


def run():
    FreeCADGui.showMainWindow() if hasattr(FreeCADGui, "showMainWindow") else None
    FreeCADGui.activateWorkbench("CurvedSlicerWorkbench")
    from freecad.curvedslicer import api

    os.makedirs(MACROS, exist_ok=True)
    os.makedirs(EXPORT, exist_ok=True)
    start_recording("session")
    doc = gui_session()
    # FreeCAD 0.20 has Std_MacroStopRecord; from 0.22 on the recording command itself stops a
    # running recording (the button turns into "Stop macro recording").
    if "Std_MacroStopRecord" in FreeCADGui.listCommands():
        FreeCADGui.runCommand("Std_MacroStopRecord")
    else:
        FreeCADGui.runCommand("Std_DlgMacroRecord")
    process_events()
    macro = os.path.join(MACROS, "session.FCMacro")
    check(os.path.isfile(macro), "the macro was recorded: %s" % macro)
    text = open(macro).read() if os.path.isfile(macro) else ""
    print("---- recorded macro ----\n%s---- end ----" % text)
    lines = [line.strip() for line in text.splitlines()]
    check(not any("job_commands" in line for line in lines), "no job_commands in the macro")
    for call in ("make_job(", "run(", "export("):
        check(any(line.startswith(("freecad.curvedslicer.api." + call, "job = freecad."
                                   "curvedslicer.api." + call)) for line in lines),
              "the macro calls freecad.curvedslicer.api.%s...) as a real line" % call)
    check(any("LayerThickness = 2.54" in line for line in lines),
          "the typed 0.1 in is recorded as 2.54 mm")
    check(any(line == "Gui.ActiveDocument.resetEdit()" for line in lines),
          "closing the panel is recorded (resetEdit)")
    first_call = min([i for i, line in enumerate(lines) if "freecad.curvedslicer.api." in line
                      and not line.startswith("import")] or [0])
    check(any(line == "import freecad.curvedslicer.api" for line in lines[:first_call]),
          "the macro imports the API before its first call (the API was loaded before recording)")
    check(not any("getDocument(%r)" % doc.Name in line for line in lines
                  if "curvedslicer" in line or "setEdit" in line or "resetEdit" in line),
          "the workbench's lines name the document as App.ActiveDocument, not by its name")

    recorded = os.path.join(TMP, "export_recorded")
    shutil.rmtree(recorded, ignore_errors=True)
    shutil.move(EXPORT, recorded)
    os.makedirs(EXPORT)
    name = doc.Name
    job = [o for o in doc.Objects if o.Name == "Job"][0]
    session_state = (job.PosePoint, [o.Visibility for o in api.layers(job)])
    check(session_state[0] > 0 and not session_state[1][0], "the session stepped the pose and "
          "hid layer 1: %s" % (session_state,))
    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
    FreeCAD.closeDocument(name)
    process_events()
    # a document holding the session document's name: the replayed one gets another name
    blocker = FreeCAD.newDocument(name)

    replay(macro)
    check(FreeCAD.ActiveDocument.Name != name, "the replay ran in a document of another name")
    check(not FreeCADGui.Control.activeDialog(), "the replay closed the panel it opened")
    replayed_job = FreeCAD.ActiveDocument.getObject("Job")
    replayed_state = (replayed_job.PosePoint, [o.Visibility for o in api.layers(replayed_job)])
    check(replayed_state == session_state, "the replay steps the pose and shows the layer range "
          "as the session did: %s" % (replayed_state,))
    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
    process_events()
    replayed = sorted(os.listdir(EXPORT))
    check(replayed == sorted(os.listdir(recorded)) and replayed,
          "the replay wrote the same files: %s" % replayed)
    same, different, errors = filecmp.cmpfiles(recorded, EXPORT, replayed, shallow=False)
    check(not different and not errors and same == replayed,
          "the replay's export equals the recorded session's byte for byte (different %s)"
          % different)
    screenshot("macro_replayed")
    del blocker
    for d in FreeCAD.listDocuments():
        FreeCAD.closeDocument(d)


finish(run)
