"""Task panel of a Job: every parameter, validation, and the voxel/memory estimate of a run.

Values are applied through FreeCADGui.doCommand (so macros record them) when OK is pressed;
the estimate (core planGrid: cells, memory against the budget) is refreshed on demand and after
every change of the voxel size, alignment or budget."""

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from ..core import CurvedSlicerError
from ..objects import job as job_module


def _mm(quantity):
    return float(FreeCAD.Units.Quantity(quantity).getValueAs("mm"))


def _spin(value, minimum, maximum, decimals=3, suffix=" mm", step=0.1):
    box = QtGui.QDoubleSpinBox()
    box.setDecimals(decimals)
    box.setRange(minimum, maximum)
    box.setSingleStep(step)
    box.setSuffix(suffix)
    box.setValue(value)
    return box


def _combo(items, current):
    box = QtGui.QComboBox()
    box.addItems(items)
    box.setCurrentIndex(max(0, items.index(current) if current in items else 0))
    return box


class TaskPanelJob:
    def __init__(self, job):
        self.job = job
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("CurvedSlicer Job")
        layout = QtGui.QVBoxLayout(self.form)

        model = QtGui.QGroupBox("Model and start surface")
        f = QtGui.QFormLayout(model)
        self.solid_label = QtGui.QLabel(job.Solid.Label if job.Solid else "(none)")
        f.addRow("Solid", self.solid_label)
        self.start_mode = _combo(job_module.START_MODES, job.StartMode)
        f.addRow("Start", self.start_mode)
        faces = ",".join(s for (_, subs) in job.StartFaces for s in subs)
        self.start_faces = QtGui.QLineEdit(faces)
        self.start_faces.setToolTip("Faces of the solid, e.g. Face1,Face6 (StartMode Faces)")
        f.addRow("Start faces", self.start_faces)
        self.surface = QtGui.QComboBox()
        self.surface_names = [""]
        self.surface.addItem("(none)")
        for o in job.Document.Objects:
            if o != job.Solid and not job_module.is_job(o) and (
                    hasattr(o, "Shape") or o.isDerivedFrom("Mesh::Feature")) and \
                    "LayerIndex" not in o.PropertiesList:
                self.surface_names.append(o.Name)
                self.surface.addItem(o.Label)
        current = job.StartSurface[0].Name if job.StartSurface else ""
        if current in self.surface_names:
            self.surface.setCurrentIndex(self.surface_names.index(current))
        f.addRow("Start surface object", self.surface)
        p, n = job.StartPlanePoint, job.StartPlaneNormal
        self.plane = [_spin(v, -1e6, 1e6) for v in (p.x, p.y, p.z)] + \
                     [_spin(v, -1.0, 1.0, 4, "", 0.1) for v in (n.x, n.y, n.z)]
        row = QtGui.QHBoxLayout()
        for w in self.plane:
            row.addWidget(w)
        f.addRow("Plane point, normal", row)
        layout.addWidget(model)

        layers = QtGui.QGroupBox("Layers")
        f = QtGui.QFormLayout(layers)
        self.layer_thickness = _spin(_mm(job.LayerThickness), 0.01, 1000.0)
        f.addRow("Layer thickness", self.layer_thickness)
        self.voxel_size = _spin(_mm(job.VoxelSize), 0.01, 1000.0)
        f.addRow("Voxel size", self.voxel_size)
        self.method = _combo(job_module.METHODS, job.Method)
        f.addRow("Method", self.method)
        self.alignment = _combo(job_module.ALIGNMENTS, job.GridAlignment)
        f.addRow("Grid alignment", self.alignment)
        self.cap_holes = QtGui.QCheckBox("Close holes of an open mesh")
        self.cap_holes.setChecked(job.CapHoles)
        f.addRow("", self.cap_holes)
        self.deflection = _spin(_mm(job.Deflection), 0.0, 100.0, 4)
        self.deflection.setSpecialValueText("auto (voxel size / 4)")
        f.addRow("Tessellation deflection", self.deflection)
        self.memory = _spin(float(job.MemoryBudget), 0.0, 1e7, 0, " MB", 100)
        self.memory.setSpecialValueText("auto (80 % of RAM)")
        f.addRow("Memory budget", self.memory)
        self.estimate_label = QtGui.QLabel("")
        self.estimate_label.setWordWrap(True)
        self.estimate_button = QtGui.QPushButton("Estimate voxels and memory")
        self.estimate_button.clicked.connect(self.update_estimate)
        f.addRow(self.estimate_button, self.estimate_label)
        layout.addWidget(layers)

        paths = QtGui.QGroupBox("Paths")
        paths.setToolTip("Bead paths on every layer (paper 3.1); a change replans the paths "
                         "without rerunning the layers")
        f = QtGui.QFormLayout(paths)
        self.bead_spacing = _spin(_mm(job.BeadSpacing), 0.01, 100.0)
        f.addRow("Bead spacing", self.bead_spacing)
        self.point_spacing = _spin(_mm(job.PointSpacing), 0.01, 100.0)
        f.addRow("Point spacing", self.point_spacing)
        self.initial_path = _combo(job_module.INITIAL_PATHS, job.InitialPath)
        f.addRow("Initial path", self.initial_path)
        self.cell_file = QtGui.QLineEdit(job.CellFile)
        f.addRow("Cell file", self.cell_file)
        note = QtGui.QLabel("Stored with the Job; paths, poses and export arrive in the next "
                            "version.")
        note.setWordWrap(True)
        f.addRow(note)
        layout.addWidget(paths)

        self.error_label = QtGui.QLabel("")
        self.error_label.setWordWrap(True)
        self.error_label.setStyleSheet("color: #b00000")
        layout.addWidget(self.error_label)

        self.voxel_size.valueChanged.connect(self._estimate_soon)
        self.alignment.currentIndexChanged.connect(self._estimate_soon)
        self.memory.valueChanged.connect(self._estimate_soon)
        self.timer = QtCore.QTimer()
        self.timer.setSingleShot(True)
        self.timer.setInterval(400)
        self.timer.timeout.connect(self.update_estimate)

    # -- estimate -------------------------------------------------------------------------------
    def _estimate_soon(self, *args):
        self.timer.start()

    def estimate(self):
        """The estimate for the values in the panel (dict of api.estimate) or raises."""
        from .. import api

        return api.estimate(self.job, voxel_size=self.voxel_size.value(),
                            grid_alignment=self.alignment.currentText(),
                            memory_budget_mb=self.memory.value(),
                            deflection=self.deflection.value())

    def update_estimate(self):
        try:
            e = self.estimate()
        except CurvedSlicerError as error:
            self.estimate_label.setText("")
            self.error_label.setText(str(error))
            return None
        text = "%d x %d x %d = %s cells, %.1f MB of %.0f MB" % (
            e["dims"][0], e["dims"][1], e["dims"][2], format(e["cells"], ","),
            e["bytes"] / 2 ** 20, e["budget_bytes"] / 2 ** 20)
        self.estimate_label.setText(text)
        self.error_label.setText("" if e["fits"] else e["message"])
        return e

    # -- apply ----------------------------------------------------------------------------------
    def commands(self):
        """The doCommand lines that apply the panel's values (without running anything)."""
        name = self.job.Name
        j = "App.getDocument(%r).getObject(%r)" % (self.job.Document.Name, name)
        lines = [
            "%s.LayerThickness = %r" % (j, self.layer_thickness.value()),
            "%s.VoxelSize = %r" % (j, self.voxel_size.value()),
            "%s.Method = %r" % (j, self.method.currentText()),
            "%s.GridAlignment = %r" % (j, self.alignment.currentText()),
            "%s.CapHoles = %r" % (j, self.cap_holes.isChecked()),
            "%s.Deflection = %r" % (j, self.deflection.value()),
            "%s.MemoryBudget = %r" % (j, self.memory.value()),
            "%s.BeadSpacing = %r" % (j, self.bead_spacing.value()),
            "%s.PointSpacing = %r" % (j, self.point_spacing.value()),
            "%s.InitialPath = %r" % (j, self.initial_path.currentText()),
            "%s.CellFile = %r" % (j, self.cell_file.text()),
            "%s.StartMode = %r" % (j, self.start_mode.currentText()),
        ]
        mode = self.start_mode.currentText()
        if mode == "Faces":
            faces = tuple(s.strip() for s in self.start_faces.text().split(",") if s.strip())
            lines.append("%s.StartFaces = [(%s.Solid, %r)]" % (j, j, faces))
        elif mode == "Surface":
            surface = self.surface_names[self.surface.currentIndex()]
            if surface:
                lines.append("%s.StartSurface = (App.getDocument(%r).getObject(%r), [])"
                             % (j, self.job.Document.Name, surface))
        elif mode == "Plane":
            v = [w.value() for w in self.plane]
            lines.append("%s.StartPlanePoint = App.Vector(%r, %r, %r)" % (j, v[0], v[1], v[2]))
            lines.append("%s.StartPlaneNormal = App.Vector(%r, %r, %r)" % (j, v[3], v[4], v[5]))
        return lines

    def validate(self):
        if self.start_mode.currentText() == "Faces" and not self.start_faces.text().strip():
            return ("no start faces: the list is empty; enter faces such as Face1 or choose "
                    "another start")
        if self.start_mode.currentText() == "Surface" and self.surface.currentIndex() == 0:
            return "no start surface: none chosen; choose the object the part grows from"
        if self.layer_thickness.value() <= 0 or self.voxel_size.value() <= 0:
            return "layer thickness and voxel size must be positive"
        return ""

    def accept(self):
        problem = self.validate()
        if problem:
            self.error_label.setText(problem)
            return False
        for line in self.commands():
            FreeCADGui.doCommand(line)
        FreeCADGui.ActiveDocument.resetEdit()
        return True

    def reject(self):
        FreeCADGui.ActiveDocument.resetEdit()
        return True

    def getStandardButtons(self):
        return QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel
