"""CurvedSlicer FreeCAD workbench: curved layers for robotic wire-arc additive manufacturing.

Macro API: ``from freecad.curvedslicer import api``. Package layout (by role, FEM style; see
docs/WORKBENCH.md). App side, no GUI imports: ``objects/`` the Job's proxy (properties,
persistence, migration), ``stages/`` what a run does (layers, paths, poses, each with its digest),
``api.py``, ``geometry.py`` (shapes/meshes to arrays), ``core.py`` (the compiled module
``_curvedslicer`` and its exception classes), ``hooks.py`` (what the GUI lends the App side).
GUI side: ``init_gui.py``, ``viewproviders/`` (styling), ``taskpanels/``, ``commands/``,
``gui_progress.py``.
"""

import os

__version__ = "0.1.0"

#: Version of the Job's property layout; objects saved with an older one are migrated on load
#: (objects/job.py, JobProxy.onDocumentRestored).
SCHEMA_VERSION = 11  # 2: paths, plan JSON, poses, thin wall; 3: NarrowStrips; 4: CornerAngle;
# 5: motion options (Clearance, AllowCollisions, AddHome, MergeTolerance, MaxA2Step, PartPlacement)
# 6: bead coverage options (MinFeatureWidth, BeadWidthMin, BeadWidthMax, ConnectInsets,
#    MeasureCoverage) and results (VoidShare, OverlapShare, ArcStarts, CoverageReport)
# 7: FillGaps (gap fill between beads; a Job from before it keeps FillGaps = False)
# 8: SimplifyLayers (layer simplification, default the core's; a Job from before gets False, the
#    full-resolution layers it sliced, and keeps its digest)
#    and MinGapArea (gap fill's smallest patch; migrated: BeadSpacing²), CornerFill (a Job from
#    before it keeps CornerFill = False) and CornerFillAngle
# 9: results of the torch angles (PoseTorchAngle, MaxTorchAngle, MaxGravityDeviation) and
#    CollisionCount (filled when the poses are next computed)
# 10: MotionDigest (the cell and robot options the shown motion was planned with; empty in a Job
#     from before it, which then skips that check before an export)
# 11: DepositionDirection (Growth; a Job from before it gets Nearest, the paper's V it planned
#     with, and keeps its digest)

PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
ICON_DIR = os.path.join(PACKAGE_DIR, "resources", "icons")


def icon_path(name):
    """Absolute path of the SVG icon ``name`` (without extension)."""
    return os.path.join(ICON_DIR, name + ".svg")
