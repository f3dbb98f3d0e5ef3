"""Default values of the Job's parameters, read from the core's options structs (one source of
defaults for the command line, the Python module and the workbench: the C++ ``Options{}``).

App side: imports only the compiled module.
"""

import math

from .core import native

_LAYERS = native.LayerJobOptions()
_PLANNER = native.PlannerOptions()
_WALL = native.ThinWallOptions()
_MOTION = native.MotionOptions()

LAYER_THICKNESS = _LAYERS.layer_thickness  # mm
# Layer surfaces simplified within 0.05 x voxel size (False: full resolution)
SIMPLIFY_LAYERS = _LAYERS.simplify_layers
BEAD_SPACING = _PLANNER.bead_spacing  # mm, curved layers
WALL_BEAD_SPACING = _WALL.bead_spacing  # mm, between the beads of a thin wall
POINT_SPACING = _PLANNER.point_spacing  # mm
FIT_TOLERANCE = _PLANNER.fit_tolerance  # mm
CORNER_ANGLE = _PLANNER.corner_angle  # degrees
# Bead coverage: the core's "< 0 = half the bead spacing" as a number for the Job
MIN_FEATURE_WIDTH = (_PLANNER.min_feature_width if _PLANNER.min_feature_width > 0
                     else 0.5 * BEAD_SPACING)  # mm
BEAD_WIDTH_MIN = _PLANNER.width_min  # fraction of the bead spacing
BEAD_WIDTH_MAX = _PLANNER.width_max  # fraction of the bead spacing
CONNECT_INSETS = _PLANNER.connect_insets
FILL_GAPS = _PLANNER.fill_gaps
# The core's "< 0 = the bead spacing squared" as a number for the Job, mm²
MIN_GAP_AREA = (_PLANNER.min_gap_area if _PLANNER.min_gap_area > 0
                else BEAD_SPACING * BEAD_SPACING)
CORNER_FILL = _PLANNER.corner_fill
CORNER_FILL_ANGLE = _PLANNER.corner_fill_angle  # degrees
MEASURE_COVERAGE = _PLANNER.measure_coverage

# Motion (robot/motion.hpp MotionOptions; the Job's Robot properties, stages/poses.py)
CLEARANCE = _MOTION.clearance  # mm
ALLOW_COLLISIONS = _MOTION.allow_collisions
ADD_HOME = _MOTION.add_home
MERGE_TOLERANCE = _MOTION.merge_tolerance  # mm
MAX_A2_STEP = math.degrees(_MOTION.max_a2_step)  # degrees (the core keeps radians)
PART_PLACEMENT = _MOTION.placement  # "rest" | "cell"
