#include "curvedslicer/field/start_surface.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <string>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace {

std::string formatMm(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

std::string joinIds(const std::vector<int>& ids, std::size_t limit = 12) {
  std::ostringstream s;
  for (std::size_t i = 0; i < ids.size() && i < limit; ++i) s << (i ? "," : "") << ids[i];
  if (ids.size() > limit) s << ",… (" << ids.size() << " in all)";
  return s.str();
}

bool finite(const Vec3& v) {
  return v.allFinite();
}

}  // namespace

std::string_view toString(StartSurface::Kind kind) {
  switch (kind) {
    case StartSurface::Kind::Plane:
      return "plane";
    case StartSurface::Kind::Faces:
      return "faces";
    case StartSurface::Kind::Mesh:
      return "mesh";
  }
  return "plane";
}

StartSurface::Kind parseStartSurfaceKind(std::string_view name) {
  for (StartSurface::Kind kind :
       {StartSurface::Kind::Plane, StartSurface::Kind::Faces, StartSurface::Kind::Mesh}) {
    if (name == toString(kind)) return kind;
  }
  throw InvalidInput("unknown start surface kind: '" + std::string(name) +
                     "'; choose plane, faces or mesh");
}

std::string StartSurface::describe() const {
  switch (kind) {
    case Kind::Plane:
      if (planeAtModelBottom) return "plane at the model's bottom (build plate)";
      if (planeNormal.normalized().isApprox(Vec3::UnitZ()))
        return "plane z=" + formatMm(planePoint.z()) + " mm";
      return "plane through (" + formatMm(planePoint.x()) + ", " + formatMm(planePoint.y()) + ", " +
             formatMm(planePoint.z()) + ") mm with normal (" + formatMm(planeNormal.x()) + ", " +
             formatMm(planeNormal.y()) + ", " + formatMm(planeNormal.z()) + ")";
    case Kind::Faces:
      return "faces " + joinIds(faceIds);
    case Kind::Mesh:
      return "surface mesh (" + std::to_string(mesh.triangleCount()) + " triangles)";
  }
  return "unknown";
}

TriMesh resolveStartSurface(const TriMesh& model, const StartSurface& start) {
  TriMesh source;
  switch (start.kind) {
    case StartSurface::Kind::Plane: {
      const Aabb box = model.bounds();
      if (box.empty()) {
        throw InvalidInput(
            "cannot place a start plane: the model has no vertices; load a model first");
      }
      Vec3 n = start.planeNormal;
      if (!finite(n) || n.norm() < 1e-12) {
        throw InvalidInput("start plane normal must be a non-zero vector: (" + formatMm(n.x()) +
                           ", " + formatMm(n.y()) + ", " + formatMm(n.z()) +
                           "); give a direction such as 0,0,1");
      }
      n.normalize();
      Vec3 p = start.planeAtModelBottom ? Vec3(box.center().x(), box.center().y(), box.min.z())
                                        : start.planePoint;
      if (start.planeAtModelBottom) n = Vec3::UnitZ();
      if (!finite(p)) {
        throw InvalidInput("start plane position is not a finite number; give coordinates in mm");
      }
      // Project the box centre onto the plane; a square of half-size = box diagonal covers the
      // model's footprint on any plane orientation.
      const Vec3 c = box.center() - n * n.dot(box.center() - p);
      const double half = std::max(box.diagonal(), 1e-3);
      Vec3 u = n.unitOrthogonal();
      Vec3 v = n.cross(u);
      source.vertices = {c - half * u - half * v, c + half * u - half * v, c + half * u + half * v,
                         c - half * u + half * v};
      source.triangles = {Vec3i(0, 1, 2), Vec3i(0, 2, 3)};
      break;
    }
    case StartSurface::Kind::Faces: {
      if (start.faceIds.empty()) {
        throw InvalidInput("no start faces given; list face ids such as faces:0-9,15");
      }
      if (model.faceIds.size() != model.triangles.size()) {
        throw InvalidInput(
            "the model carries no face ids, so faces cannot be selected; use a plane or a surface "
            "mesh as the start surface");
      }
      const std::set<int> wanted(start.faceIds.begin(), start.faceIds.end());
      std::set<int> found;
      std::vector<int> remap(model.vertices.size(), -1);
      for (std::size_t t = 0; t < model.triangles.size(); ++t) {
        if (!wanted.count(model.faceIds[t])) continue;
        found.insert(model.faceIds[t]);
        Vec3i tri;
        for (int k = 0; k < 3; ++k) {
          int& m = remap[model.triangles[t][k]];
          if (m < 0) {
            m = static_cast<int>(source.vertices.size());
            source.vertices.push_back(model.vertices[model.triangles[t][k]]);
          }
          tri[k] = m;
        }
        source.triangles.push_back(tri);
        source.faceIds.push_back(model.faceIds[t]);
      }
      std::vector<int> missing;
      for (int id : wanted)
        if (!found.count(id)) missing.push_back(id);
      if (!missing.empty()) {
        // STL/OBJ ids count triangles from 0, CAD ids (FreeCAD's FaceN) faces from 1: the range
        // the model has
        const auto [low, high] =
            model.faceIds.empty()
                ? std::pair<int, int>{0, -1}
                : std::pair<int, int>{
                      *std::min_element(model.faceIds.begin(), model.faceIds.end()),
                      *std::max_element(model.faceIds.begin(), model.faceIds.end())};
        throw InvalidInput("start face ids not found in the model: " + joinIds(missing) +
                           "; valid ids are " + std::to_string(low) + ".." + std::to_string(high) +
                           " (triangles removed as degenerate or duplicate have no id)");
      }
      break;
    }
    case StartSurface::Kind::Mesh: {
      if (start.mesh.triangles.empty()) {
        throw InvalidInput("the start surface mesh has no triangles; give a surface with faces");
      }
      for (std::size_t i = 0; i < start.mesh.vertices.size(); ++i) {
        if (!finite(start.mesh.vertices[i])) {
          throw InvalidInput("start surface vertex " + std::to_string(i) +
                             " has a non-finite coordinate; repair the surface mesh");
        }
      }
      for (const Vec3i& t : start.mesh.triangles) {
        if (t.minCoeff() < 0 || t.maxCoeff() >= static_cast<int>(start.mesh.vertices.size())) {
          throw InvalidInput("start surface mesh has a triangle index out of range; repair it");
        }
      }
      source = start.mesh;
      break;
    }
  }
  return source;
}

}  // namespace curvedslicer
