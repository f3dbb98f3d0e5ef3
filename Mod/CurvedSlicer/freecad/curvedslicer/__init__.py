"""CurvedSlicer FreeCAD workbench: curved layers for robotic wire-arc additive manufacturing.

Macro API: ``from freecad.curvedslicer import api``. Package layout (by role, FEM style):
``objects/`` document-object proxies (no GUI imports), ``viewproviders/``, ``taskpanels/``,
``commands/`` (GUI only), ``geometry.py`` (shapes/meshes to arrays), ``core.py`` (the compiled
module ``_curvedslicer`` and its exception classes).
"""

import os

__version__ = "0.1.0"

#: Version of the Job's property layout; objects saved with an older one are migrated on load
#: (objects/job.py, JobProxy.onDocumentRestored).
SCHEMA_VERSION = 4  # 2: paths, plan JSON, poses, thin wall; 3: NarrowStrips; 4: CornerAngle

PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
ICON_DIR = os.path.join(PACKAGE_DIR, "resources", "icons")


def icon_path(name):
    """Absolute path of the SVG icon ``name`` (without extension)."""
    return os.path.join(ICON_DIR, name + ".svg")
