"""Where the motion leaves the ideal pose, in the 3D view: the weld moves whose torch is tilted
off gravity (to clear the deposit, the table or the fixture) and those whose deposition direction
is off gravity (the positioner at a limit or blending near its rotation axis), as thick lines in
the part frame over the paths, one feature per range of angle, coloured by range (the view
provider colours them, viewproviders/view_job.py style_deviations).

A weld move (from one arc-on motion point to the next) falls into the range of the larger of its
two end points' angles; moves below the first range (1°) are not drawn: the paths show them.
"""

import FreeCAD

from .features import group_members

#: (key, motion-dict field, label) of the two kinds of deviation drawn.
KINDS = (("torch", "torch_angle", "torch angle"),
         ("gravity", "residual", "gravity deviation"))
#: Ranges of angle in degrees: [low, high); None = no upper bound.
RANGES = ((1.0, 5.0), (5.0, 10.0), (10.0, None))


def range_label(low, high):
    return "%g-%g deg" % (low, high) if high is not None else "over %g deg" % low


def deviation_segments(m):
    """{(kind key, range index): [(start, end), ...]} of the motion dict `m`: every weld move
    (an arc-on point and the point before it) with its end points in the part frame, by the
    larger angle of its ends."""
    import numpy

    arc_on = numpy.asarray(m["arc_on"], dtype=bool)
    positions = numpy.asarray(m["position"], dtype=float).reshape(-1, 3)
    moves = numpy.nonzero(arc_on[1:])[0] + 1  # index of each weld move's end point
    out = {}
    for key, field, _ in KINDS:
        values = numpy.degrees(numpy.asarray(m[field], dtype=float))
        larger = numpy.maximum(values[moves - 1], values[moves]) if len(moves) else values[:0]
        for r, (low, high) in enumerate(RANGES):
            inside = larger >= low
            if high is not None:
                inside &= larger < high
            ends = moves[inside]
            out[(key, r)] = [(tuple(positions[i - 1]), tuple(positions[i])) for i in ends]
    return out


def deviation_objects(job):
    """{(kind key, range index): feature} of the Job's deviation features."""
    found = {}
    for o in group_members(job.PathsGroup):
        if "DeviationKind" in o.PropertiesList:
            found[(o.DeviationKind, int(o.DeviationRange))] = o
    return found


def _digest(m):
    import numpy

    return "%d %.12g %.12g" % (len(m["arc_on"]), float(numpy.sum(m["torch_angle"])),
                               float(numpy.sum(m["residual"])))


def draw_deviations(job, m):
    """(Re)builds the deviation features of `job` from its motion dict `m` (no-op when they were
    built from the same motion): one per kind and range, a compound of its weld moves, hidden
    when empty."""
    import Part

    if job.PathsGroup is None:
        return
    digest = _digest(m)
    existing = deviation_objects(job)
    if existing and all(o.MotionDigest == digest for o in existing.values()) and \
            len(existing) == len(KINDS) * len(RANGES):
        return
    segments = deviation_segments(m)
    doc = job.Document
    for key, _, label in KINDS:
        for r, (low, high) in enumerate(RANGES):
            feature = existing.get((key, r))
            if feature is None:
                feature = doc.addObject("Part::Feature", "Deviation")
                for (ptype, name, tip) in (
                        ("App::PropertyString", "DeviationKind",
                         "torch: torch angle off gravity; gravity: deposition direction off "
                         "gravity"),
                        ("App::PropertyInteger", "DeviationRange", "Range of angle (0, 1, 2)"),
                        ("App::PropertyInteger", "DeviationMoves", "Weld moves in the range"),
                        ("App::PropertyString", "MotionDigest", "Motion the lines were built from")):
                    feature.addProperty(ptype, name, "Deviation", tip)
                    feature.setEditorMode(name, 1)
                feature.DeviationKind = key
                feature.DeviationRange = r
                job.PathsGroup.addObject(feature)
            moves = segments[(key, r)]
            edges = [Part.LineSegment(FreeCAD.Vector(*a), FreeCAD.Vector(*b)).toShape()
                     for (a, b) in moves if a != b]
            feature.Shape = Part.makeCompound(edges) if edges else Part.Shape()
            feature.DeviationMoves = len(moves)
            feature.MotionDigest = digest
            feature.Label = "%s %s %s" % (job.Label, label, range_label(low, high))
            feature.Visibility = bool(edges)
            feature.purgeTouched()
    job.PathsGroup.purgeTouched()
