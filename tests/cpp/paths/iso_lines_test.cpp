// Iso-lines by marching triangles and the bead value sequence.
#include "curvedslicer/paths/iso_lines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "curvedslicer/core/error.hpp"
#include "paths/revolution_meshes.hpp"

namespace curvedslicer {
namespace {

using testing::makeRectangleMesh;

TEST(IsoLines, LinearFieldGivesExactStraightLines) {
  const TriMesh mesh = makeRectangleMesh(0, 10, 0, 8, 10, 8);
  std::vector<double> f;
  for (const Vec3& v : mesh.vertices) f.push_back(0.6 * v.x() + 0.8 * v.y());
  const std::vector<Polyline> lines = extractIsoLines(mesh, f, 5.05);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_FALSE(lines[0].closed);
  for (const Vec3& p : lines[0].points) EXPECT_NEAR(0.6 * p.x() + 0.8 * p.y(), 5.05, 1e-12);
  // Ends on the boundary: the line leaves the surface there.
  for (const Vec3* end : {&lines[0].points.front(), &lines[0].points.back()}) {
    const bool onBoundary = std::abs(end->x()) < 1e-12 || std::abs(end->x() - 10) < 1e-12 ||
                            std::abs(end->y()) < 1e-12 || std::abs(end->y() - 8) < 1e-12;
    EXPECT_TRUE(onBoundary);
  }
  // Orientation: larger values on the left seen from +z (the triangles' normal side).
  const Vec3 dir = lines[0].points.back() - lines[0].points.front();
  const Vec3 left = Vec3::UnitZ().cross(dir);
  EXPECT_GT(left.dot(Vec3(0.6, 0.8, 0)), 0.0);
}

TEST(IsoLines, RadialFieldGivesClosedCircle) {
  const TriMesh mesh = makeRectangleMesh(-10, 10, -10, 10, 40, 40);
  std::vector<double> f;
  for (const Vec3& v : mesh.vertices) f.push_back(v.norm());
  const std::vector<Polyline> lines = extractIsoLines(mesh, f, 6.1);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_TRUE(lines[0].closed);
  EXPECT_NEAR(lines[0].length(), 2 * M_PI * 6.1, 0.05);
  for (const Vec3& p : lines[0].points) EXPECT_NEAR(p.norm(), 6.1, 0.03);
}

TEST(IsoLines, SplitWhereTheFieldStops) {
  const TriMesh mesh = makeRectangleMesh(0, 10, 0, 10, 10, 10);
  std::vector<double> f;
  for (const Vec3& v : mesh.vertices) {
    // No value in a vertical strip: the line x + ... at y = 5.5 is cut into two pieces.
    f.push_back(v.x() > 3.5 && v.x() < 6.5 ? std::numeric_limits<double>::infinity() : v.y());
  }
  const std::vector<Polyline> lines = extractIsoLines(mesh, f, 5.5);
  EXPECT_EQ(lines.size(), 2u);
  for (const Polyline& l : lines) {
    EXPECT_FALSE(l.closed);
    for (const Vec3& p : l.points) EXPECT_NEAR(p.y(), 5.5, 1e-12);
  }
}

TEST(IsoLines, ManyValuesInOnePassEqualOneAtATime) {
  // A wavy radial field with a hole of no values, values in any order, some exactly at vertex
  // values (0 and 2, where vertices count as above), one crossing nothing (50), one repeated.
  const TriMesh mesh = makeRectangleMesh(-10, 10, -10, 10, 40, 40);
  std::vector<double> f;
  for (const Vec3& v : mesh.vertices) {
    const bool hole = std::abs(v.x() - 4.0) < 1.2 && std::abs(v.y()) < 1.2;
    f.push_back(hole ? std::nan("") : v.norm() + 0.3 * std::sin(3.0 * v.x()) + std::round(v.y()));
  }
  const std::vector<double> values = {6.1, 0.0, 2.0, 50.0, -3.5, 6.1, 11.25, 1.7};
  const std::vector<std::vector<Polyline>> batch = extractIsoLines(mesh, f, values);
  ASSERT_EQ(batch.size(), values.size());
  std::size_t lines = 0;
  for (std::size_t k = 0; k < values.size(); ++k) {
    SCOPED_TRACE(values[k]);
    const std::vector<Polyline> single = extractIsoLines(mesh, f, values[k]);
    ASSERT_EQ(batch[k].size(), single.size());
    for (std::size_t i = 0; i < single.size(); ++i) {
      EXPECT_EQ(batch[k][i].closed, single[i].closed);
      EXPECT_EQ(batch[k][i].points, single[i].points);  // bit-identical
    }
    lines += single.size();
  }
  EXPECT_GT(lines, 8u);
  EXPECT_TRUE(batch[3].empty());
  EXPECT_THROW(extractIsoLines(mesh, f, std::vector<double>{1.0, INFINITY}), InvalidInput);
}

TEST(IsoLines, ValueSequence) {
  EXPECT_EQ(computeIsoValues(2.0, 7.0, IsoValueStart::Boundary), (std::vector<double>{1, 3, 5, 7}));
  EXPECT_EQ(computeIsoValues(2.0, 7.0, IsoValueStart::InteriorCurve),
            (std::vector<double>{0, 2, 4, 6}));
  EXPECT_TRUE(computeIsoValues(2.0, 0.5, IsoValueStart::Boundary).empty());
  EXPECT_THROW(computeIsoValues(0.0, 7.0, IsoValueStart::Boundary), InvalidInput);
  EXPECT_THROW(computeIsoValues(-1.0, 7.0, IsoValueStart::Boundary), InvalidInput);
  EXPECT_THROW(computeIsoValues(1e-9, 7.0, IsoValueStart::Boundary), InvalidInput);
}

TEST(IsoLines, BadInput) {
  const TriMesh mesh = makeRectangleMesh(0, 1, 0, 1, 1, 1);
  EXPECT_THROW(extractIsoLines(mesh, {1.0, 2.0}, 0.5), InvalidInput);
  EXPECT_THROW(extractIsoLines(mesh, {0, 1, 2, 3}, std::nan("")), InvalidInput);
  EXPECT_TRUE(extractIsoLines(TriMesh{}, {}, 0.5).empty());
}

}  // namespace
}  // namespace curvedslicer
