"""Hostile files through the workbench API do not take FreeCAD down: a 100,000-deep
cell.json and a cell with a number beyond the double range are InvalidInput naming the file; a
cell "file" that is /dev/zero, a FIFO or a folder is InvalidInput before anything is read (FreeCAD
neither grows nor blocks); an export onto a FIFO is an IoError that leaves the FIFO in place."""

import os
import stat
import sys

sys.path.insert(0, os.environ.get("CURVEDSLICER_TEST_DIR", os.path.dirname(__file__)))

import cs_testing  # noqa: E402
from freecad.curvedslicer import api  # noqa: E402
from freecad.curvedslicer.core import InvalidInput, IoError  # noqa: E402


class TestRobustness(cs_testing.DocumentTestCase):
    def box_job(self):
        box = self.box(20, 16, 6)
        job = api.make_job(self.doc, box, layer_thickness=2.0, voxel_size=1.0, bead_spacing=4.0,
                           point_spacing=2.0, cell_file="")
        api.run(job, progress=False)
        return job

    def test_hostile_cell_files_raise_invalid_input(self):
        job = self.box_job()
        deep = cs_testing.tmp_path("deep_cell.json")
        with open(deep, "w") as f:
            f.write("[" * 100000)
        overflow = cs_testing.tmp_path("overflow_cell.json")
        with open(overflow, "w") as f:
            f.write('{"format": "curvedslicer-cell", "gravity": [0, 0, -1e999]}')
        target = cs_testing.tmp_path("ROBUST.JBI")
        for cell_file, detail in ((deep, "nest deeper than 64 levels at line 1, column 65"),
                                  (overflow, "number overflow parsing '-1e999' at line 1")):
            with self.assertRaises(InvalidInput) as caught:
                api.export(job, target, format="jbi", cell_file=cell_file)
            message = str(caught.exception)
            self.assertIn(os.path.basename(cell_file) + ": not valid JSON", message)
            self.assertIn(detail, message)
            self.assertLess(len(message), 400)
            self.assertFalse(os.path.exists(target))
        # The job is still usable afterwards.
        self.assertGreater(api.export(job, None, format="csv")["motion_count"], 0)

    def fresh_fifo(self, name):
        """A new FIFO in the test folder, removed when the test ends."""
        fifo = cs_testing.tmp_path(name)
        if os.path.lexists(fifo):
            os.remove(fifo)
        os.mkfifo(fifo)
        self.addCleanup(os.remove, fifo)
        return fifo

    def test_cell_files_that_are_not_regular_files_are_refused_unread(self):
        job = self.box_job()
        fifo = self.fresh_fifo("robust_cell_fifo.json")
        for cell_file, kind in (("/dev/zero", "a device"), (fifo, "a FIFO (named pipe)"),
                                (os.path.dirname(fifo), "a folder")):
            with self.assertRaises(InvalidInput) as caught:
                api.export(job, None, format="csv", cell_file=cell_file)
            self.assertIn("cell file '%s' is %s, not a regular file" % (cell_file, kind),
                          str(caught.exception))

    def test_export_onto_a_fifo_is_refused(self):
        job = self.box_job()
        fifo = self.fresh_fifo("robust_fifo.jbi")
        with self.assertRaises(IoError) as caught:
            api.export(job, fifo, format="jbi")
        self.assertIn("output path is a FIFO (named pipe), not a regular file",
                      str(caught.exception))
        self.assertTrue(stat.S_ISFIFO(os.lstat(fifo).st_mode))


cs_testing.main(__name__)
