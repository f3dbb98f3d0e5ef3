"""Editors of the Job task panel (GUI only): lengths and angles in FreeCAD's own unit-aware
Gui::QuantitySpinBox ("1 in" is 25.4 mm, "2*0.5 mm" is 1 mm), plain number spin boxes,
enumeration combo boxes, vectors (three boxes stacked), links to another object's faces (object
combo box, face list, "From selection"), and the checks behind them (quantities out of range or
not understood, face lists, cell files).

Every editor reports its value as a plain Python value (float, str, tuple) so the panel can tell
what the user changed, and formats it as the Python expression a macro assigns to the property.
Qt5 and Qt6 through FreeCAD's PySide shim only. Cheap: no computation beyond reading a cell
file (the core's validating reader, milliseconds)."""

import os
import re

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from ..core import CurvedSlicerError, native

FACE_NAME = re.compile(r"^Face([1-9][0-9]*)$")
COORDINATE_LIMIT = 1e6  # mm and direction components the vector editors accept
QUANTITY_LIMIT = 1e12  # the quantity boxes' own range: wide, the fields check their ranges


def mm(quantity):
    """A length property (Quantity or float) in mm."""
    return float(FreeCAD.Units.Quantity(quantity).getValueAs("mm"))


def degrees(quantity):
    """An angle property (Quantity or float) in degrees."""
    return float(FreeCAD.Units.Quantity(quantity).getValueAs("deg"))


def enum_value(value):
    """The integer of a Qt enumeration member on PySide2 (int subclass) and PySide6 (Enum)."""
    return int(getattr(value, "value", value))


def spin(value, minimum, maximum, decimals=3, suffix=" mm", step=0.1):
    """A QDoubleSpinBox showing `value` with a unit suffix (" mm", " MB", "" for none)."""
    box = QtGui.QDoubleSpinBox()
    box.setDecimals(decimals)
    box.setRange(minimum, maximum)
    box.setSingleStep(step)
    box.setSuffix(suffix)
    box.setValue(value)
    return box


class QuantityField:
    """A length (`unit` "mm") or angle ("deg") in a Gui::QuantitySpinBox (FreeCAD's unit-aware
    spin box: units, arithmetic, the user's unit schema). The box itself accepts any value, so
    a value out of range stays visible and `problem()` names it ("layer thickness must be
    positive: 0 mm; ..."); text the box cannot read ("abc", "5 deg" for a length) is a problem
    too, instead of silently keeping the previous value. `widget` is the QWidget to lay out."""

    def __init__(self, value, unit, what, minimum=None, maximum=None, exclusive_minimum=True,
                 example="1.5 mm"):
        self.unit, self.what, self.example = unit, what, example
        self.minimum, self.maximum = minimum, maximum
        self.exclusive_minimum = exclusive_minimum
        self.widget = FreeCADGui.UiLoader().createWidget("Gui::QuantitySpinBox")
        self.widget.setProperty("unit", unit)
        self.widget.setProperty("minimum", -QUANTITY_LIMIT)
        self.widget.setProperty("maximum", QUANTITY_LIMIT)
        self.widget.setProperty("singleStep", 1.0 if unit == "deg" else 0.1)
        self.widget.setMinimumWidth(80)
        # The box's line edit as a child widget (QAbstractSpinBox.lineEdit() is protected).
        self.edit = self.widget.findChild(QtGui.QLineEdit)
        self.set_value(value)

    def __getattr__(self, name):  # setEnabled, isEnabled, setToolTip, setFocus, ...
        return getattr(self.widget, name)

    def text(self):
        return self.edit.text()

    def set_text(self, text):
        """Types `text` into the box (as the user would)."""
        self.edit.setText(text)

    def set_value(self, value):
        self.widget.setProperty("rawValue", float(value))

    setValue = set_value

    def value(self):
        """The value in `unit` (mm or degrees) the box holds (its last readable text); a
        formula typed as "=2*0.5 mm" is evaluated (the box itself reads "=" only when bound to
        a property)."""
        if self.text().strip().startswith("="):
            value, message = self._read()
            if message is None:
                return value
        return float(self.widget.property("rawValue"))

    def on_change(self, slot):
        self.edit.textChanged.connect(slot)

    def _read(self):
        """(value in `unit`, None) of the text, or (None, message) when it is not a quantity of
        this kind."""
        text = self.text().strip()
        formula = text[1:].strip() if text.startswith("=") else text
        dimension = FreeCAD.Units.Length if self.unit == "mm" else FreeCAD.Units.Angle
        kind = "length" if self.unit == "mm" else "angle"
        try:
            q = FreeCAD.Units.Quantity(formula)
        except (ValueError, ArithmeticError):
            q = None
        if q is None or not (q.Unit == dimension or q.Unit == FreeCAD.Units.Unit()):
            return None, ("%s not understood: %r; enter a %s such as %s" % (
                self.what, text, kind, self.example))
        if q.Unit == FreeCAD.Units.Unit():
            return float(q.Value), None
        return float(q.getValueAs(self.unit)), None

    def problem(self):
        """"" or "<what> must be ...: <value>; enter ..." for text that is unreadable or out of
        range."""
        value, message = self._read()
        if message:
            return message
        shown = "%g %s" % (value, "°" if self.unit == "deg" else self.unit)
        low = self.minimum
        if low is not None and (value <= low if self.exclusive_minimum else value < low):
            if low == 0:
                need = "positive" if self.exclusive_minimum else "zero or positive"
            else:
                need = "%s %g %s" % ("above" if self.exclusive_minimum else "at least", low,
                                     self.unit)
            return "%s must be %s: %s; enter e.g. %s" % (self.what, need, shown, self.example)
        if self.maximum is not None and value > self.maximum:
            return "%s too large: %s (at most %g %s); enter e.g. %s" % (
                self.what, shown, self.maximum, self.unit, self.example)
        return ""


def combo(items, current):
    """A QComboBox of an enumeration with `current` selected (the first item if unknown)."""
    box = QtGui.QComboBox()
    box.addItems(items)
    box.setCurrentIndex(items.index(current) if current in items else 0)
    return box


def split_names(text):
    """("Face1", "Face6") of a comma or space separated list, unchecked."""
    return tuple(s for s in re.split(r"[,\s]+", text.strip()) if s)


def parse_faces(text):
    """split_names(text); raises ValueError naming the first entry that is not FaceN."""
    names = split_names(text)
    for name in names:
        if not FACE_NAME.match(name):
            raise ValueError(name)
    return tuple(names)


def face_count(obj):
    """Number of faces of a shape object, or None for an object without a shape (a mesh)."""
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull():
        return None
    return len(shape.Faces)


def faces_problem(what, obj, faces):
    """"" if `faces` (FaceN names) exist on `obj`, else a message saying which face and what to
    do. `what` names the field, e.g. "start face"."""
    if not faces:
        return ""
    count = face_count(obj)
    if count is None:
        return ("%s on an object without faces: %s of %s; clear the face list to use the whole "
                "object" % (what, ", ".join(faces), obj.Label))
    for name in faces:
        if int(FACE_NAME.match(name).group(1)) > count:
            return ("%s not on the object: %s (%s has %d faces); pick faces of %s again"
                    % (what, name, obj.Label, count, obj.Label))
    return ""


def cell_problem(path):
    """"" if `path` is empty (the paper's cell) or a cell file the core reads, else a message
    naming the file, what is wrong with it and what to do."""
    if not path:
        return ""
    if not os.path.isfile(path):
        return ("cell file does not exist: %s; choose an existing cell JSON (Browse…, e.g. "
                "resources/cells/motoman_hp20d_tilt_rotate.json of the project) or clear the "
                "field for the paper's cell (Motoman HP20D with a tilt-rotate positioner)" % path)
    try:
        native.read_cell_json(path)
    except CurvedSlicerError as error:
        return ("cell file not usable: %s: %s; or choose another cell JSON (Browse…), or clear "
                "the field for the paper's cell" % (path, error))
    return ""


def document_ref(doc_name, module="App"):
    """The macro expression of a document: App.ActiveDocument (Gui.ActiveDocument) when it is the
    active one, so a recorded macro replays into a document of another name; else by name."""
    active = FreeCAD.ActiveDocument
    if active is not None and active.Name == doc_name:
        return "%s.ActiveDocument" % module
    return "%s.getDocument(%r)" % (module, doc_name)


def object_ref(doc_name, obj_name):
    """The macro expression of a document object (in the active document: through
    App.ActiveDocument, see document_ref)."""
    return "%s.getObject(%r)" % (document_ref(doc_name), obj_name)


def candidate_objects(job):
    """Objects a Job may link as its solid or a surface: Part shapes, PartDesign Bodies and
    meshes of the document, except Jobs and the objects Jobs made (layers, paths, poses)."""
    from ..objects.job import is_job

    doc = job.Document
    made = set()
    for o in doc.Objects:
        if is_job(o):
            made.add(o.Name)
            stack = list(o.Group)
            while stack:
                child = stack.pop()
                if child.Name in made:
                    continue
                made.add(child.Name)
                stack.extend(getattr(child, "Group", []) or [])
    return [o for o in doc.Objects if o.Name not in made and (
        o.isDerivedFrom("Part::Feature") or o.isDerivedFrom("Mesh::Feature"))]


class ObjectCombo(QtGui.QComboBox):
    """A combo box of document objects; "(none)" first. `name()` is the chosen object's Name or
    "" for none."""

    def __init__(self, objects, current=None):
        super().__init__()
        self.names = [""]
        self.addItem("(none)")
        for o in objects:
            self.add_object(o)
        if current is not None:
            self.set_object(current)

    def add_object(self, obj):
        if obj.Name in self.names:
            return
        self.names.append(obj.Name)
        self.addItem(obj.Label if obj.Label == obj.Name else "%s (%s)" % (obj.Label, obj.Name))

    def set_object(self, obj):
        """Selects `obj` (added to the list if it is not there); None selects "(none)"."""
        if obj is None:
            self.setCurrentIndex(0)
            return
        self.add_object(obj)
        self.setCurrentIndex(self.names.index(obj.Name))

    def name(self):
        return self.names[max(self.currentIndex(), 0)]


class VectorField(QtGui.QWidget):
    """Three boxes x, y, z stacked (narrow enough for the combo view): a point in mm (`unit`
    " mm", unit-aware quantity boxes) or a direction (`unit` "", plain spin boxes)."""

    def __init__(self, vector, unit=" mm", what="point"):
        super().__init__()
        form = QtGui.QFormLayout(self)
        form.setContentsMargins(0, 0, 0, 0)
        self.boxes = []
        for axis, v in zip("xyz", (vector.x, vector.y, vector.z)):
            if unit:
                box = QuantityField(float(v), "mm", "%s %s" % (what, axis),
                                    maximum=COORDINATE_LIMIT, example="12.5 mm")
                widget = box.widget
            else:
                box = widget = spin(float(v), -COORDINATE_LIMIT, COORDINATE_LIMIT, 4, "", 0.1)
            widget.setToolTip(axis)
            self.boxes.append(box)
            form.addRow(axis, widget)

    def value(self):
        return tuple(b.value() for b in self.boxes)

    def set_value(self, xyz):
        for b, v in zip(self.boxes, xyz):
            b.setValue(float(v))

    def problem(self):
        """"" or the first coordinate that is not understood or beyond COORDINATE_LIMIT."""
        for b in self.boxes:
            if isinstance(b, QuantityField):
                message = b.problem()
                if not message and b.value() < -COORDINATE_LIMIT:
                    message = "%s too small: %g mm (at least %g mm)" % (b.what, b.value(),
                                                                       -COORDINATE_LIMIT)
                if message:
                    return message
        return ""

    def is_zero(self):
        return all(v == 0.0 for v in self.value())

    def code(self):
        return "App.Vector(%r, %r, %r)" % self.value()


def selected_object_and_faces():
    """(object, (FaceN, ...)) of the first entry of the 3D selection, or (None, ())."""
    selection = FreeCADGui.Selection.getSelectionEx()
    if not selection:
        return None, ()
    first = selection[0]
    return first.Object, tuple(n for n in first.SubElementNames if FACE_NAME.match(n))


class LinkSubField(QtGui.QWidget):
    """A link to (some faces of) an object: object combo box, face list (empty = the whole
    object) and a button taking both from the 3D selection. value() is (Name, (faces...)) or
    ("", ()) for no link."""

    def __init__(self, objects, link, what):
        super().__init__()
        self.what = what
        obj, subs = (link[0], tuple(link[1])) if link else (None, ())
        layout = QtGui.QGridLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        self.object = ObjectCombo(objects, obj)
        self.faces = QtGui.QLineEdit(",".join(subs))
        self.faces.setPlaceholderText("all faces")
        self.faces.setToolTip("Faces of the object, e.g. Face1,Face3; empty = the whole object")
        self.pick = QtGui.QPushButton("From selection")
        self.pick.setToolTip("Take the object and faces selected in the 3D view")
        self.pick.clicked.connect(self.take_selection)
        layout.addWidget(self.object, 0, 0, 1, 2)
        layout.addWidget(self.faces, 1, 0)
        layout.addWidget(self.pick, 1, 1)

    def take_selection(self):
        obj, faces = selected_object_and_faces()
        if obj is None:
            return False
        self.object.set_object(obj)
        self.faces.setText(",".join(faces))
        return True

    def value(self):
        """(object Name, face names as entered); ("", ()) for no object."""
        name = self.object.name()
        return (name, split_names(self.faces.text()) if name else ())

    def problem(self, doc, required):
        """"" or a message: face names not FaceN, faces missing on the object, or (if
        `required`) no object."""
        name = self.object.name()
        try:
            faces = parse_faces(self.faces.text()) if name else ()
        except ValueError as error:
            return ("%s face not understood: %s; enter faces as Face1,Face3, or pick them and "
                    "press From selection" % (self.what, error))
        if not name:
            return ("no %s: none chosen; choose the object (and faces), e.g. pick them and press "
                    "From selection" % self.what) if required else ""
        return faces_problem(self.what + " face", doc.getObject(name), faces)

    def code(self, doc_name):
        name, faces = self.value()
        if not name:
            return "None"
        return "(%s, %r)" % (object_ref(doc_name, name), list(faces))


class FileField(QtGui.QWidget):
    """A file path with a Browse… button (JSON filter)."""

    def __init__(self, path, title, file_filter):
        super().__init__()
        self.title = title
        self.file_filter = file_filter
        self.on_change = []  # callables run after editing finished or a file was chosen
        row = QtGui.QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        self.edit = QtGui.QLineEdit(path)
        self.browse = QtGui.QPushButton("Browse…")
        self.browse.clicked.connect(self.choose)
        self.edit.editingFinished.connect(self._changed)
        row.addWidget(self.edit)
        row.addWidget(self.browse)

    def text(self):
        return self.edit.text().strip()

    def choose(self):
        start = os.path.dirname(self.text()) if self.text() else os.path.expanduser("~")
        chosen = QtGui.QFileDialog.getOpenFileName(self, self.title, start, self.file_filter)
        path = chosen[0] if isinstance(chosen, (tuple, list)) else chosen
        if path:
            self.set_text(path)
        return path

    def set_text(self, path):
        self.edit.setText(path)
        self._changed()

    def _changed(self):
        for callback in self.on_change:
            callback()


def single_shot_timer(interval_ms, slot, parent):
    """A single-shot timer owned by `parent` (stops with it, never fires into a closed panel)."""
    timer = QtCore.QTimer(parent)
    timer.setSingleShot(True)
    timer.setInterval(interval_ms)
    timer.timeout.connect(slot)
    return timer
