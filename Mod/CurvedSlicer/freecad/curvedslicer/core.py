"""The compiled core (``_curvedslicer``) and the exception classes of the workbench.

Every error the workbench raises on purpose derives from ``CurvedSlicerError``:
``InvalidInput`` (bad parameters or geometry), ``IoError``, ``ResourceLimit`` (memory budget),
``NumericalFailure``, ``Cancelled`` (the progress callback asked to stop) and ``NotAvailable``
(a feature this build of the workbench does not offer).
Messages read "<what was wrong>: <value>; <what to do>".
"""

try:
    from . import _curvedslicer as native
except ImportError as error:  # pragma: no cover - depends on the installation
    raise ImportError(
        "CurvedSlicer's compiled module _curvedslicer could not be loaded: %s; build it for "
        "FreeCAD's Python (cmake -DPython3_EXECUTABLE=/usr/bin/python3) and install the "
        "workbench with cmake --install" % error
    ) from error

CurvedSlicerError = native.CurvedSlicerError
InvalidInput = native.InvalidInput
IoError = native.IoError
ResourceLimit = native.ResourceLimit
NumericalFailure = native.NumericalFailure
Cancelled = native.Cancelled


class NotAvailable(CurvedSlicerError):
    """A feature that is not wired into this version of the workbench yet."""
