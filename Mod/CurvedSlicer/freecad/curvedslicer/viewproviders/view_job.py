"""View provider of the Job: icon, double-click opens the task panel, and the styling of the
Job's result features: layers coloured by height (blue at the start surface to red at the top),
paths as coloured lines, travel dashed, the positioner in greys, the robot, torch and deposit of
the pose simulation.

The stages (App side) never style; the view provider restyles when a stage's result property
changes (``updateData``), deferred to the event loop so that an undo or redo in progress (whose
groups can hold objects not yet restored) is finished first. ``attach`` and ``restore`` are the
hooks init_gui.py installs into the App side (hooks.py)."""

import FreeCAD

from .. import icon_path


def height_color(fraction):
    """RGB ramp blue -> cyan -> green -> yellow -> red for fraction in [0, 1]."""
    f = min(max(fraction, 0.0), 1.0)
    stops = [(0.0, (0.1, 0.2, 0.9)), (0.25, (0.0, 0.8, 0.9)), (0.5, (0.1, 0.8, 0.2)),
             (0.75, (0.95, 0.85, 0.1)), (1.0, (0.9, 0.15, 0.1))]
    for (f0, c0), (f1, c1) in zip(stops, stops[1:]):
        if f <= f1:
            t = (f - f0) / (f1 - f0)
            return tuple(a + t * (b - a) for a, b in zip(c0, c1))
    return stops[-1][1]


def path_color(fraction):
    """The line colour of a path layer: its layer's colour, darker, so beads stand out on their
    own layer's surface (the layer inspector shows the two together)."""
    return tuple(0.55 * c for c in height_color(fraction))


def _differs(current, value):
    """True if a view property's `current` value is not `value` (colours compared on r, g, b
    within one step of the 8 bits per channel they are saved with)."""
    if isinstance(value, tuple):
        return any(abs(float(c) - float(v)) > 1.01 / 255 for c, v in zip(current, value))
    return current != value


def set_view(vobj, name, value):
    """Sets a view property only when it changes: restyling a document as it was saved (after
    opening it, or after an undo) then does not mark the document modified."""
    # hasattr, not PropertiesList: FreeCAD 1.x lists ShapeAppearance there but still takes
    # ShapeColor as an attribute (the layers stayed grey on 1.1 with the list test)
    if hasattr(vobj, name) and _differs(getattr(vobj, name), value):
        setattr(vobj, name, value)


def color_layers(job):
    """Colours the Job's layer meshes by height (no-op headless)."""
    if not FreeCAD.GuiUp:
        return
    from ..stages.layers import layer_objects

    features = layer_objects(job)
    heights = [float(f.Height) for f in features]
    if not heights:
        return
    low, high = min(heights), max(heights)
    for feature, h in zip(features, heights):
        vobj = feature.ViewObject
        if vobj is None:
            continue
        set_view(vobj, "ShapeColor",
                 height_color(0.0 if high <= low else (h - low) / (high - low)))
        set_view(vobj, "Lighting", "Two side")


def style_paths(job):
    """Arc-on beads as solid lines coloured by plan layer height (path_color), arc-off travel
    as thin dashed grey lines, the cell's parts by style_cell (no-op headless)."""
    if not FreeCAD.GuiUp:
        return
    from ..stages import paths as path_stage
    from ..stages import poses

    features = path_stage.path_objects(job)
    count = max(len(features), 1)
    for i, feature in enumerate(features):
        vobj = feature.ViewObject
        if vobj is None:
            continue
        set_view(vobj, "LineColor", path_color(i / max(count - 1, 1)))
        set_view(vobj, "LineWidth", 2.0)
        set_view(vobj, "DrawStyle", "Solid")
    travel = path_stage.travel_object(job)
    if travel is not None and travel.ViewObject is not None:
        set_view(travel.ViewObject, "LineColor", (0.45, 0.45, 0.45))
        set_view(travel.ViewObject, "LineWidth", 1.0)
        set_view(travel.ViewObject, "DrawStyle", "Dashed")
    style_cell(poses.pose_objects(job))
    style_voids(job)
    style_deviations(job)


#: Line colours of the deviation features (stages/deviations.py) by kind and range: the torch
#: angle off gravity from green (1-5 deg) through yellow to red (over 10 deg), the deposition
#: direction off gravity from light violet to magenta.
DEVIATION_COLORS = {"torch": ((0.1, 0.75, 0.2), (0.95, 0.8, 0.05), (0.9, 0.1, 0.05)),
                    "gravity": ((0.7, 0.6, 0.95), (0.6, 0.3, 0.9), (0.9, 0.05, 0.8))}


def style_deviations(job):
    """The deviation lines thick and coloured by kind and range (no-op headless)."""
    if not FreeCAD.GuiUp:
        return
    from ..stages import deviations

    for (kind, index), feature in deviations.deviation_objects(job).items():
        vobj = feature.ViewObject
        if vobj is None:
            continue
        colours = DEVIATION_COLORS.get(kind)
        if colours and 0 <= index < len(colours):
            set_view(vobj, "LineColor", colours[index])
        set_view(vobj, "LineWidth", 5.0)
        set_view(vobj, "DrawStyle", "Solid")


#: Colour of the uncovered-region markers (stages/voids.py).
VOID_COLOR = (0.9, 0.05, 0.05)


