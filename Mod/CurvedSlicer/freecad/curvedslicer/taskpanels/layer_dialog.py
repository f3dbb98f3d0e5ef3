"""The layer inspector: a spin box and a slider pick one plan layer; the view
shows only that layer's surface and its paths (api.show_layer, recorded in macros), and the
dialog shows the layer's number, height, paths, coverage (when the plan measured it) and
warnings. "All layers" shows every layer again; "Uncovered regions" marks the largest voids of
the layers shown (api.show_voids)."""

import FreeCADGui
from PySide import QtCore, QtGui

from ..commands.job_commands import _ref, do_api, show_error, toggle_voids
from ..core import CurvedSlicerError


def coverage_lines(coverage):
    """Readable lines of a plan layer's coverage object (plan file version 2): shares as
    percentages, other numbers as they are, lists (the voids) as their count; [] for none or a
    layer whose coverage was not measured."""
    if not coverage or coverage.get("measured") is False:
        return []
    lines = []
    for key, value in coverage.items():
        if key == "measured":
            continue
        name = key.replace("_", " ")
        if isinstance(value, list):
            lines.append("%s: %d" % (name, len(value)))
        elif isinstance(value, bool):
            lines.append("%s: %s" % (name, "yes" if value else "no"))
        elif isinstance(value, float) and key.endswith("share"):
            lines.append("%s: %.1f %%" % (name, 100.0 * value))
        elif isinstance(value, (int, float)):
            lines.append("%s: %g" % (name, value))
    return lines


class LayerDialog(QtGui.QDialog):
    """Spin box + slider (1..plan layers), an "All layers" check box, the layer's numbers."""

    def __init__(self, job, parent=None):
        super().__init__(parent)
        self.job = job
        self.setObjectName("CurvedSlicerLayers")
        self.setWindowTitle("Layers of %s" % job.Label)
        count = max(int(job.PlanLayerCount), 1)
        layout = QtGui.QVBoxLayout(self)
        row = QtGui.QHBoxLayout()
        self.spin = QtGui.QSpinBox()
        self.spin.setRange(1, count)
        self.spin.setPrefix("Layer ")
        self.spin.setSuffix(" of %d" % count)
        self.slider = QtGui.QSlider(QtCore.Qt.Horizontal)
        self.slider.setRange(1, count)
        self.slider.setTickPosition(QtGui.QSlider.TicksBelow)
        self.slider.setTickInterval(max(1, count // 20))
        row.addWidget(self.spin)
        row.addWidget(self.slider, 1)
        layout.addLayout(row)
        self.all_layers = QtGui.QCheckBox("All layers")
        layout.addWidget(self.all_layers)
        from .. import api

        self.voids = QtGui.QCheckBox("Uncovered regions")
        self.voids.setObjectName("LayerVoids")
        self.voids.setToolTip("A red disc on each of the layer's largest voids (centre and area "
                              "from the plan's coverage)")
        self.voids.setChecked(api.voids_shown(job))
        layout.addWidget(self.voids)
        self.title = QtGui.QLabel()
        self.title.setObjectName("LayerTitle")
        layout.addWidget(self.title)
        self.coverage = QtGui.QLabel()
        self.coverage.setObjectName("LayerCoverage")
        layout.addWidget(self.coverage)
        self.warnings = QtGui.QPlainTextEdit()
        self.warnings.setObjectName("LayerWarnings")
        self.warnings.setReadOnly(True)
        self.warnings.setMaximumHeight(120)
        layout.addWidget(self.warnings)
        self.spin.valueChanged.connect(self.slider.setValue)
        self.slider.valueChanged.connect(self.spin.setValue)
        self.spin.valueChanged.connect(self.apply)
        self.all_layers.toggled.connect(self.apply)
        self.voids.toggled.connect(self.show_voids)
        self.info = None
        self.apply()

    def show_voids(self, checked):
        """Shows or hides the uncovered regions (of the layers shown)."""
        toggle_voids(self.job, bool(checked))
        FreeCADGui.updateGui()

    def apply(self, *args):
        """Shows the chosen layer (or all) and its numbers."""
        index = 0 if self.all_layers.isChecked() else self.spin.value()
        for widget in (self.spin, self.slider):
            widget.setEnabled(index != 0)
        try:
            do_api("show_layer(%s, %d)" % (_ref(self.job), index))
            from .. import api

            self.info = api.layer_info(self.job, self.spin.value())
        except CurvedSlicerError as error:
            show_error("the layer cannot be shown", error)
            return
        info = self.info
        self.title.setText("Layer %d of %d · height %.2f mm · %d paths · %d points%s"
                           % (info["index"], info["count"], info["height"], info["paths"],
                              info["points"], " (all layers shown)" if index == 0 else ""))
        lines = coverage_lines(info["coverage"])
        self.coverage.setText("Coverage: " + ", ".join(lines) if lines else
                              "Coverage: not measured in this plan")
        self.warnings.setPlainText("\n".join(info["warnings"]) if info["warnings"] else
                                   "No warnings for this layer")
        FreeCADGui.updateGui()
