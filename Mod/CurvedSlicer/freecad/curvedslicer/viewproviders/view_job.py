"""View provider of the Job: icon, double-click opens the task panel, layers coloured by height
(blue at the start surface to red at the top)."""

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


def color_layers(job):
    """Colours the Job's layer meshes by height (no-op headless)."""
    if not FreeCAD.GuiUp:
        return
    from ..objects.job import layer_objects

    features = layer_objects(job)
    heights = [float(f.Height) for f in features]
    if not heights:
        return
    low, high = min(heights), max(heights)
    for feature, h in zip(features, heights):
        vobj = feature.ViewObject
        if vobj is None:
            continue
        vobj.ShapeColor = height_color(0.0 if high <= low else (h - low) / (high - low))
        if "Lighting" in vobj.PropertiesList:
            vobj.Lighting = "Two side"


class ViewProviderJob:
    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        return icon_path("Job")

    def updateData(self, obj, prop):
        if prop == "LayerHeights":
            color_layers(obj)

    def onChanged(self, vobj, prop):
        pass

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui

        from ..taskpanels.task_job import TaskPanelJob

        FreeCADGui.Control.showDialog(TaskPanelJob(vobj.Object))
        return True

    def unsetEdit(self, vobj, mode=0):
        import FreeCADGui

        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj):
        import FreeCADGui

        FreeCADGui.ActiveDocument.setEdit(vobj.Object.Name)
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

    QtCore.QTimer.singleShot(0, lambda: color_layers(obj) if obj.Document else None)


def attach(obj):
    """Attaches the view provider (only when the GUI is up)."""
    if FreeCAD.GuiUp and obj.ViewObject is not None:
        ViewProviderJob(obj.ViewObject)
