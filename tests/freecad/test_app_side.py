"""The App side of the workbench never imports a GUI module: with FreeCADGui, PySide and the
workbench's GUI modules (init_gui, commands/, taskpanels/, viewproviders/, gui_progress) blocked by
an import hook, every App module imports, and a Job is made (api.make_job), run (api.run, then a
recompute after a parameter change) and exported (api.export) headless, also with
``FreeCAD.GuiUp`` claimed True (an import behind ``if FreeCAD.GuiUp`` then hits the block). The
source of every App module is also read for GUI imports anywhere in it (inside functions too)."""

import ast
import importlib
import importlib.abc
import os
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import cs_testing  # noqa: E402

PACKAGE = "freecad.curvedslicer"
GUI_TOP_LEVEL = ("FreeCADGui", "PySide", "PySide2", "PySide6", "shiboken2", "shiboken6")
GUI_MODULES = tuple(PACKAGE + "." + name for name in
                    ("init_gui", "commands", "taskpanels", "viewproviders", "gui_progress"))


def is_gui_module(name):
    return (name.split(".")[0] in GUI_TOP_LEVEL
            or any(name == m or name.startswith(m + ".") for m in GUI_MODULES))


class BlockGui(importlib.abc.MetaPathFinder):
    """Refuses GUI modules and records every attempt (an attempt caught by the importer would
    otherwise go unnoticed)."""

    def __init__(self):
        self.attempts = []

    def find_spec(self, name, path=None, target=None):
        if is_gui_module(name):
            self.attempts.append(name)
            raise ImportError("GUI module imported by the App side: %s" % name)
        return None


BLOCKER = BlockGui()
for loaded in [name for name in sys.modules if is_gui_module(name)]:
    del sys.modules[loaded]
sys.meta_path.insert(0, BLOCKER)

import FreeCAD  # noqa: E402
from freecad.curvedslicer import api  # noqa: E402

PACKAGE_DIR = os.path.dirname(importlib.import_module(PACKAGE).__file__)


def app_modules():
    """{module name: file} of every App-side module of the package."""
    found = {}
    for root, dirs, files in os.walk(PACKAGE_DIR):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for f in sorted(files):
            if not f.endswith(".py"):
                continue
            rel = os.path.relpath(os.path.join(root, f), PACKAGE_DIR)[:-3].replace(os.sep, ".")
            name = PACKAGE + ("" if rel == "__init__" else "." + rel.replace(".__init__", ""))
            if not is_gui_module(name):
                found[name] = os.path.join(root, f)
    return found


def imported_names(name, path):
    """Absolute names of the modules `path` (module `name`) imports anywhere in its source."""
    with open(path) as f:
        tree = ast.parse(f.read(), path)
    package = name if path.endswith("__init__.py") else name.rpartition(".")[0]
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.extend(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                parent = ".".join(parts[:len(parts) - node.level + 1])
                base = parent + ("." + base if base else "")
            names.append(base)
            names.extend(base + "." + alias.name for alias in node.names)
    return names


class TestAppSide(cs_testing.DocumentTestCase):
    def test_the_app_side_is_what_we_think(self):
        modules = app_modules()
        for expected in ("api", "geometry", "core", "hooks", "preferences", "objects.job",
                         "stages", "stages.layers", "stages.paths", "stages.poses"):
            self.assertIn(PACKAGE + "." + expected, modules)
        self.assertFalse(FreeCAD.GuiUp)

    def test_every_app_module_imports_with_the_gui_blocked(self):
        for name in app_modules():
            importlib.import_module(name)
        self.assertEqual(BLOCKER.attempts, [])

    def test_no_app_module_imports_a_gui_module_anywhere(self):
        offenders = {}
        for name, path in app_modules().items():
            gui = sorted({n for n in imported_names(name, path) if is_gui_module(n)})
            if gui:
                offenders[name] = gui
        self.assertEqual(offenders, {})

    def test_the_source_check_sees_a_lazy_gui_import(self):
        path = cs_testing.tmp_path("lazy_gui_import.py")
        with open(path, "w") as f:
            f.write("import FreeCAD\n\ndef style(job):\n    if FreeCAD.GuiUp:\n"
                    "        from ..viewproviders import view_job\n")
        names = imported_names(PACKAGE + ".stages.lazy", path)
        self.assertIn(PACKAGE + ".viewproviders.view_job", names)

    def test_make_run_recompute_and_export_headless(self):
        box = self.box(30, 20, 12)
        job = api.make_job(self.doc, box, start=(box, ["Face5"]), layer_thickness=3.0,
                           voxel_size=1.0)
        self.assertIsNone(job.ViewObject)
        api.run(job, progress=False)
        self.assertEqual(job.LayerCount, 3)  # a 12 mm box in 3 mm layers
        self.assertGreater(job.PathCount, 0)
        self.assertGreater(job.PoseCount, 0)
        job.BeadSpacing = 4.0
        api.recompute(job)
        self.assertTrue(job.PathsStatus.startswith("Planned"), job.PathsStatus)
        self.assertEqual(job.RunCount, 1)  # a path parameter alone does not rerun the layers
        path = cs_testing.tmp_path("app_side.JBI")
        result = api.export(job, path, format="jbi")
        self.assertTrue(os.path.getsize(path) > 0)
        self.assertGreater(result["motion_count"], 0)
        self.assertEqual(BLOCKER.attempts, [])

    def test_the_app_side_does_not_ask_whether_the_gui_is_up(self):
        """With GuiUp claimed True (and the GUI still blocked), the App side runs the same: it
        leaves GUI work to hooks.py instead of importing GUI modules behind GuiUp."""
        saved = FreeCAD.GuiUp
        FreeCAD.GuiUp = True
        try:
            box = self.box(30, 20, 12)
            job = api.make_job(self.doc, box, layer_thickness=3.0, voxel_size=1.0)
            api.run(job, progress=False)
            self.assertEqual(job.LayerCount, 3)
            self.assertGreater(job.PathCount, 0)
        finally:
            FreeCAD.GuiUp = saved
        self.assertEqual(BLOCKER.attempts, [])


cs_testing.main(__name__)
