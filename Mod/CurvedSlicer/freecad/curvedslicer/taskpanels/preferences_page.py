"""Preferences page (Edit > Preferences > CurvedSlicer): default voxel size and robot cell of new
Jobs. The page's icon in the Preferences dialog is resources/icons/preferences-curvedslicer.svg
(FreeCAD looks up "preferences-<group>" on its icon path; init_gui.py adds the folder). The cell
file has a Browse… button and is checked with the core's reader when saved."""

from PySide import QtGui

from .. import preferences
from .job_fields import FileField, cell_problem


class PreferencesPage:
    def __init__(self, parent=None):
        self.form = QtGui.QWidget(parent)
        self.form.setWindowTitle("CurvedSlicer")
        layout = QtGui.QFormLayout(self.form)
        self.voxel = QtGui.QDoubleSpinBox()
        self.voxel.setDecimals(3)
        self.voxel.setRange(0.01, 100.0)
        self.voxel.setSuffix(" mm")
        layout.addRow("Default voxel size", self.voxel)
        self.cell = FileField("", "Default robot cell file", "Cell JSON (*.json);;All files (*)")
        self.cell.edit.setPlaceholderText("the paper's cell (Motoman HP20D)")
        self.cell.on_change.append(self.update_cell_status)
        layout.addRow("Default robot cell file", self.cell)
        self.cell_status = QtGui.QLabel("")
        self.cell_status.setWordWrap(True)
        layout.addRow("", self.cell_status)
        self.loadSettings()

    def update_cell_status(self):
        problem = cell_problem(self.cell.text())
        self.cell_status.setStyleSheet("color: #b00000" if problem else "")
        self.cell_status.setText(problem)
        return problem

    def loadSettings(self):
        self.voxel.setValue(preferences.default_voxel_size())
        self.cell.edit.setText(preferences.default_cell_file())
        self.update_cell_status()

    def saveSettings(self):
        preferences.set_defaults(voxel_size=self.voxel.value(), cell_file=self.cell.text())