def style_voids(job):
    """The uncovered-region discs in red, lit on both sides (no-op headless)."""
    if not FreeCAD.GuiUp:
        return
    from ..stages import voids

    for feature in voids.void_objects(job):
        vobj = feature.ViewObject
        if vobj is None:
            continue
        set_view(vobj, "ShapeColor", VOID_COLOR)
        set_view(vobj, "LineColor", VOID_COLOR)
        set_view(vobj, "Lighting", "Two side")
        set_view(vobj, "Visibility", bool(feature.Visibility))


#: Shape colours of the cell's parts: the positioner in greys, the robot in a robot's orange,
#: the torch in copper.
CELL_COLORS = {"PositionerBase": (0.35, 0.35, 0.38), "PositionerCradle": (0.55, 0.55, 0.6),
               "PositionerTable": (0.75, 0.75, 0.78), "Robot": (0.95, 0.55, 0.1),
               "Torch": (0.72, 0.45, 0.2)}
DEPOSIT_COLOR = (0.85, 0.1, 0.1)


def style_cell(objects):
    """Colours of the pose view's parts ({role: object}); the deposit as thick red lines."""
    for role, obj in objects.items():
        vobj = obj.ViewObject
        if vobj is None:
            continue
        if role in CELL_COLORS:
            set_view(vobj, "ShapeColor", CELL_COLORS[role])
        elif role == "PosePart":
            see_through(obj)
        elif role == "Deposit":
            set_view(vobj, "LineColor", DEPOSIT_COLOR)
            set_view(vobj, "PointColor", DEPOSIT_COLOR)
            set_view(vobj, "LineWidth", 4.0)
            set_view(vobj, "PointSize", 1.0)


#: Transparency of the part carried by the positioner (0..1): the deposit inside it stays visible.
PART_TRANSPARENCY = 0.5


def see_through(obj):
    """Shows `obj` (a shape feature or an App::Link to one) transparent, so the deposit and the
    torch tip inside it can be seen."""
    vobj = obj.ViewObject
    if vobj is None:
        return
    if hasattr(vobj, "ShapeMaterial") and hasattr(vobj, "OverrideMaterial"):  # App::Link
        material = vobj.ShapeMaterial
        if not vobj.OverrideMaterial or abs(material.Transparency - PART_TRANSPARENCY) > 0.01:
            material.Transparency = PART_TRANSPARENCY
            vobj.ShapeMaterial = material
            vobj.OverrideMaterial = True
    else:
        set_view(vobj, "Transparency", int(round(100 * PART_TRANSPARENCY)))


#: Result properties after whose change the Job's features are restyled: the layer stage sets
#: LayerHeights after writing the layers, the path stage PlanDigest after drawing the paths, the
#: pose stage PoseCount after placing the positioner.
STYLED_BY = ("LayerHeights", "PlanDigest", "PoseCount")

_pending = set()  # (document name, Job name) with a restyling scheduled


def schedule_styling(job):
    """Restyles the Job's features once the event loop runs (several changes in one run or one
    undo coalesce into one restyling). Nothing happens if the Job is gone by then."""
    from PySide import QtCore

    key = (job.Document.Name, job.Name)
    if key in _pending:
        return
    _pending.add(key)
    QtCore.QTimer.singleShot(0, lambda: _style_later(key))


def _style_later(key):
    _pending.discard(key)
    job = _find(key)
    if job is not None:
        color_layers(job)
        style_paths(job)


def _find(key):
    """The Job named by (document name, object name), or None if either was closed/removed."""
    doc_name, name = key
    if doc_name not in FreeCAD.listDocuments():
        return None
    return FreeCAD.getDocument(doc_name).getObject(name)


class ViewProviderJob:
    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        return icon_path("Job")

    def updateData(self, obj, prop):
        if prop in STYLED_BY:
            schedule_styling(obj)

    def onChanged(self, vobj, prop):
        pass

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui

        from ..taskpanels.task_job import TaskPanelJob

        self.panel = TaskPanelJob(vobj.Object)  # the open panel (tests drive it)
        FreeCADGui.Control.showDialog(self.panel)
        return True

    def unsetEdit(self, vobj, mode=0):
        import FreeCADGui

        self.panel = None
        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj):
        from ..commands.job_commands import edit_job

        edit_job(vobj.Object)
        return True

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    dumps = __getstate__
    loads = __setstate__


def restore(obj):
    """After loading a document in the GUI: attaches the view provider if the Job has none (it
    was saved headless) and colours the layers once their view providers exist."""
    if not FreeCAD.GuiUp or obj.ViewObject is None:
        return
    if getattr(obj.ViewObject, "Proxy", None) is None:
        ViewProviderJob(obj.ViewObject)
    from PySide import QtCore

    key = (obj.Document.Name, obj.Name)
    QtCore.QTimer.singleShot(0, lambda: _restyle_restored(key))


def _restyle_restored(key):
    job = _find(key)
    if job is not None:
        color_layers(job)
        style_paths(job)
        _sync_visibility(job)


def _sync_visibility(job):
    """A document saved headless has no GUI visibility for the path and pose objects; take the
    object's own Visibility."""
    from ..stages import paths as path_stage
    from ..stages import poses

    from ..stages import voids

    objects = list(path_stage.path_objects(job)) + list(poses.pose_objects(job).values())
    objects += voids.void_objects(job)
    travel = path_stage.travel_object(job)
    if travel is not None:
        objects.append(travel)
    for o in objects:
        if o.ViewObject is not None:
            set_view(o.ViewObject, "Visibility", bool(o.Visibility))


def attach(obj):
    """Attaches the view provider (only when the GUI is up)."""
    if FreeCAD.GuiUp and obj.ViewObject is not None:
        ViewProviderJob(obj.ViewObject)
