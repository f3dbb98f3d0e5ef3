// Tests of computePcaFrame (frame.hpp): axes of rotated boxes, tessellation independence,
// determinism, the snapping of degenerate (equal-variance) axes to the model axes, bad input.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/shapes.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/voxel/frame.hpp"

namespace curvedslicer::testing {
namespace {

Mat3 someRotation() {
  return Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
}

void expectProperFrame(const Frame& frame) {
  const Mat3& R = frame.rotation;
  EXPECT_NEAR((R.transpose() * R - Mat3::Identity()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  // x and y are signed so that their largest-magnitude component is positive.
  for (int c = 0; c < 2; ++c) {
    Eigen::Index largest = 0;
    R.col(c).cwiseAbs().maxCoeff(&largest);
    EXPECT_GT(R(largest, c), 0.0) << "column " << c;
  }
}

TEST(PcaFrame, RotatedBoxRecoversItsAxes) {
  const Vec3 center(12.0, -4.0, 7.0);
  const Vec3 half(15.0, 10.0, 5.0);  // distinct extents: x longest, z shortest
  const Mat3 R = someRotation();
  const TriMesh box = rotated(makeBox(center - half, center + half), R, center);
  const Frame frame = computePcaFrame(box);
  expectProperFrame(frame);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(std::abs(frame.rotation.col(c).dot(R.col(c))), 1.0, 1e-12) << "axis " << c;
  }
  EXPECT_NEAR((frame.origin - center).norm(), 0.0, 1e-12);
  // The box is symmetric in its own frame.
  Aabb local;
  for (const Vec3& p : box.vertices) local.extend(frame.toFrame(p));
  EXPECT_NEAR((local.max - half).norm(), 0.0, 1e-9);
  EXPECT_NEAR((local.min + half).norm(), 0.0, 1e-9);
}

TEST(PcaFrame, IndependentOfTessellation) {
  const Vec3 lo(-3.0, 1.0, 2.0), hi(17.0, 9.0, 5.0);
  const Mat3 R = someRotation();
  const Vec3 c = 0.5 * (lo + hi);
  const Frame coarse = computePcaFrame(rotated(makeBox(lo, hi), R, c));
  const Frame fine = computePcaFrame(rotated(makeSubdividedBox(lo, hi, 7), R, c));
  EXPECT_NEAR((coarse.rotation - fine.rotation).norm(), 0.0, 1e-9);
  EXPECT_NEAR((coarse.origin - fine.origin).norm(), 0.0, 1e-9);
}

TEST(PcaFrame, DeterministicAndIndependentOfTriangleOrder) {
  const TriMesh bunny = readMesh(modelPath("bunny_closed_low_res.stl"));
  const Frame a = computePcaFrame(bunny);
  const Frame b = computePcaFrame(bunny);
  EXPECT_EQ(a.rotation, b.rotation);
  EXPECT_EQ(a.origin, b.origin);
  expectProperFrame(a);

  TriMesh reordered = bunny;
  std::reverse(reordered.triangles.begin(), reordered.triangles.end());
  for (Vec3i& t : reordered.triangles) t = Vec3i(t[1], t[2], t[0]);
  const Frame c = computePcaFrame(reordered);
  EXPECT_NEAR((a.rotation - c.rotation).norm(), 0.0, 1e-9);
  EXPECT_NEAR((a.origin - c.origin).norm(), 0.0, 1e-9);
}

TEST(PcaFrame, CubeAndSphereStayModelAligned) {
  const Frame cube = computePcaFrame(makeBox(Vec3(1, 2, 3), Vec3(11, 12, 13)));
  EXPECT_EQ(cube.rotation, Mat3::Identity());
  EXPECT_NEAR((cube.origin - Vec3(6, 7, 8)).norm(), 0.0, 1e-12);

  const Frame fineCube = computePcaFrame(makeSubdividedBox(Vec3(0, 0, 0), Vec3(5, 5, 5), 6));
  EXPECT_EQ(fineCube.rotation, Mat3::Identity());

  const Frame sphere = computePcaFrame(makeSphere(Vec3(1, 1, 1), 4.0, 3));
  EXPECT_EQ(sphere.rotation, Mat3::Identity());
}

TEST(PcaFrame, CylinderStaysModelAligned) {
  // Tall cylinder along z: the axis has the largest variance; the two equal ones snap to x, y.
  const Frame tall = computePcaFrame(makeCylinder(Vec3(0, 0, 0), 10.0, 60.0, 64));
  Mat3 expected;
  expected.col(0) = Vec3::UnitZ();
  expected.col(1) = Vec3::UnitX();
  expected.col(2) = Vec3::UnitY();
  EXPECT_EQ(tall.rotation, expected);
  EXPECT_NEAR((tall.origin - Vec3(0, 0, tall.origin.z())).norm(), 0.0, 1e-12);

  // Flat disc: the two equal variances are the largest.
  const Frame disc = computePcaFrame(makeCylinder(Vec3(5, 5, 0), 20.0, 3.0, 48));
  EXPECT_EQ(disc.rotation, Mat3::Identity());

  // Tall cylinder along x (exact axis permutation of the vertices).
  TriMesh alongX = makeCylinder(Vec3(0, 0, 0), 10.0, 60.0, 64);
  for (Vec3& p : alongX.vertices) p = Vec3(p.z(), p.x(), p.y());
  EXPECT_EQ(computePcaFrame(alongX).rotation, Mat3::Identity());
}

TEST(PcaFrame, BundledBoxAndCylinderStayModelAligned) {
  // Single-precision STL coordinates: the equal variances still agree within the tolerance.
  EXPECT_EQ(computePcaFrame(readMesh(modelPath("simple_box_closed_low_res.stl"))).rotation,
            Mat3::Identity());
  Mat3 tall;
  tall.col(0) = Vec3::UnitZ();
  tall.col(1) = Vec3::UnitX();
  tall.col(2) = Vec3::UnitY();
  EXPECT_EQ(computePcaFrame(readMesh(modelPath("simple_cylinder_closed_mid_res.stl"))).rotation,
            tall);
}

TEST(PcaFrame, TiltedCylinderKeepsOneModelAxisInItsCrossSection) {
  // Axis in the yz-plane: the model x axis lies in the degenerate cross-section plane, so it
  // becomes the second grid axis.
  const Mat3 tilt = Eigen::AngleAxisd(0.4, Vec3::UnitX()).toRotationMatrix();
  const TriMesh cylinder = rotated(makeCylinder(Vec3(0, 0, 0), 5.0, 40.0, 96), tilt, Vec3::Zero());
  const Frame frame = computePcaFrame(cylinder);
  expectProperFrame(frame);
  EXPECT_NEAR(std::abs(frame.rotation.col(0).dot(tilt.col(2))), 1.0, 1e-12);
  EXPECT_NEAR((frame.rotation.col(1) - Vec3::UnitX()).norm(), 0.0, 1e-9);
}

TEST(PcaFrame, RejectsEmptyDegenerateAndNonFiniteMeshes) {
  EXPECT_THROW(computePcaFrame(TriMesh{}), InvalidInput);

  TriMesh collinear;
  collinear.vertices = {Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)};
  collinear.triangles = {Vec3i(0, 1, 2), Vec3i(0, 2, 1)};
  try {
    computePcaFrame(collinear);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("zero surface area"), std::string::npos) << e.what();
  }

  TriMesh nan = makeBox(Vec3(0, 0, 0), Vec3(1, 1, 1));
  nan.vertices[3].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(computePcaFrame(nan), InvalidInput);

  TriMesh badIndex = makeBox(Vec3(0, 0, 0), Vec3(1, 1, 1));
  badIndex.triangles[2][1] = 99;
  EXPECT_THROW(computePcaFrame(badIndex), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer::testing
