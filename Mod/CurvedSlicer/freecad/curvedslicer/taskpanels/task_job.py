"""Task panel of a Job: every user-facing Job property, validation, and the voxel/memory
estimate of a run.

Lengths and angles are FreeCAD's unit-aware Gui::QuantitySpinBox ("1 in" is 25.4 mm, "2*0.5 mm"
is 1 mm); a value out of range or text that is not a length is named below the tabs while typing
and refused on OK/Apply/Run (never silently replaced by the previous value). The tabs scroll and
the form rows wrap, so the panel fits the default width of the combo view.

Four tabs follow the property groups: Model (Solid, PlanKind, the start surface and the thin
wall), Layers (with the estimate: core planGrid cells and memory against the budget, refreshed on
demand and after a change of the voxel size, alignment or budget), Paths, Robot (cell file with a
file dialog, torch orientation, part placement and the other motion options, pose point). Fields
that the chosen modes do not use are disabled (e.g. the wall fields unless PlanKind is ThinWall,
the initial plane unless InitialPath is Plane).

OK and Apply first validate what the panel would set (a message "<what>: <value>; <what to do>"
below the tabs, the tab with the field brought forward, nothing applied), then assign the
properties the user changed through FreeCADGui.doCommand inside one transaction, so macro
recording captures them and Undo reverts them. Nothing is computed on apply; the Run button
applies, then runs the Job (recorded as freecad.curvedslicer.api.run).
"""

import FreeCADGui
from PySide import QtCore, QtGui

from .. import api, geometry
from ..core import CurvedSlicerError, InvalidInput
from ..objects import job as job_module
from .job_fields import (FileField, LinkSubField, ObjectCombo, QuantityField, VectorField,
                         candidate_objects, cell_problem, combo, degrees, enum_value,
                         document_ref, faces_problem, mm, object_ref, parse_faces,
                         selected_object_and_faces, single_shot_timer, spin, split_names)

LENGTH_LIMIT = 1000.0  # mm, the largest thickness, voxel, spacing the panel accepts
INT_MAX = 2 ** 31 - 1


def _form(parent):
    form = QtGui.QFormLayout(parent)
    form.setFieldGrowthPolicy(QtGui.QFormLayout.AllNonFixedFieldsGrow)
    form.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)  # labels above fields when narrow
    return form


def _scrolled(widget):
    """`widget` in a frameless scroll area: a tab never forces the combo view wider or
    taller; what does not fit scrolls."""
    area = QtGui.QScrollArea()
    area.setWidgetResizable(True)
    area.setFrameShape(QtGui.QFrame.NoFrame)
    area.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarAsNeeded)
    area.setWidget(widget)
    area.setMinimumHeight(360)  # the combo view is tall: show most of a tab at once
    return area


