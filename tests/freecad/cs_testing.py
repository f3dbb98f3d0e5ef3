"""Helpers of the FreeCAD tests: run a unittest module inside freecadcmd/freecad and exit with
its result, temporary paths, a fresh document per test, running a check script in a new
freecadcmd process."""

import json
import os
import subprocess
import sys
import unittest

import FreeCAD

MARKER = "CURVEDSLICER-TESTS-OK"
TMP = os.environ.get("CURVEDSLICER_TEST_TMP", "/tmp")


def tmp_path(name):
    return os.path.join(TMP, name)


class DocumentTestCase(unittest.TestCase):
    """A fresh document per test, closed afterwards."""

    def setUp(self):
        self.doc = FreeCAD.newDocument(self.id().split(".")[-1])

    def tearDown(self):
        FreeCAD.closeDocument(self.doc.Name)

    def box(self, length=20.0, width=16.0, height=10.0, name="Box"):
        box = self.doc.addObject("Part::Box", name)
        box.Length, box.Width, box.Height = length, width, height
        self.doc.recompute()
        return box


def run_in_new_process(code, timeout=120):
    """Runs `code` in a fresh freecadcmd; the code must print one line 'RESULT <json>' and the
    process must exit 0 (no crash at exit either).

    Returns the decoded JSON."""
    script = tmp_path("subprocess_%d.py" % abs(hash(code)))
    with open(script, "w") as f:
        f.write("import sys, json\ntry:\n")
        for line in code.splitlines():
            f.write("    " + line + "\n")
        f.write("except Exception as e:\n    print('RESULT ' + json.dumps({'error': repr(e)}))\n"
                "sys.stdout.flush()\n"
                # as close_all_documents(): freecadcmd 1.1 crashes at exit otherwise
                "import FreeCAD\nfor name in list(FreeCAD.listDocuments()):\n"
                "    FreeCAD.closeDocument(name)\nsys.exit(0)\n")
    freecadcmd = os.environ.get("CURVEDSLICER_FREECADCMD", "freecadcmd")
    run = subprocess.run([freecadcmd, script], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         timeout=timeout, env=dict(os.environ))
    out = run.stdout.decode("utf-8", "replace").replace("\r", "\n")
    if run.returncode != 0:
        raise AssertionError("the subprocess exited with %d:\n%s" % (run.returncode, out[-3000:]))
    for line in out.splitlines():
        if line.startswith("RESULT "):
            return json.loads(line[len("RESULT "):])
    raise AssertionError("the subprocess printed no RESULT line:\n" + out[-3000:])


def close_all_documents():
    """Closes every open document: freecadcmd 1.1 crashes at exit (in FreeCAD's Mesh module) when
    a document holding a Mesh feature is still open."""
    for name in list(FreeCAD.listDocuments()):
        FreeCAD.closeDocument(name)


def main(module_name):
    """Runs the TestCases of `module_name`, closes the documents they left open and exits 0
    (printing the marker) or 1."""
    suite = unittest.defaultTestLoader.loadTestsFromModule(sys.modules[module_name])
    result = unittest.TextTestRunner(stream=sys.stdout, verbosity=2).run(suite)
    close_all_documents()
    sys.stdout.flush()
    if result.wasSuccessful():
        print(MARKER)
        sys.stdout.flush()
        sys.exit(0)
    sys.exit(1)
