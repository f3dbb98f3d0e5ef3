// Unit tests of pipeline/option_parsing.hpp: the textual options of `curvedslicer layers`.
#include "curvedslicer/pipeline/option_parsing.hpp"

#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <string>
#include <vector>

#include "common/text_assertions.hpp"
#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

using Ids = std::vector<int>;

using testing::contains;

template <typename F>
std::string invalidInputMessage(F&& f) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected InvalidInput";
  return {};
}

TEST(OptionParsing, IdListSinglesAndRanges) {
  EXPECT_EQ(parseIdList("0-3,15"), (Ids{0, 1, 2, 3, 15}));
  EXPECT_EQ(parseIdList(" 7 , 2-2 ,5- 6"), (Ids{7, 2, 5, 6}));
  EXPECT_EQ(parseIdList("4,4,3-5"), (Ids{4, 3, 5}));  // duplicates removed, order kept
  EXPECT_EQ(parseIdList(std::to_string(INT_MAX)), (Ids{INT_MAX}));
}

TEST(OptionParsing, IdListRejectsBadSyntax) {
  for (const char* bad : {"", " ", "1,,2", "1,", ",1", "a", "1-a", "3-1", "-1", "+2", "1.5", "1--2",
                          "2147483648", "0-99999999999"}) {
    const std::string message = invalidInputMessage([&] { parseIdList(bad); });
    EXPECT_TRUE(contains(message, "face id list")) << "input '" << bad << "'";
    EXPECT_TRUE(contains(message, "0-9,15")) << "input '" << bad << "'";
  }
  EXPECT_TRUE(contains(invalidInputMessage([] { parseIdList("9-3"); }), "reversed range"));
  EXPECT_TRUE(contains(invalidInputMessage([] { parseIdList("0-60000000"); }), "longer than"));
}

TEST(OptionParsing, StartSpecPlaneBottomIsTheBuildPlate) {
  const StartSurfaceSpec spec = parseStartSurfaceSpec("plane:bottom");
  EXPECT_EQ(spec.surface.kind, StartSurface::Kind::Plane);
  EXPECT_TRUE(spec.surface.planeAtModelBottom);
  EXPECT_EQ(spec.text, "plane:bottom");
  EXPECT_TRUE(parseStartSurfaceSpec("Plane:Bottom").surface.planeAtModelBottom);
}

TEST(OptionParsing, StartSpecHorizontalPlane) {
  const StartSurfaceSpec spec = parseStartSurfaceSpec("plane:z=-12.5");
  EXPECT_EQ(spec.surface.kind, StartSurface::Kind::Plane);
  EXPECT_FALSE(spec.surface.planeAtModelBottom);
  EXPECT_DOUBLE_EQ(spec.surface.planePoint.z(), -12.5);
  EXPECT_DOUBLE_EQ(spec.surface.planeNormal.normalized().z(), 1.0);
  EXPECT_TRUE(
      contains(invalidInputMessage([] { parseStartSurfaceSpec("plane:z=abc"); }), "not a number"));
  EXPECT_TRUE(
      contains(invalidInputMessage([] { parseStartSurfaceSpec("plane:z=nan"); }), "finite"));
  EXPECT_TRUE(
      contains(invalidInputMessage([] { parseStartSurfaceSpec("plane:top"); }), "plane:bottom"));
}

TEST(OptionParsing, StartSpecFacesAndMesh) {
  const StartSurfaceSpec faces = parseStartSurfaceSpec("faces:0-2,9");
  EXPECT_EQ(faces.surface.kind, StartSurface::Kind::Faces);
  EXPECT_EQ(faces.surface.faceIds, (Ids{0, 1, 2, 9}));
  EXPECT_TRUE(
      contains(invalidInputMessage([] { parseStartSurfaceSpec("faces:1;2"); }), "face id list"));

  const StartSurfaceSpec mesh = parseStartSurfaceSpec("mesh:some/base.obj");
  EXPECT_EQ(mesh.surface.kind, StartSurface::Kind::Mesh);
  EXPECT_EQ(mesh.meshFile, std::filesystem::path("some/base.obj"));
  EXPECT_TRUE(contains(invalidInputMessage([] { parseStartSurfaceSpec("mesh:"); }), "mesh:FILE"));
}

TEST(OptionParsing, StartSpecUnknownKindListsTheForms) {
  for (const char* bad : {"bottom", "sphere:1", "", ":"}) {
    const std::string message = invalidInputMessage([&] { parseStartSurfaceSpec(bad); });
    EXPECT_TRUE(contains(message, "plane:bottom, plane:z=MM, faces:IDS")) << bad;
  }
}

TEST(OptionParsing, LoadStartSurfaceNamesTheMeshFile) {
  const StartSurfaceSpec spec = parseStartSurfaceSpec("mesh:/nonexistent/base.obj");
  const std::string message = invalidInputMessage([&] { loadStartSurface(spec); });
  EXPECT_TRUE(contains(message, "start surface mesh"));
  EXPECT_TRUE(contains(message, "/nonexistent/base.obj"));
  // Other kinds pass through unchanged.
  EXPECT_EQ(loadStartSurface(parseStartSurfaceSpec("faces:3")).faceIds, std::vector<int>{3});
}

TEST(OptionParsing, Lengths) {
  EXPECT_DOUBLE_EQ(parseLength("1.5", "x"), 1.5);
  EXPECT_DOUBLE_EQ(parseLength(" 2e-1 ", "x"), 0.2);
  EXPECT_DOUBLE_EQ(parseLength("-3", "x"), -3.0);  // range checks come later
  EXPECT_TRUE(std::isnan(parseLength("nan", "x")));
  EXPECT_TRUE(std::isinf(parseLength("inf", "x")));
  for (const char* bad : {"", "abc", "1.5mm", "1,5"}) {
    const std::string message = invalidInputMessage([&] { parseLength(bad, "voxel size"); });
    EXPECT_TRUE(contains(message, "voxel size is not a number")) << bad;
  }
}

TEST(OptionParsing, GridAlignmentAndFormatNames) {
  EXPECT_EQ(parseGridAlignment("pca"), GridAlignment::Pca);
  EXPECT_EQ(parseGridAlignment("MODEL"), GridAlignment::Model);
  EXPECT_EQ(toString(GridAlignment::Pca), "pca");
  EXPECT_EQ(toString(GridAlignment::Model), "model");
  EXPECT_TRUE(contains(invalidInputMessage([] { parseGridAlignment("obb"); }), "pca"));
  EXPECT_EQ(parseLayerFileFormat("ply"), LayerFileFormat::Ply);
  EXPECT_EQ(parseLayerFileFormat("Obj"), LayerFileFormat::Obj);
  EXPECT_EQ(toString(LayerFileFormat::Ply), "ply");
  EXPECT_EQ(toString(LayerFileFormat::Obj), "obj");
  EXPECT_TRUE(contains(invalidInputMessage([] { parseLayerFileFormat("stl"); }), "ply or obj"));
}

}  // namespace
}  // namespace curvedslicer
