"""Registers the CurvedSlicer workbench with FreeCAD's GUI (loaded by FreeCAD at start-up)."""

import FreeCADGui

from freecad.curvedslicer import icon_path


class CurvedSlicerWorkbench(FreeCADGui.Workbench):
    MenuText = "CurvedSlicer"
    ToolTip = "Curved layers for robotic wire-arc additive manufacturing"
    Icon = icon_path("Workbench")

    def Initialize(self):
        from freecad.curvedslicer.commands import job_commands
        from freecad.curvedslicer.taskpanels.preferences_page import PreferencesPage

        from freecad.curvedslicer import ICON_DIR

        FreeCADGui.addIconPath(ICON_DIR)  # preferences-curvedslicer.svg: the page's icon
        names = job_commands.register()
        self.appendToolbar("CurvedSlicer", job_commands.TOOLBAR)
        self.appendMenu("CurvedSlicer", names)
        FreeCADGui.addPreferencePage(PreferencesPage, "CurvedSlicer")

    def Activated(self):
        pass

    def Deactivated(self):
        pass

    def GetClassName(self):
        return "Gui::PythonWorkbench"


def install_hooks():
    """Lends the App side the GUI's progress dialog and view providers (hooks.py), from start-up
    on: a document with Jobs may be opened, or a macro run, before the workbench is activated."""
    from freecad.curvedslicer import hooks
    from freecad.curvedslicer.gui_progress import DialogProgress
    from freecad.curvedslicer.viewproviders import view_job

    hooks.install(progress_factory=DialogProgress, attach_view=view_job.attach,
                  restore_view=view_job.restore)


install_hooks()
FreeCADGui.addWorkbench(CurvedSlicerWorkbench())
