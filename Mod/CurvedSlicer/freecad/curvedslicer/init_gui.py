"""Registers the CurvedSlicer workbench with FreeCAD's GUI (loaded by FreeCAD at start-up)."""

import FreeCADGui

from freecad.curvedslicer import icon_path


class CurvedSlicerWorkbench(FreeCADGui.Workbench):
    MenuText = "CurvedSlicer"
    ToolTip = "Curved layers for robotic wire-arc additive manufacturing"
    Icon = icon_path("Workbench")

    def Initialize(self):
        from freecad.curvedslicer.commands import job_commands
        from freecad.curvedslicer.objects import job as job_module
        from freecad.curvedslicer.gui_progress import DialogProgress
        from freecad.curvedslicer.taskpanels.preferences_page import PreferencesPage

        names = job_commands.register()
        self.appendToolbar("CurvedSlicer", names[:4])
        self.appendMenu("CurvedSlicer", names)
        job_module.set_default_progress_factory(DialogProgress)
        FreeCADGui.addPreferencePage(PreferencesPage, "CurvedSlicer")

    def Activated(self):
        pass

    def Deactivated(self):
        pass

    def GetClassName(self):
        return "Gui::PythonWorkbench"


FreeCADGui.addWorkbench(CurvedSlicerWorkbench())
