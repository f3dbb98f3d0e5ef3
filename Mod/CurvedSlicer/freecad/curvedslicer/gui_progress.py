"""Progress dialog with Cancel for long core calls on the GUI thread (GUI only).

The core calls the callback on the calling (GUI) thread; it updates the dialog, lets Qt process
events (so FreeCAD stays responsive and Cancel can be clicked) and returns False once Cancel was
pressed, which makes the core raise Cancelled at its next check."""

from PySide import QtCore, QtGui


class DialogProgress:
    def __init__(self, title="CurvedSlicer"):
        self.dialog = QtGui.QProgressDialog("Starting…", "Cancel", 0, 1000)
        self.dialog.setWindowTitle(title)
        self.dialog.setWindowModality(QtCore.Qt.ApplicationModal)
        self.dialog.setMinimumDuration(300)
        self.dialog.setAutoClose(False)
        self.dialog.setAutoReset(False)
        self.dialog.setValue(0)

    def __call__(self, stage, fraction):
        self.dialog.setLabelText("%s (%d %%)" % (stage, int(100 * fraction)))
        self.dialog.setValue(int(1000 * min(max(fraction, 0.0), 1.0)))
        QtGui.QApplication.processEvents()
        return not self.dialog.wasCanceled()

    def cancel(self):
        self.dialog.cancel()

    def close(self):
        self.dialog.reset()
        self.dialog.hide()
        self.dialog.deleteLater()
