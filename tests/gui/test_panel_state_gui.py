"""GUI test under xvfb-run (freecad script): the Job task panel as FreeCAD's own and the Job's
state in the tree.

- Lengths are Gui::QuantitySpinBox: typing "1 in" gives 25.4 mm, "2*0.5 mm" 1 mm; "0" for the
  layer thickness and "abc" are named below the tabs while typing and refused by OK (the Job
  keeps its value).
- The panel fits the combo view at its default width (no field cut off; screenshot saved).
- The panel's Run button applies and runs the Job.
- A failed recompute (layer thickness 0, Std_Refresh) puts the Job in FreeCAD's error state: the
  message in the tree item's tooltip and in the Report view; a good recompute clears it.
- A recompute with fewer layers leaves no "unused" objects in the tree.
- A document saved and reopened is not marked modified.
Screenshots go to the test's folder under the build tree (CURVEDSLICER_TEST_TMP)."""

import os
import sys

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))
from gui_testing import (TMP, check, finish, process_events, report_view,  # noqa: E402
                         screenshot, tree_item)


def make_job():
    from freecad.curvedslicer import api

    doc = FreeCAD.newDocument("PanelTest")
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 30, 20, 12
    doc.recompute()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, "Box", "Face5")
    FreeCADGui.runCommand("CurvedSlicer_CreateJob")
    process_events()
    jobs = [o for o in doc.Objects if api.is_job(o)]
    check(len(jobs) == 1, "Create Job made one Job")
    return doc, jobs[0]


def quantities_and_refusal(job):
    panel = job.ViewObject.Proxy.panel
    check(panel is not None and FreeCADGui.Control.activeDialog(), "the panel is open")
    thickness = panel.layer_thickness
    check(thickness.widget.metaObject().className() == "Gui::QuantitySpinBox",
          "layer thickness is a Gui::QuantitySpinBox (%s)"
          % thickness.widget.metaObject().className())
    thickness.set_text("1 in")
    process_events()
    check(abs(thickness.value() - 25.4) < 1e-9, "'1 in' gives 25.4 mm (%r)" % thickness.value())
    panel.voxel_size.set_text("2*0.5 mm")
    check(abs(panel.voxel_size.value() - 1.0) < 1e-9, "'2*0.5 mm' gives 1 mm (%r)"
          % panel.voxel_size.value())
    panel.bead_spacing.set_text("=0.5*2 mm")
    check(abs(panel.bead_spacing.value() - 1.0) < 1e-9, "'=0.5*2 mm' gives 1 mm (%r)"
          % panel.bead_spacing.value())
    panel.bead_spacing.set_text("3.7 mm")
    check(panel.error_label.text() == "", "valid values: no message (%s)"
          % panel.error_label.text())
    check(panel.apply(), "the panel applies 1 in")
    check(abs(float(job.LayerThickness) - 25.4) < 1e-9 and abs(float(job.VoxelSize) - 1) < 1e-9,
          "LayerThickness 25.4 mm, VoxelSize 1 mm (%s, %s)" % (job.LayerThickness,
                                                              job.VoxelSize))

    thickness.set_text("0")
    process_events()
    live = panel.error_label.text()
    check(live.startswith("layer thickness must be positive: 0 mm"),
          "typing 0 names the problem at once: %s" % live)
    screenshot("panel_refuses_zero")
    check(not panel.accept(), "OK refuses a layer thickness of 0")
    check(panel.error_label.text().startswith("layer thickness must be positive: 0 mm"),
          "the refusal says why: %s" % panel.error_label.text())
    check(panel.tabs.currentIndex() == 1, "the Layers tab is brought forward")
    check(abs(float(job.LayerThickness) - 25.4) < 1e-9, "refused: the Job keeps 25.4 mm")
    thickness.set_text("abc")
    check(not panel.apply() and "layer thickness not understood: 'abc'"
          in panel.error_label.text(), "text that is no length is refused: %s"
          % panel.error_label.text())
    panel.corner_angle.set_text("200 deg")
    thickness.set_text("3 mm")
    check(not panel.apply() and panel.error_label.text().startswith(
        "corner angle too large: 200 °"), "an angle out of range is refused: %s"
        % panel.error_label.text())
    panel.corner_angle.set_text("30 deg")
    check(panel.apply(), "3 mm and 30° apply")
    return panel


def fits_the_combo_view(panel):
    window = FreeCADGui.getMainWindow()
    window.resize(1280, 1000)
    process_events(0.3)
    combo = [d for d in window.findChildren(QtGui.QDockWidget)
             if d.objectName() in ("Combo View", "Tasks")]
    width = combo[0].width() if combo else 0
    needed = panel.form.minimumSizeHint().width()
    print("combo view %d px wide, the panel needs %d px" % (width, needed))
    check(0 < needed <= width, "the panel fits the default combo view (%d <= %d px)"
          % (needed, width))
    right = combo[0].mapToGlobal(QtCore.QPoint(combo[0].width(), 0)).x() if combo else 0
    cut = []
    for index in range(panel.tabs.count()):
        panel.tabs.setCurrentIndex(index)
        process_events(0.1)
        for w in panel.tabs.currentWidget().findChildren(QtGui.QWidget):
            if w.isVisible() and isinstance(w, (QtGui.QAbstractSpinBox, QtGui.QComboBox,
                                                QtGui.QLineEdit, QtGui.QPushButton)):
                if w.mapToGlobal(QtCore.QPoint(w.width(), 0)).x() > right:
                    cut.append(w.objectName() or type(w).__name__)
        screenshot("panel_tab_%s" % panel.tabs.tabText(index))
    check(not cut, "no field of any tab reaches past the combo view: %s" % cut)
    panel.tabs.setCurrentIndex(1)


