"""Checks of the macro API's arguments before anything is stored in a Job.

A FreeCAD length property stores a negative value as 0, so a bad argument must be refused before
it reaches the property, with the value the caller gave. The messages are the core's (those the
command line prints for the same option). Pure Python: no FreeCAD GUI imports.
"""

import math

from .core import InvalidInput


def _number(value):
    """float(value) for ints and floats (not bools, not strings); None otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value)


def _shown(value, precision):
    number = _number(value)
    return ("%." + str(precision) + "g") % number if number is not None else repr(value)


def short_repr(value, limit=60):
    """repr(value) cut to `limit` characters, for messages (a huge value is not echoed whole)."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit] + "..."


def positive_mm(value, what, example, precision=6, unit="millimetres"):
    """value as a float > 0 and finite, else InvalidInput "<what> must be a positive number of
    <unit>: <value>; pass a value such as <example>" (the core's text; precision as it prints)."""
    number = _number(value)
    if number is None or not math.isfinite(number) or number <= 0.0:
        raise InvalidInput("%s must be a positive number of %s: %s; pass a value such as %s"
                           % (what, unit, _shown(value, precision), example))
    return number


def zero_or_positive(value, what, unit, example):
    """value as a float, 0 (automatic) or positive and finite."""
    number = _number(value)
    if number is None or not math.isfinite(number) or number < 0.0:
        raise InvalidInput("%s must be 0 (automatic) or a positive number of %s: %s; pass e.g. %s"
                           % (what, unit, _shown(value, 6), example))
    return number


def corner_angle(value):
    """Degrees in (0, 180], the core's check."""
    number = _number(value)
    if number is None or not math.isfinite(number) or not 0.0 < number <= 180.0:
        raise InvalidInput("corner angle must be in (0, 180] degrees: %s; pass a value such as "
                           "30, or 180 to keep no corners" % _shown(value, 4))
    return number


def choice(value, what, choices):
    """value if it is one of `choices` (strings), else InvalidInput listing them."""
    if not isinstance(value, str) or value not in choices:
        raise InvalidInput("unknown %s: %r; use one of %s" % (what, value, ", ".join(choices)))
    return value


def vector(value, what):
    """A 3-tuple of finite floats from a sequence of 3 numbers or a FreeCAD.Vector."""
    if hasattr(value, "x") and hasattr(value, "y") and hasattr(value, "z"):
        value = (value.x, value.y, value.z)
    try:
        items = list(value)
    except TypeError:
        items = None
    numbers = [_number(v) for v in items] if items is not None else []
    if len(numbers) != 3 or any(n is None or not math.isfinite(n) for n in numbers):
        raise InvalidInput("%s must be 3 finite numbers (x, y, z): %r; pass e.g. (0, 0, 1)"
                           % (what, value))
    return tuple(numbers)


def document_object(value, what, allow_none=False):
    """value if it is a FreeCAD document object (or None when allowed), else InvalidInput naming
    the argument and what to pass (a string such as 'Box' is the object's name, not the object)."""
    if value is None and allow_none:
        return value
    if value is not None and hasattr(value, "isDerivedFrom") and hasattr(value, "Document"):
        return value
    hint = ""
    if isinstance(value, str):
        hint = " (a name; pass the object itself, e.g. doc.getObject(%r))" % value
    raise InvalidInput("%s must be a FreeCAD object: %r of type %s%s; pass a Part solid, a "
                       "PartDesign Body or a closed Mesh feature of the document"
                       % (what, value, type(value).__name__, hint))


def program_date(value):
    """"" (the exporters' fixed default) or "YYYY/MM/DD HH:MM"; the core checks the pattern, here
    only the type."""
    if not isinstance(value, str):
        raise InvalidInput("date must be a string \"YYYY/MM/DD HH:MM\" or \"\": %r; pass e.g. "
                           "\"2026/11/22 07:00\"" % (value,))
    return value


def output_path(value):
    """None (nothing written) or a non-empty file path (the core's message for an empty one)."""
    if value is None:
        return value
    if not isinstance(value, str):
        try:
            import os

            value = os.fspath(value)
        except TypeError:
            raise InvalidInput("path must be a file path or None: %r; pass e.g. '/tmp/PART.JBI'"
                               % (value,)) from None
    if not value:
        raise InvalidInput("output path is empty: ''; pass a file path such as 'PART.JBI'")
    return value
