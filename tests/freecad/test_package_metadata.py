"""The Addon Manager's package.xml, read by FreeCAD's own parser (FreeCAD.Metadata, as the Addon
Manager and FreeCAD's start-up read it): the elements the format requires, the version the Python
package and the compiled module report, a workbench entry whose class is the one init_gui
registers, a subdirectory and icons that exist, and a FreeCAD range that includes the running
FreeCAD (else FreeCAD skips the workbench at start-up)."""

import ast
import os
import re
import sys
import unittest
import xml.etree.ElementTree as ElementTree

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import cs_testing  # noqa: E402
import FreeCAD  # noqa: E402

import freecad.curvedslicer as package  # noqa: E402
from freecad.curvedslicer.core import native  # noqa: E402

NAMESPACE = "{https://wiki.freecad.org/Package_Metadata}"
PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(package.__file__))))
PACKAGE_XML = os.path.join(PACKAGE_ROOT, "package.xml")


def registered_workbench_classes():
    """Names of the classes init_gui.py passes to FreeCADGui.addWorkbench (read, not imported:
    init_gui needs the GUI)."""
    with open(os.path.join(os.path.dirname(package.__file__), "init_gui.py")) as f:
        tree = ast.parse(f.read())
    names = set()
    for node in ast.walk(tree):
        if (isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "addWorkbench"
                and node.args and isinstance(node.args[0], ast.Call)):
            names.add(getattr(node.args[0].func, "id", None))
    return names


class PackageMetadata(unittest.TestCase):
    def setUp(self):
        self.assertTrue(os.path.isfile(PACKAGE_XML), PACKAGE_XML)
        self.metadata = FreeCAD.Metadata(PACKAGE_XML)
        self.xml = ElementTree.parse(PACKAGE_XML).getroot()

    def test_required_elements(self):
        self.assertEqual(self.xml.tag, NAMESPACE + "package")
        self.assertEqual(self.xml.get("format"), "1")
        for element in ("name", "description", "version", "date", "maintainer", "license",
                        "content"):
            found = self.xml.find(NAMESPACE + element)
            self.assertIsNotNone(found, "package.xml has no <%s>" % element)
        self.assertRegex(self.xml.find(NAMESPACE + "date").text.strip(), r"^\d{4}-\d{2}-\d{2}$")
        self.assertEqual(self.metadata.Name, "CurvedSlicer")
        self.assertTrue(self.metadata.Description.strip())
        self.assertTrue(self.metadata.Maintainer and
                        all(m["name"] and "@" in m["email"] for m in self.metadata.Maintainer))
        self.assertTrue(self.metadata.License and self.metadata.License[0]["name"])

    def test_version_matches_package_and_module(self):
        self.assertRegex(self.metadata.Version, r"^\d+\.\d+\.\d+$")
        self.assertEqual(self.metadata.Version, package.__version__)
        self.assertEqual(self.metadata.Version, native.__version__)

    def test_workbench_entry(self):
        workbenches = self.metadata.Content.get("workbench", [])
        self.assertEqual(len(workbenches), 1)
        workbench = workbenches[0]
        self.assertIn(workbench.Classname, registered_workbench_classes())
        self.assertTrue(os.path.isdir(os.path.join(PACKAGE_ROOT, workbench.Subdirectory)))
        for icon in (self.metadata.Icon, workbench.Icon):
            self.assertTrue(os.path.isfile(os.path.join(PACKAGE_ROOT, icon)), icon)

    def test_supports_the_running_freecad(self):
        workbench = self.metadata.Content["workbench"][0]
        self.assertTrue(self.metadata.supportsCurrentFreeCAD())
        self.assertTrue(workbench.supportsCurrentFreeCAD())
        self.assertTrue(re.match(r"^\d+\.\d+", workbench.FreeCADMin), workbench.FreeCADMin)

    def test_addon_manager_reads_it(self):
        """FreeCAD 1.x's Addon Manager parses package.xml with its own pure-Python reader (it
        prints "Invalid version" and substitutes 0.0.0 for a version it cannot parse)."""
        try:
            import addonmanager_metadata
        except ImportError:
            self.skipTest("this FreeCAD has no addonmanager_metadata (0.20)")
        import contextlib
        import io

        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            metadata = addonmanager_metadata.MetadataReader.from_file(PACKAGE_XML)
        self.assertEqual(printed.getvalue(), "")
        self.assertEqual(metadata.name, "CurvedSlicer")
        self.assertEqual(str(metadata.version).strip(), package.__version__)
        workbench = metadata.content["workbench"][0]
        self.assertIn(workbench.classname, registered_workbench_classes())
        running = addonmanager_metadata.Version(from_list=FreeCAD.Version()[:3])
        self.assertLessEqual(workbench.freecadmin, running)
        python = addonmanager_metadata.Version(from_list=sys.version_info[:3])
        self.assertLessEqual(workbench.pythonmin, python)


cs_testing.main(__name__)