def run_button(job, panel):
    panel.layer_thickness.set_text("3 mm")
    panel.run_button.click()
    process_events()
    check(job.LayerCount == 3 and job.PathCount > 0, "the Run button ran the Job (%d layers, %s)"
          % (job.LayerCount, job.PathsStatus))
    check(panel.status_label.text().startswith("Layers: Done") or "layers" in
          panel.status_label.text(), "the panel shows the run's status: %s"
          % panel.status_label.text())
    check(panel.accept(), "OK closes the panel")
    process_events()


def error_state(doc, job):
    report = report_view()
    before = report.toPlainText() if report is not None else ""
    doc.openTransaction("Layer thickness 0")
    job.LayerThickness = 0
    doc.commitTransaction()
    FreeCADGui.runCommand("Std_Refresh")
    process_events(0.5)
    check("Invalid" in job.State, "a failed recompute puts the Job in the error state (%s)"
          % job.State)
    tip = hover_tooltip(job)
    check("layer thickness must be a positive number" in tip, "the tree's tooltip on the Job "
          "has the message: %s" % tip)
    text = report.toPlainText() if report is not None else ""
    new = text[len(before):] if text.startswith(before) else text
    check("layer thickness must be a positive number" in new, "the Report view has the message")
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Name, job.Name)
    screenshot("job_in_error_state")
    job.LayerThickness = 3.0
    FreeCADGui.runCommand("Std_Refresh")
    process_events(0.5)
    check(job.State == ["Up-to-date"], "a good recompute clears the error state (%s)"
          % job.State)


def hover_tooltip(obj):
    """The tooltip the tree view shows when the pointer enters `obj`'s item (for an object in
    error: its status string)."""
    window = FreeCADGui.getMainWindow()
    for tabs in window.findChildren(QtGui.QTabWidget):
        for i in range(tabs.count()):
            if tabs.tabText(i) == "Model":
                tabs.setCurrentIndex(i)
    process_events(0.2)
    item = tree_item(obj)
    if item is None:
        return ""
    tree = item.treeWidget()
    tree.scrollToItem(item)
    process_events(0.2)
    tree.itemEntered.emit(item, 0)  # as the pointer entering the item
    process_events(0.3)
    return QtGui.QToolTip.text() if QtGui.QToolTip.isVisible() else ""


def fewer_layers(doc, job):
    from freecad.curvedslicer import api

    job.LayerThickness = 5.0
    FreeCADGui.runCommand("Std_Refresh")
    process_events()
    unused = [o.Label for o in doc.Objects if "unused" in o.Label]
    check(job.LayerCount == 2 and len(api.layers(job)) == 2 and not unused,
          "a recompute with fewer layers leaves no unused objects (%d layers, unused %s)"
          % (job.LayerCount, unused))
    check(len(api.path_features(job)) == job.PlanLayerCount, "one path feature per plan layer")


def reopened_not_modified(doc):
    path = os.path.join(TMP, "reopen.FCStd")
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    process_events()
    reopened = FreeCAD.openDocument(path)
    process_events(0.5)
    gui_doc = FreeCADGui.getDocument(reopened.Name)
    check(not gui_doc.Modified, "a reopened document is not marked modified")
    from freecad.curvedslicer.commands.job_commands import ExportDialog

    dialog = ExportDialog(reopened.getObject("Job"))
    check(os.path.dirname(dialog.path.text()) == os.path.dirname(path),
          "the export dialog starts in the document's folder: %s" % dialog.path.text())
    dialog.format.setCurrentIndex([f[1] for f in dialog.filters].index("gcode"))
    check(dialog.path.text().endswith(".gcode") or dialog.path.text().endswith(".nc")
          or dialog.gcode_mode.isEnabled(), "choosing G-code enables the G-code mode")
    dialog.close()
    FreeCAD.closeDocument(reopened.Name)


def preferences_page():
    from freecad.curvedslicer import ICON_DIR
    from freecad.curvedslicer.taskpanels.preferences_page import PreferencesPage

    page = PreferencesPage()
    check(page.cell.browse.text() == "Browse…", "the preferences page has a Browse button")
    page.cell.set_text(os.path.join(TMP, "no_such_cell.json"))
    check(page.cell_status.text().startswith("cell file does not exist"),
          "a missing default cell file is named: %s" % page.cell_status.text())
    check(os.path.isfile(os.path.join(ICON_DIR, "preferences-curvedslicer.svg")),
          "the preferences page has its icon (preferences-curvedslicer)")


def run():
    FreeCADGui.showMainWindow() if hasattr(FreeCADGui, "showMainWindow") else None
    FreeCADGui.activateWorkbench("CurvedSlicerWorkbench")
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/OutputWindow").SetBool("checkError",
                                                                                True)
    doc, job = make_job()
    panel = quantities_and_refusal(job)
    fits_the_combo_view(panel)
    run_button(job, panel)
    error_state(doc, job)
    fewer_layers(doc, job)
    reopened_not_modified(doc)
    preferences_page()


finish(run)
