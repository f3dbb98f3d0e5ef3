// Analytic test solids as closed, outward-oriented triangle meshes (mm), for tests and benchmarks.
// Every generator is deterministic. "segments" = facets around a circle.
#pragma once

#include <string>

#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer::testing {

/// Axis-aligned box [min, max], 12 triangles.
TriMesh makeBox(const Vec3& min, const Vec3& max);

/// Box with each face split into an n×n grid of quads (2 triangles each).
TriMesh makeSubdividedBox(const Vec3& min, const Vec3& max, int n);

/// Applies a rigid rotation (about `center`) to all vertices.
TriMesh rotated(const TriMesh& mesh, const Mat3& rotation, const Vec3& center);

/// Sphere from a subdivided icosahedron (`subdivisions` ≥ 0; 20·4^s triangles), vertices on the
/// sphere.
TriMesh makeSphere(const Vec3& center, double radius, int subdivisions);

/// Thick spherical shell R1 < R2: outer sphere outward, inner sphere inward (one closed solid with
/// a cavity). Use `innerSurface` for the inner sphere as a start surface.
TriMesh makeSphericalShell(const Vec3& center, double r1, double r2, int subdivisions);

/// Torus around the z axis: major radius R, minor radius r.
TriMesh makeTorus(const Vec3& center, double majorRadius, double minorRadius, int majorSegments,
                  int minorSegments);

/// Cylinder/prism along z: base at z0, height h, `segments` sides (a regular polygon inscribed in
/// the circle of `radius`). `rings` ≥ 1 splits the side into rings; caps are fans around a
/// centre vertex.
TriMesh makeCylinder(const Vec3& baseCenter, double radius, double height, int segments,
                     int rings = 1);

/// The same solid as makeCylinder(…, segments, 1) but tessellated with sliver triangles: caps as
/// fans from one rim vertex (long thin triangles) and sides split into thin strips with steep
/// diagonals.
TriMesh makeSliverCylinder(const Vec3& baseCenter, double radius, double height, int segments);

/// The same prism, each side quad and cap refined so the total is about `targetTriangles`.
TriMesh makeFineCylinder(const Vec3& baseCenter, double radius, double height, int segments,
                         int targetTriangles);

/// Truncated cone along z (r0 at base z0, r1 at top).
TriMesh makeCone(const Vec3& baseCenter, double r0, double r1, double height, int segments);

/// L-shaped prism extruded along z over [0, height]: leg 1 = [0, a]×[0, w], leg 2 = [0, w]×[0, b].
/// The re-entrant edge is the line x = y = w. Face ids: the end face of leg 1 (x = a) has id 1,
/// the end face of leg 2 (y = b) id 2, every other triangle 0.
TriMesh makeLPrism(double a, double b, double w, double height);

/// Half annulus (U-bend, rectangular section) in the xy-plane: inner radius ri, outer ro, angles
/// θ ∈ [0, π] (y ≥ 0), extruded over z ∈ [0, height]. Face ids: end face at θ = 0 (y = 0, x > 0)
/// has id 1, end face at θ = π (y = 0, x < 0) id 2, every other triangle 0.
TriMesh makeHalfAnnulus(double ri, double ro, double height, int segments);

/// U-channel prism in the xy-plane: arms [0,a]×[0,w] and [0,a]×[b−w,b] joined by [0,w]×[0,b],
/// extruded over z ∈ [0, height]; two reflex edges at (w, w) and (w, b − w). Face id 1: the end
/// face x = a of the lower arm.
TriMesh makeUChannel(double a, double b, double w, double height);

/// Open-top box (a thin-walled shell): the outer box [0, size.x]×[0, size.y]×[0, size.z] minus the
/// cavity [wall, size.x − wall]×[wall, size.y − wall]×[wall, size.z] (floor and four side walls of
/// thickness `wall`, open at z = size.z), 28 triangles, closed and outward-oriented; the cavity's
/// eight edges are reflex edges of the solid.
TriMesh makeOpenBox(const Vec3& size, double wall);

/// Flat rectangle [x0, x1] × [y0, y1] at height z, n × m cells of two triangles each, normals +z
/// (an open surface, e.g. a flat layer).
TriMesh makeFlatGrid(double x0, double x1, double y0, double y1, double z, int n, int m);

/// Removes every k-th triangle so that about `fraction` of them are gone (deterministic).
TriMesh deleteTriangles(const TriMesh& mesh, double fraction);

/// Writes `mesh` as binary STL to a fresh file under the test temp folder and returns its path.
std::string writeTempStl(const TriMesh& mesh, const std::string& name);

}  // namespace curvedslicer::testing
