"""Preferences page (Edit > Preferences > CurvedSlicer): default voxel size and robot cell."""

from PySide import QtGui

from .. import preferences


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
        self.cell = QtGui.QLineEdit()
        layout.addRow("Default robot cell file", self.cell)
        self.loadSettings()

    def loadSettings(self):
        self.voxel.setValue(preferences.default_voxel_size())
        self.cell.setText(preferences.default_cell_file())

    def saveSettings(self):
        preferences.set_defaults(voxel_size=self.voxel.value(), cell_file=self.cell.text())
