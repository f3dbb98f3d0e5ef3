"""The core's messages in the workbench's words: where a message of the core names a command-line
option (``--allow-collisions``), the workbench user reads the Job property or the dialog control
that does the same. App side (no GUI imports).
"""

from .core import Cancelled, CurvedSlicerError

#: (the core's words, the workbench's words), applied in this order.
_OPTIONS = (
    ("(--placement rest; Python MotionOptions(placement=\"rest\"); the Job's PartPlacement Rest)",
     "(the Job's PartPlacement Rest)"),
    ("(--allow-collisions)", "(the Job's AllowCollisions)"),
    ("(allowed: --allow-collisions)", "(allowed: the Job's AllowCollisions)"),
    ("(--placement auto finds the lowest)", "(the Job's PartPlacement Auto finds the lowest)"),
    ("(--placement cell)", "(the Job's PartPlacement Cell)"),
    ("use --placement cell to keep", "use the Job's PartPlacement Cell to keep"),
    ("(--clearance)", "(the Job's Clearance)"),
    ("or --allow-foreign-cell to write it anyway",
     "or tick \"Write it for another vendor's cell\" in the export dialog "
     "(api.export(..., allow_foreign_cell=True)) to write it anyway"),
    ("pass --cap-holes (CapHoles)", "set the Job's CapHoles"),
    ("enable hole capping (--cap-holes)", "enable hole capping (the Job's CapHoles)"),
    ("(--min-feature-width, MinFeatureWidth)", "(MinFeatureWidth)"),
    ("(--bead-width-range, BeadWidthMin/BeadWidthMax)", "(BeadWidthMin/BeadWidthMax)"),
    ("(--min-gap-area, MinGapArea)", "(MinGapArea)"),
    ("(--corner-fill-angle, CornerFillAngle)", "(CornerFillAngle)"),
)


def for_workbench(text):
    """`text` with the command line's option names replaced by the workbench's."""
    for core, workbench in _OPTIONS:
        text = text.replace(core, workbench)
    return text


def rephrased(error):
    """An exception of the same class as `error` whose message names the workbench's controls
    (`error` itself when nothing changes, and always for Cancelled)."""
    if isinstance(error, Cancelled) or not isinstance(error, CurvedSlicerError):
        return error
    text = str(error)
    better = for_workbench(text)
    return error if better == text else type(error)(better)
