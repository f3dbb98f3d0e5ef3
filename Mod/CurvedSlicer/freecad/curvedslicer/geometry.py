"""Shapes and meshes of FreeCAD objects as numpy arrays for the core (no GUI imports).

A model is a dict ``{"vertices": (n, 3) float64 mm, "triangles": (m, 3) int32, "face_ids":
(m,) int32 or None, "kind": "shape" | "mesh", "digest": hex}``. Shapes are passed to the core as
BREP text (``shape.exportBrepToString()``) and tessellated there by OpenCASCADE, each triangle
tagged with FreeCAD's 1-based face number (``FaceN``); the digest (SHA-256 of the BREP text or of
the mesh arrays) tells the Job whether its input changed.
"""

import hashlib

import numpy as np

import FreeCAD

from .core import InvalidInput, native


def _describe(obj):
    return "%s (%s)" % (obj.Label, obj.TypeId)


def _digest(*parts):
    h = hashlib.sha256()
    for part in parts:
        if isinstance(part, np.ndarray):
            h.update(np.ascontiguousarray(part).tobytes())
        else:
            h.update(str(part).encode("utf-8"))
        h.update(b"\0")
    return h.hexdigest()


def is_mesh_object(obj):
    return obj is not None and obj.isDerivedFrom("Mesh::Feature")


def mesh_arrays(mesh):
    """(vertices (n, 3) float64, triangles (m, 3) int32) of a ``Mesh.Mesh`` (placement applied)."""
    points, facets = mesh.Topology
    vertices = np.array([(p.x, p.y, p.z) for p in points], dtype=np.float64).reshape(-1, 3)
    triangles = np.array(facets, dtype=np.int32).reshape(-1, 3)
    return vertices, triangles


def solid_shape(obj):
    """The solid shape of a Part feature or PartDesign Body; InvalidInput when there is none."""
    if obj is None:
        raise InvalidInput("no solid: the Job's Solid is empty; set it to a Part solid, a "
                           "PartDesign Body or a closed Mesh")
    shape = getattr(obj, "Shape", None)
    if shape is None:
        raise InvalidInput("not a solid: %s has no shape or mesh; select a Part solid, a "
                           "PartDesign Body or a closed Mesh" % _describe(obj))
    if shape.isNull() or not shape.Solids:
        raise InvalidInput(
            "not a solid: %s has %d faces and no solid; select a closed solid (a Part solid, a "
            "PartDesign Body, or a Mesh that encloses a volume), or make one with Part > "
            "Convert to solid" % (_describe(obj), 0 if shape.isNull() else len(shape.Faces)))
    return shape


def model_from_object(obj, deflection, cap_holes=False):
    """The model of a Job: tessellated solid shape or a closed mesh (see the module comment).

    ``deflection``: chord error of the tessellation, mm. ``cap_holes``: accept an open mesh (the
    core closes it). Raises InvalidInput for anything that is not a solid.
    """
    if is_mesh_object(obj):
        vertices, triangles = mesh_arrays(obj.Mesh)
        if len(triangles) == 0:
            raise InvalidInput("empty mesh: %s has no triangles; select a closed mesh or a solid"
                               % _describe(obj))
        if not cap_holes:
            report = native.analyze_mesh(vertices, triangles)
            if report["open_edges"] > 0 or report["non_manifold_edges"] > 0:
                raise InvalidInput(
                    "open mesh: %s has %d open and %d non-manifold edges; repair it (Mesh > "
                    "Analyze > Evaluate and repair) or set the Job's CapHoles to true"
                    % (_describe(obj), report["open_edges"], report["non_manifold_edges"]))
        return {"vertices": vertices, "triangles": triangles, "face_ids": None, "kind": "mesh",
                "digest": _digest("mesh", vertices, triangles)}
    shape = solid_shape(obj)
    brep = shape.exportBrepToString()
    mesh = native.tessellate_brep(brep, deflection=deflection)
    return {"vertices": mesh["vertices"], "triangles": mesh["triangles"],
            "face_ids": mesh["face_ids"], "kind": "shape", "digest": _digest("shape", brep)}


def face_numbers(sub_names, owner):
    """FaceN numbers (1-based) of sub-element names such as ["Face3", "Face7"]."""
    numbers = []
    for name in sub_names:
        if not name.startswith("Face") or not name[4:].isdigit():
            raise InvalidInput(
                "start element is not a face: %s of %s; pick faces (FaceN) of the solid"
                % (name, owner.Label))
        numbers.append(int(name[4:]))
    return numbers


def surface_from_object(obj, sub_names, deflection):
    """Start-surface mesh from another object: the picked faces, or its whole surface.

    Returns (vertices, triangles, digest)."""
    if obj is None:
        raise InvalidInput("no start surface: StartSurface is empty; link the object (and faces) "
                           "the part grows from, or choose another StartMode")
    if is_mesh_object(obj):
        vertices, triangles = mesh_arrays(obj.Mesh)
        return vertices, triangles, _digest("mesh", vertices, triangles)
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull() or not shape.Faces:
        raise InvalidInput("start surface has no faces: %s; link an object with faces or a mesh"
                           % _describe(obj))
    if sub_names:
        import Part

        faces = [shape.getElement(name) for name in sub_names if name.startswith("Face")]
        if not faces:
            raise InvalidInput("start surface selection has no face: %s of %s; pick faces"
                               % (", ".join(sub_names), obj.Label))
        shape = Part.makeCompound(faces)
    brep = shape.exportBrepToString()
    mesh = native.tessellate_brep(brep, deflection=deflection)
    return mesh["vertices"], mesh["triangles"], _digest("surface", brep)


def vectors(vertices):
    """FreeCAD vectors of an (n, 3) array (Mesh.Mesh needs them)."""
    return [FreeCAD.Vector(*p) for p in np.asarray(vertices, dtype=float).tolist()]