class TaskPanelJob:
    def __init__(self, job):
        self.job = job
        self.doc_name = job.Document.Name
        objects = candidate_objects(job)
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("CurvedSlicer Job")
        layout = QtGui.QVBoxLayout(self.form)
        self.status_label = QtGui.QLabel("Layers: %s\nPaths: %s" % (job.Status, job.PathsStatus))
        self.status_label.setWordWrap(True)
        layout.addWidget(self.status_label)
        self.tabs = QtGui.QTabWidget()
        self.tabs.setUsesScrollButtons(True)
        layout.addWidget(self.tabs, 1)
        self.tabs.addTab(_scrolled(self._model_tab(job, objects)), "Model")
        self.tabs.addTab(_scrolled(self._layers_tab(job)), "Layers")
        self.tabs.addTab(_scrolled(self._paths_tab(job, objects)), "Paths")
        self.tabs.addTab(_scrolled(self._robot_tab(job)), "Robot")

        self.error_label = QtGui.QLabel("")
        self.error_label.setObjectName("CurvedSlicerPanelError")
        self.error_label.setWordWrap(True)
        self.error_label.setStyleSheet("color: #b00000")
        layout.addWidget(self.error_label)
        self.run_button = QtGui.QPushButton("Run")
        self.run_button.setObjectName("CurvedSlicerPanelRun")
        self.run_button.setToolTip("Apply the values and compute the layers, paths and poses "
                                   "(progress with Cancel)")
        self.run_button.clicked.connect(self.run)
        layout.addWidget(self.run_button)

        self.initial = self.values()
        for field in self.quantity_fields():
            field.on_change(self.show_quantity_problem)
        for box in (self.plan_kind, self.start_mode, self.wall_edge, self.initial_path):
            box.currentIndexChanged.connect(self.update_enabled)
        self.solid.currentIndexChanged.connect(self.update_enabled)
        self.update_enabled()

        self.timer = single_shot_timer(400, self.update_estimate, self.form)
        self.voxel_size.on_change(self._estimate_soon)
        self.alignment.currentIndexChanged.connect(self._estimate_soon)
        self.memory.valueChanged.connect(self._estimate_soon)

    # -- tabs -----------------------------------------------------------------------------------
    def _model_tab(self, job, objects):
        tab = QtGui.QWidget()
        layout = QtGui.QVBoxLayout(tab)

        model = QtGui.QGroupBox("Model")
        f = _form(model)
        self.solid = ObjectCombo(objects, job.Solid)
        self.solid.setToolTip("The part to slice: a Part solid, a PartDesign Body or a closed "
                              "Mesh (ThinWall: optional, carried by the positioner model)")
        f.addRow("Solid", self.solid)
        self.plan_kind = combo(job_module.PLAN_KINDS, job.PlanKind)
        self.plan_kind.setToolTip("CurvedLayers: paths on curved layers grown from the start "
                                  "surface; ThinWall: one bead per layer on the wall surface")
        f.addRow("Plan kind", self.plan_kind)
        layout.addWidget(model)

        self.start_group = QtGui.QGroupBox("Start surface (curved layers)")
        f = _form(self.start_group)
        self.start_mode = combo(job_module.START_MODES, job.StartMode)
        f.addRow("Start", self.start_mode)
        faces = ",".join(s for (_, subs) in job.StartFaces for s in subs)
        self.start_faces = QtGui.QLineEdit(faces)
        self.start_faces.setToolTip("Faces of the solid, e.g. Face1,Face6 (Start Faces)")
        self.start_faces_pick = QtGui.QPushButton("From selection")
        self.start_faces_pick.setToolTip("Take the faces selected on the solid in the 3D view")
        self.start_faces_pick.clicked.connect(self.take_start_faces)
        row = QtGui.QHBoxLayout()
        row.addWidget(self.start_faces)
        row.addWidget(self.start_faces_pick)
        f.addRow("Start faces", row)
        self.start_surface = LinkSubField(objects, job.StartSurface, "start surface")
        f.addRow("Start surface", self.start_surface)
        self.start_point = VectorField(job.StartPlanePoint, " mm", "start plane point")
        f.addRow("Plane point", self.start_point)
        self.start_normal = VectorField(job.StartPlaneNormal, "")
        f.addRow("Plane normal", self.start_normal)
        layout.addWidget(self.start_group)

        self.wall_group = QtGui.QGroupBox("Thin wall")
        f = _form(self.wall_group)
        self.wall_surface = LinkSubField(objects, job.WallSurface, "wall surface")
        f.addRow("Wall surface", self.wall_surface)
        self.wall_edge = combo(job_module.WALL_EDGES, job.WallEdge)
        self.wall_edge.setToolTip("Lowest: the boundary loop lowest along the axis; Nearest: the "
                                  "loop nearest to the point")
        f.addRow("Start edge", self.wall_edge)
        self.wall_axis = VectorField(job.WallAxis, "")
        f.addRow("Up axis", self.wall_axis)
        self.wall_point = VectorField(job.WallPoint, " mm", "wall point")
        f.addRow("Point near edge", self.wall_point)
        layout.addWidget(self.wall_group)
        layout.addStretch(1)
        return tab

    def _layers_tab(self, job):
        tab = QtGui.QWidget()
        f = _form(tab)
        self.layer_thickness = QuantityField(mm(job.LayerThickness), "mm", "layer thickness",
                                             0.0, LENGTH_LIMIT, example="1.5 mm")
        self.layer_thickness.setToolTip("Layer thickness h (a length: 1.5 mm, 0.06 in, ...)")
        f.addRow("Layer thickness", self.layer_thickness.widget)
        self.voxel_size = QuantityField(mm(job.VoxelSize), "mm", "voxel size", 0.0, LENGTH_LIMIT,
                                        example="0.5 mm")
        self.voxel_size.setToolTip("Voxel edge length; time and memory grow as 1/L^3 (ThinWall: "
                                   "sets the tessellation of the wall surface)")
        f.addRow("Voxel size", self.voxel_size.widget)
        self.method = combo(job_module.METHODS, job.Method)
        f.addRow("Method", self.method)
        self.alignment = combo(job_module.ALIGNMENTS, job.GridAlignment)
        f.addRow("Grid alignment", self.alignment)
        self.cap_holes = QtGui.QCheckBox("Close holes of an open mesh")
        self.cap_holes.setChecked(job.CapHoles)
        f.addRow("", self.cap_holes)
        self.simplify_layers = QtGui.QCheckBox("Simplify layer surfaces")
        self.simplify_layers.setToolTip("Edge collapse within 0.05 x voxel size, the rim kept on "
                                        "the part; off: full marching-tetrahedra resolution")
        self.simplify_layers.setChecked(job.SimplifyLayers)
        f.addRow("", self.simplify_layers)
        self.deflection = QuantityField(mm(job.Deflection), "mm", "tessellation deflection",
                                        0.0, 100.0, exclusive_minimum=False,
                                        example="0.1 mm (0 = auto)")
        self.deflection.setToolTip("Chord error of the tessellation; 0 = auto (voxel size / 4)")
        f.addRow("Tessellation deflection", self.deflection.widget)
        self.memory = spin(float(job.MemoryBudget), 0.0, 1e7, 0, " MB", 100)
        self.memory.setSpecialValueText("auto (80 % of RAM)")
        f.addRow("Memory budget", self.memory)
        self.estimate_label = QtGui.QLabel("")
        self.estimate_label.setWordWrap(True)
        self.estimate_button = QtGui.QPushButton("Estimate voxels and memory")
        self.estimate_button.clicked.connect(self.update_estimate)
        f.addRow(self.estimate_button, self.estimate_label)
        return tab

    def _paths_tab(self, job, objects):
        tab = QtGui.QWidget()
        tab.setToolTip("Bead paths on every layer (paper 3.1); a change replans the paths "
                       "without rerunning the layers")
        f = _form(tab)
        self.bead_spacing = QuantityField(mm(job.BeadSpacing), "mm", "bead spacing", 0.0,
                                          LENGTH_LIMIT, example="3.7 mm")
        f.addRow("Bead spacing", self.bead_spacing.widget)
        self.point_spacing = QuantityField(mm(job.PointSpacing), "mm", "point spacing", 0.0,
                                           LENGTH_LIMIT, example="2 mm")
        f.addRow("Point spacing", self.point_spacing.widget)
        self.fit_tolerance = QuantityField(float(job.FitTolerance), "mm", "fit tolerance", 0.0,
                                           100.0, example="0.05 mm")
        f.addRow("Fit tolerance", self.fit_tolerance.widget)
        self.corner_angle = QuantityField(degrees(job.CornerAngle), "deg", "corner angle", 0.0,
                                          180.0, example="30°")
        self.corner_angle.setToolTip("Where a path turns by more than this within 0.2 mm, the "
                                     "spline fit keeps the raw vertex as an exact corner; 180 "
                                     "keeps none (every path one smooth spline)")
        f.addRow("Corner angle", self.corner_angle.widget)
        self.surface_method = combo(job_module.SURFACE_METHODS, job.SurfaceMethod)
        self.surface_method.setToolTip("Surface geodesic field: Accurate, or Paper (the paper's "
                                       "search, eq. 15)")
        f.addRow("Surface method", self.surface_method)
        self.deposition_direction = combo(job_module.DEPOSITION_DIRECTIONS,
                                          job.DepositionDirection)
        self.deposition_direction.setToolTip(
            "Deposition direction V, turned onto gravity by the positioner: Growth keeps the "
            "paper's V (towards the nearest deposited point) within 30 degrees of the layer's "
            "growth direction, else takes that direction; Nearest keeps the paper's V everywhere")
        f.addRow("Deposition direction", self.deposition_direction)
        self.path_display = combo(job_module.PATH_DISPLAYS, job.PathDisplay)
        f.addRow("Display", self.path_display)
        self.initial_group = QtGui.QGroupBox("Initial path (curved layers)")
        g = _form(self.initial_group)
        self.initial_path = combo(job_module.INITIAL_PATHS, job.InitialPath)
        self.initial_path.setToolTip("Boundary: contour-parallel paths; Plane / Surface: the "
                                     "section of every layer with it is the first path")
        g.addRow("Initial path", self.initial_path)
        self.narrow_strips = combo(job_module.NARROW_STRIPS, job.NarrowStrips)
        self.narrow_strips.setToolTip("Where paths of one level come closer than 0.95 x bead "
                                      "spacing: CentreBead puts one bead on the strip's centre "
                                      "line (reported per layer); Overlap keeps the paths")
        g.addRow("Narrow strips", self.narrow_strips)
        self.initial_point = VectorField(job.InitialPlanePoint, " mm", "initial plane point")
        g.addRow("Plane point", self.initial_point)
        self.initial_normal = VectorField(job.InitialPlaneNormal, "")
        g.addRow("Plane normal", self.initial_normal)
        self.initial_surface = LinkSubField(objects, job.InitialSurface, "initial surface")
        g.addRow("Surface", self.initial_surface)
        f.addRow(self.initial_group)
        self.coverage_group = QtGui.QGroupBox("Bead coverage (curved layers)")
        c = _form(self.coverage_group)
        self.min_feature_width = QuantityField(mm(job.MinFeatureWidth), "mm",
                                               "minimum feature width", 0.0, LENGTH_LIMIT,
                                               example="1.85 mm")
        self.min_feature_width.setToolTip("Regions narrower than one bead but at least this wide "
                                          "get a single centre bead; narrower ones are left out "
                                          "and reported")
        c.addRow("Min. width", self.min_feature_width.widget)
        self.bead_width_min = spin(float(job.BeadWidthMin), 0.0, 1.0, 2, "", 0.05)
        self.bead_width_min.setToolTip("Adaptive bead width: smallest width as a fraction of "
                                       "the bead spacing, in (0, 1] (1 and 1: fixed width)")
        c.addRow("Width min", self.bead_width_min)
        self.bead_width_max = spin(float(job.BeadWidthMax), 1.0, 100.0, 2, "", 0.05)
        self.bead_width_max.setToolTip("Adaptive bead width: largest width as a fraction of the "
                                       "bead spacing")
        c.addRow("Width max", self.bead_width_max)
        self.connect_insets = QtGui.QCheckBox("Connect insets")
        self.connect_insets.setToolTip("Join consecutive rings of one region with a short "
                                       "step-over into one arc-on path")
        self.connect_insets.setChecked(job.ConnectInsets)
        c.addRow(self.connect_insets)
        self.fill_gaps = QtGui.QCheckBox("Fill gaps between beads")
        self.fill_gaps.setToolTip("A bead on the centre line of every uncovered strip between "
                                  "beads at least the minimum feature width wide")
        self.fill_gaps.setChecked(job.FillGaps)
        c.addRow(self.fill_gaps)
        self.min_gap_area = spin(float(job.MinGapArea), 0.01, 1e6, 2, " mm²", 1.0)
        self.min_gap_area.setToolTip("Gap fill: the smallest uncovered patch that gets a fill "
                                     "bead; smaller patches stay empty (default: bead spacing "
                                     "squared)")
        c.addRow("Min. gap area", self.min_gap_area)
        self.corner_fill = QtGui.QCheckBox("Fill corners")
        self.corner_fill.setToolTip("The outer ring dips toward convex corners sharper than the "
                                    "corner-fill angle, its bead's edge at most a quarter of the "
                                    "bead spacing past the part's edge")
        self.corner_fill.setChecked(job.CornerFill)
        c.addRow(self.corner_fill)
        self.corner_fill_angle = spin(float(job.CornerFillAngle), 1.0, 179.0, 1, "°", 5.0)
        self.corner_fill_angle.setToolTip("Corner fill takes corners of the layer boundary "
                                          "sharper than this (default 85°: acute corners)")
        c.addRow("Corner-fill angle", self.corner_fill_angle)
        self.measure_coverage = QtGui.QCheckBox("Measure coverage")
        self.measure_coverage.setToolTip("Void and overlap share of every layer (the path "
                                         "layers' VoidShare / OverlapShare)")
        self.measure_coverage.setChecked(job.MeasureCoverage)
        c.addRow(self.measure_coverage)
        f.addRow(self.coverage_group)
        return tab

    def _robot_tab(self, job):
        tab = QtGui.QWidget()
        f = _form(tab)
        self.cell_file = FileField(job.CellFile, "Robot cell file",
                                   "Cell JSON (*.json);;All files (*)")
        self.cell_file.edit.setPlaceholderText("the paper's cell (Motoman HP20D)")
        self.cell_file.setToolTip("Robot cell description (JSON); empty = the paper's cell")
        self.cell_file.on_change.append(self.update_cell_status)
        f.addRow("Cell file", self.cell_file)
        self.cell_status = QtGui.QLabel("")
        self.cell_status.setWordWrap(True)
        f.addRow("", self.cell_status)
        self.tool_along_travel = QtGui.QCheckBox("Torch x along the travel")
        self.tool_along_travel.setToolTip("Torch x axis along the travel direction. Off: the "
                                          "torch orientation stays fixed while the positioner "
                                          "turns the part (no wrist wind-up)")
        self.tool_along_travel.setChecked(job.ToolAlongTravel)
        f.addRow(self.tool_along_travel)
        self.part_placement = combo(job_module.PART_PLACEMENTS, job.PartPlacement)
        self.part_placement.setToolTip("Rest: the part's lowest bead bottom on the table top "
                                       "(the cell's table_to_part rotation and xy); Cell: the "
                                       "cell's table_to_part as given")
        f.addRow("Placement", self.part_placement)
        self.clearance = QuantityField(mm(job.Clearance), "mm", "clearance", 0.0, LENGTH_LIMIT,
                                       exclusive_minimum=False, example="10 mm")
        self.clearance.setToolTip("Arc-off moves travel this high above the part and the "
                                  "deposit (leaving and approaching along the torch's axis)")
        f.addRow("Clearance", self.clearance.widget)
        self.add_home = QtGui.QCheckBox("Start and end at home")
        self.add_home.setToolTip("Start and end the program at the cell's home pose")
        self.add_home.setChecked(job.AddHome)
        f.addRow(self.add_home)
        self.allow_collisions = QtGui.QCheckBox("Allow collisions")
        self.allow_collisions.setToolTip("Remaining collisions become warnings. Off: a collision "
                                         "of torch or positioner with the part or the deposit "
                                         "after re-routing is an error")
        self.allow_collisions.setChecked(job.AllowCollisions)
        f.addRow(self.allow_collisions)
        self.merge_tolerance = QuantityField(mm(job.MergeTolerance), "mm", "merge tolerance", 0.0,
                                             100.0, exclusive_minimum=False, example="0.01 mm")
        self.merge_tolerance.setToolTip("Consecutive path points closer than this are merged")
        f.addRow("Merge tolerance", self.merge_tolerance.widget)
        self.max_a2_step = QuantityField(degrees(job.MaxA2Step), "deg", "maximum a2 step", 0.0,
                                         180.0, example="5°")
        self.max_a2_step.setToolTip("Largest turn of the table rotation a2 between consecutive "
                                    "points of a weld; points are inserted where it turns faster")
        f.addRow("Max a2 step", self.max_a2_step.widget)
        self.pose_point = QtGui.QSpinBox()
        count = int(job.PoseCount)
        self.pose_point.setRange(0, count - 1 if count > 0 else INT_MAX)
        self.pose_point.setValue(int(job.PosePoint))
        self.pose_point.setToolTip("Motion point (0-based, execution order) the positioner model "
                                   "shows; %s" % ("%d points planned" % count if count else
                                                  "no plan yet (clamped when planned)"))
        f.addRow("Pose point", self.pose_point)
        self.update_cell_status()
        return tab

    # -- modes ----------------------------------------------------------------------------------
    def update_enabled(self, *args):
        """Enables the fields the chosen plan kind, start mode, wall edge and initial path use."""
        curved = self.plan_kind.currentText() == "CurvedLayers"
        mode = self.start_mode.currentText()
        self.start_group.setEnabled(curved)
        self.start_faces.setEnabled(mode == "Faces")
        self.start_faces_pick.setEnabled(mode == "Faces")
        self.start_surface.setEnabled(mode == "Surface")
        self.start_point.setEnabled(mode == "Plane")
        self.start_normal.setEnabled(mode == "Plane")
        self.wall_group.setEnabled(not curved)
        lowest = self.wall_edge.currentText() == "Lowest"
        self.wall_axis.setEnabled(lowest)
        self.wall_point.setEnabled(not lowest)
        for w in (self.layer_thickness, self.method, self.alignment, self.cap_holes,
                  self.simplify_layers, self.memory, self.estimate_button):
            w.setEnabled(curved)
        if not curved:
            self.estimate_label.setText("no voxel grid: a thin wall is planned on its surface")
        initial = self.initial_path.currentText()
        self.initial_group.setEnabled(curved)
        self.coverage_group.setEnabled(curved)
        self.initial_point.setEnabled(initial == "Plane")
        self.initial_normal.setEnabled(initial == "Plane")
        self.initial_surface.setEnabled(initial == "Surface")

    def take_start_faces(self):
        """Start faces from the 3D selection (faces picked on the panel's solid)."""
        obj, faces = selected_object_and_faces()
        if obj is None or not faces:
            self.error_label.setText("no faces selected: pick the start faces on the solid in "
                                     "the 3D view, then press From selection")
            return False
        self.solid.set_object(obj)
        self.start_faces.setText(",".join(faces))
        return True

    def update_cell_status(self):
        problem = cell_problem(self.cell_file.text())
        self.cell_status.setStyleSheet("color: #b00000" if problem else "")
        self.cell_status.setText(problem or ("valid cell file" if self.cell_file.text() else
                                             "the paper's cell (Motoman HP20D, tilt-rotate "
                                             "positioner)"))
        return problem

    # -- estimate -------------------------------------------------------------------------------
    def _estimate_soon(self, *args):
        self.timer.start()

    def solid_object(self):
        name = self.solid.name()
        return self.job.Document.getObject(name) if name else None

    def estimate(self):
        """The estimate for the values in the panel (dict as api.estimate) or raises."""
        return api.estimate(self.job, voxel_size=self.voxel_size.value(),
                            grid_alignment=self.alignment.currentText(),
                            memory_budget_mb=float(self.memory.value()),
                            deflection=self.deflection.value(), solid=self.solid_object(),
                            cap_holes=self.cap_holes.isChecked())

    def update_estimate(self):
        if self.plan_kind.currentText() != "CurvedLayers":
            return None
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

    # -- quantities -----------------------------------------------------------------------------
    def quantity_fields(self):
        """Every length and angle field of the panel (vector coordinates included)."""
        fields = [self.layer_thickness, self.voxel_size, self.deflection, self.bead_spacing,
                  self.point_spacing, self.fit_tolerance, self.corner_angle, self.clearance,
                  self.merge_tolerance, self.max_a2_step]
        for vector in (self.start_point, self.wall_point, self.initial_point):
            fields.extend(vector.boxes)
        return fields

    def quantity_problems(self):
        """[(message, widget)] of the enabled length and angle fields whose text is not
        understood or out of range."""
        found = []
        for field in self.quantity_fields():
            if field.widget.isEnabled():
                message = field.problem()
                if message:
                    found.append((message, field.widget))
        return found

    def show_quantity_problem(self, *args):
        """While typing: the first length or angle the panel would refuse, or nothing."""
        found = self.quantity_problems()
        self.error_label.setText(found[0][0] if found else "")

    # -- values ---------------------------------------------------------------------------------
    def _start_faces_value(self):
        return (self.solid.name(), split_names(self.start_faces.text()))

    def values(self):
        """{property: (comparable value, macro expression)} of the panel (face lists as
        entered; validate() checks them)."""
        d = self.doc_name
        solid = self.solid.name()
        faces = self._start_faces_value()
        v = {
            "Solid": (solid, object_ref(d, solid) if solid else "None"),
            "PlanKind": self.plan_kind.currentText(),
            "StartMode": self.start_mode.currentText(),
            "StartFaces": (faces, "[(%s, %r)]" % (object_ref(d, solid), faces[1])
                           if solid and faces[1] else "[]"),
            "StartSurface": (self.start_surface.value(), self.start_surface.code(d)),
            "StartPlanePoint": self.start_point,
            "StartPlaneNormal": self.start_normal,
            "LayerThickness": self.layer_thickness.value(),
            "VoxelSize": self.voxel_size.value(),
            "Method": self.method.currentText(),
            "GridAlignment": self.alignment.currentText(),
            "CapHoles": self.cap_holes.isChecked(),
            "SimplifyLayers": self.simplify_layers.isChecked(),
            "Deflection": self.deflection.value(),
            "MemoryBudget": self.memory.value(),
            "WallSurface": (self.wall_surface.value(), self.wall_surface.code(d)),
            "WallEdge": self.wall_edge.currentText(),
            "WallAxis": self.wall_axis,
            "WallPoint": self.wall_point,
            "BeadSpacing": self.bead_spacing.value(),
            "PointSpacing": self.point_spacing.value(),
            "FitTolerance": self.fit_tolerance.value(),
            "CornerAngle": self.corner_angle.value(),
            "InitialPath": self.initial_path.currentText(),
            "InitialPlanePoint": self.initial_point,
            "InitialPlaneNormal": self.initial_normal,
            "InitialSurface": (self.initial_surface.value(), self.initial_surface.code(d)),
            "SurfaceMethod": self.surface_method.currentText(),
            "DepositionDirection": self.deposition_direction.currentText(),
            "NarrowStrips": self.narrow_strips.currentText(),
            "MinFeatureWidth": self.min_feature_width.value(),
            "BeadWidthMin": self.bead_width_min.value(),
            "BeadWidthMax": self.bead_width_max.value(),
            "ConnectInsets": self.connect_insets.isChecked(),
            "FillGaps": self.fill_gaps.isChecked(),
            "MinGapArea": self.min_gap_area.value(),
            "CornerFill": self.corner_fill.isChecked(),
            "CornerFillAngle": self.corner_fill_angle.value(),
            "MeasureCoverage": self.measure_coverage.isChecked(),
            "PathDisplay": self.path_display.currentText(),
            "CellFile": self.cell_file.text(),
            "ToolAlongTravel": self.tool_along_travel.isChecked(),
            "PartPlacement": self.part_placement.currentText(),
            "Clearance": self.clearance.value(),
            "AddHome": self.add_home.isChecked(),
            "AllowCollisions": self.allow_collisions.isChecked(),
            "MergeTolerance": self.merge_tolerance.value(),
            "MaxA2Step": self.max_a2_step.value(),
            "PosePoint": self.pose_point.value(),
        }
        for name, value in v.items():
            if isinstance(value, VectorField):
                v[name] = (value.value(), value.code())
            elif not isinstance(value, tuple):
                v[name] = (value, repr(value))
        return v

    # -- validation -----------------------------------------------------------------------------
    def problems(self):
        """[(message, widget)] of what the panel would set wrongly, most basic first."""
        found = self.quantity_problems()
        doc = self.job.Document
        curved = self.plan_kind.currentText() == "CurvedLayers"
        solid = self.solid_object()
        if curved:
            try:
                if not geometry.is_mesh_object(solid):
                    geometry.solid_shape(solid)
            except InvalidInput as error:
                found.append(("%s; or choose Plan kind ThinWall" % error, self.solid))
        mode = self.start_mode.currentText()
        try:
            faces = parse_faces(self.start_faces.text())
        except ValueError as error:
            found.append(("start face not understood: %s; enter faces as Face1,Face6, or pick "
                          "them and press From selection" % error, self.start_faces))
            faces = None
        if curved and mode == "Faces" and faces is not None:
            if not faces:
                found.append(("no start faces: the list is empty; enter faces such as Face1 "
                              "(or pick them and press From selection) or choose another start",
                              self.start_faces))
            elif solid is not None and geometry.is_mesh_object(solid):
                found.append(("start faces on a mesh: %s is a mesh; use Start Surface with a "
                              "separate surface object, or Plane" % solid.Label,
                              self.start_faces))
            elif solid is not None:
                problem = faces_problem("start face", solid, faces)
                if problem:
                    found.append((problem, self.start_faces))
        problem = self.start_surface.problem(doc, curved and mode == "Surface")
        if not problem and curved and mode == "Surface" and \
                self.start_surface.object.name() == self.solid.name():
            problem = ("start surface is the solid itself: %s; use Start Faces to grow from "
                       "faces of the solid" % solid.Label)
        if problem:
            found.append((problem, self.start_surface))
        if curved and mode == "Plane" and self.start_normal.is_zero():
            found.append(("start plane normal is zero: (0, 0, 0); enter the normal towards the "
                          "part, e.g. (0, 0, 1)", self.start_normal))
        problem = self.wall_surface.problem(doc, not curved)
        if problem:
            found.append((problem, self.wall_surface))
        if not curved and self.wall_edge.currentText() == "Lowest" and self.wall_axis.is_zero():
            found.append(("wall axis is zero: (0, 0, 0); enter the up direction, e.g. (0, 0, 1)",
                          self.wall_axis))
        initial = self.initial_path.currentText()
        if curved and initial == "Plane" and self.initial_normal.is_zero():
            found.append(("initial plane normal is zero: (0, 0, 0); enter the plane's normal, "
                          "e.g. (1, 0, 0)", self.initial_normal))
        problem = self.initial_surface.problem(doc, curved and initial == "Surface")
        if problem:
            found.append((problem, self.initial_surface))
        problem = cell_problem(self.cell_file.text())
        if problem:
            found.append((problem, self.cell_file))
        return found

    def validate(self):
        """"" or the first problem's message (its tab is brought forward)."""
        found = self.problems()
        if not found:
            return ""
        message, widget = found[0]
        widget = getattr(widget, "widget", widget)  # a QuantityField's box
        for i in range(self.tabs.count()):
            if self.tabs.widget(i).isAncestorOf(widget):
                self.tabs.setCurrentIndex(i)
        widget.setFocus()
        return message

    # -- apply ----------------------------------------------------------------------------------
    def commands(self):
        """The doCommand lines that assign the properties the user changed (nothing runs)."""
        j = object_ref(self.doc_name, self.job.Name)
        current = self.values()
        return ["%s.%s = %s" % (j, name, code) for (name, (value, code)) in current.items()
                if value != self.initial[name][0]]

    def apply(self):
        """Validates, then applies the changed values in one transaction. True if applied."""
        problem = self.validate()
        if problem:
            self.error_label.setText(problem)
            return False
        lines = self.commands()
        self.error_label.setText("")
        if lines:
            doc = self.job.Document
            doc.openTransaction("Edit CurvedSlicer Job")
            try:
                for line in lines:
                    FreeCADGui.doCommand(line)
            finally:
                doc.commitTransaction()
            self.initial = self.values()
        self.update_status()
        return True

    def update_status(self):
        self.status_label.setText("Layers: %s\nPaths: %s" % (self.job.Status,
                                                             self.job.PathsStatus))
        count = int(self.job.PoseCount)
        self.pose_point.setRange(0, count - 1 if count > 0 else INT_MAX)

    def run(self):
        """The Run button: applies the values (nothing runs when one is refused), then runs the
        Job with the progress dialog, recorded as api.run; the panel stays open. True when the
        run succeeded."""
        if not self.apply():
            return False
        from ..commands.job_commands import run_selected_job

        ok = run_selected_job(self.job)
        self.update_status()
        self.initial = self.values()
        return ok

    def accept(self):
        if not self.apply():
            return False
        self.close()
        return True

    def reject(self):
        self.close()
        return True

    def close(self):
        """Closes the panel, recorded as Gui.getDocument(...).resetEdit()."""
        FreeCADGui.doCommand("%s.resetEdit()" % document_ref(self.doc_name, "Gui"))

    def clicked(self, button):
        if enum_value(button) == enum_value(QtGui.QDialogButtonBox.Apply):
            self.apply()

    def getStandardButtons(self):
        return (QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Apply |
                QtGui.QDialogButtonBox.Cancel)
