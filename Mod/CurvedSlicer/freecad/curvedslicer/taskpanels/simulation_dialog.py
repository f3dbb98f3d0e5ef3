"""The pose simulation player: play/pause, a speed factor over the motion's
own time line (native.plan_motion's ``time``: 1× is real time), a scrub slider and a point spin
box; the cell (positioner carrying the part, robot, torch, deposit so far) follows the point
(api.set_pose) and the dialog shows the point's joints, configuration and flags.

Playing and dragging the slider do not fill the macro with poses: the point reached is recorded
once (``set_pose``) when playback pauses or the slider is released; the spin box records each
value."""

import bisect

import FreeCADGui
from PySide import QtCore, QtGui

from ..commands.job_commands import _ref, do_api, show_error
from ..core import CurvedSlicerError

SPEEDS = [0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0]
DEFAULT_SPEED = 20.0
TICK_MS = 50
JOINT_NAMES = ["S", "L", "U", "R", "B", "T"]


class SimulationDialog(QtGui.QDialog):
    def __init__(self, job, parent=None):
        super().__init__(parent)
        from .. import api

        self.job = job
        self.setObjectName("CurvedSlicerSimulation")
        self.setWindowTitle("Simulate %s" % job.Label)
        self.motion = api.motion(job)
        self.times = [float(t) for t in self.motion["time"]]
        self.count = len(self.times)
        layout = QtGui.QVBoxLayout(self)
        controls = QtGui.QHBoxLayout()
        self.play_button = QtGui.QPushButton("Play")
        self.play_button.setCheckable(True)
        self.play_button.toggled.connect(self.set_playing)
        self.speed = QtGui.QComboBox()
        self.speed.addItems(["%g×" % s for s in SPEEDS])
        self.speed.setCurrentIndex(SPEEDS.index(DEFAULT_SPEED))
        self.speed.setToolTip("Playback speed over the program's time line (1× = real time)")
        self.spin = QtGui.QSpinBox()
        self.spin.setRange(0, max(self.count - 1, 0))
        self.spin.setPrefix("Point ")
        self.spin.setSuffix(" of %d" % self.count)
        controls.addWidget(self.play_button)
        controls.addWidget(QtGui.QLabel("Speed"))
        controls.addWidget(self.speed)
        controls.addWidget(self.spin)
        layout.addLayout(controls)
        self.slider = QtGui.QSlider(QtCore.Qt.Horizontal)
        self.slider.setRange(0, max(self.count - 1, 0))
        layout.addWidget(self.slider)
        form = QtGui.QFormLayout()
        self.point_label = QtGui.QLabel()
        self.point_label.setObjectName("SimulationPoint")
        self.positioner_label = QtGui.QLabel()
        self.positioner_label.setObjectName("SimulationPositioner")
        self.robot_label = QtGui.QLabel()
        self.robot_label.setObjectName("SimulationRobot")
        self.flags_label = QtGui.QLabel()
        self.flags_label.setObjectName("SimulationFlags")
        for name, label in (("Point", self.point_label), ("Positioner", self.positioner_label),
                            ("Robot", self.robot_label), ("Flags", self.flags_label)):
            label.setWordWrap(True)
            form.addRow(name, label)
        layout.addLayout(form)
        self.setMinimumWidth(520)
        self.timer = QtCore.QTimer(self)
        self.timer.setInterval(TICK_MS)
        self.timer.timeout.connect(self.tick)
        self.clock = 0.0  # s on the motion's time line
        self.slider.setValue(int(job.PosePoint))
        self.spin.setValue(int(job.PosePoint))
        self.slider.valueChanged.connect(self._slider_moved)
        self.slider.sliderReleased.connect(self.record)
        self.spin.valueChanged.connect(self._spin_changed)
        self.show_point(int(job.PosePoint))

    # ---- showing a point ---------------------------------------------------------------------

    def show_point(self, index, record=False):
        """Places the cell at motion point `index` and shows its numbers; `record`: through the
        macro API (one recorded set_pose line)."""
        from .. import api

        try:
            if record:
                do_api("set_pose(%s, %d)" % (_ref(self.job), index))
            else:
                api.set_pose(self.job, index)
            info = api.pose_info(self.job)
        except CurvedSlicerError as error:
            self.set_playing(False)
            show_error("the pose cannot be shown", error)
            return None
        self.clock = self.times[info["index"]] if self.times else 0.0
        for widget in (self.slider, self.spin):
            if widget.value() != info["index"]:
                widget.blockSignals(True)
                widget.setValue(info["index"])
                widget.blockSignals(False)
        self.point_label.setText(
            "%d of %d: %s, layer %d path %d%s · t %.1f s · %.1f mm/s · deposit %d moves" % (
                info["index"], info["count"], info["kind"], info["layer"], info["path"],
                " (arc on)" if info["arc_on"] else "", info["time"], info["speed"],
                info["deposit_moves"]))
        self.positioner_label.setText("tilt a1 %.1f°, rotation a2 %.1f°" % (info["a1"],
                                                                          info["a2"]))
        joints = ", ".join("%s %.1f°" % (n, v) for n, v in zip(JOINT_NAMES, info["joints"]))
        self.robot_label.setText("%s · %s" % (joints, ", ".join(info["configuration"])))
        self.flags_label.setText(", ".join(info["flags"]) if info["flags"] else "none")
        FreeCADGui.updateGui()
        return info

    def _slider_moved(self, value):
        self.show_point(value)

    def _spin_changed(self, value):
        self.show_point(value, record=True)

    def record(self):
        """Records the point shown (set_pose) in the macro."""
        self.show_point(self.slider.value(), record=True)

    # ---- playing -----------------------------------------------------------------------------

    def speed_factor(self):
        return SPEEDS[self.speed.currentIndex()]

    def set_playing(self, playing):
        if self.play_button.isChecked() != playing:
            self.play_button.setChecked(playing)  # emits toggled -> here again
            return
        self.play_button.setText("Pause" if playing else "Play")
        if playing:
            if self.slider.value() >= self.count - 1:
                self.show_point(0)
            self.timer.start()
        elif self.timer.isActive():
            self.timer.stop()
            self.record()

    def is_playing(self):
        return self.timer.isActive()

    def tick(self):
        """Advances the clock by one tick times the speed; shows the last point reached (at
        least the next one, so slow spans still move)."""
        if self.job.Document is None:
            self.timer.stop()
            return
        current = self.slider.value()
        self.clock += TICK_MS / 1000.0 * self.speed_factor()
        index = max(bisect.bisect_right(self.times, self.clock) - 1, current + 1)
        if index >= self.count - 1:
            self.show_point(self.count - 1)
            self.set_playing(False)
            return
        self.show_point(index)

    def done(self, result):
        self.set_playing(False)
        super().done(result)

    def closeEvent(self, event):
        self.set_playing(False)
        super().closeEvent(event)
