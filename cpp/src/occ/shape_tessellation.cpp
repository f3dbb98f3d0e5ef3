// OpenCASCADE tessellation with FreeCAD face numbers (see occ/shape_tessellation.hpp).
#include "curvedslicer/occ/shape_tessellation.hpp"

#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopAbs_ShapeEnum.hxx>
#include <TopExp.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"

namespace curvedslicer {
namespace {

// Fraction of the bounding-box diagonal within which tessellation nodes are merged (the layer
// job's default weld tolerance, mesh_repair.hpp).
constexpr double kRelativeWeldTolerance = 1e-6;

std::string describeFailure(const Standard_Failure& failure) {
  const char* text = failure.GetMessageString();
  std::string what = failure.DynamicType()->Name();
  if (text != nullptr && *text != '\0') what += std::string(" (") + text + ")";
  return what;
}

void checkOptions(const TessellationOptions& options) {
  if (!(options.linearDeflection > 0.0) || !std::isfinite(options.linearDeflection)) {
    throw InvalidInput("tessellation deflection must be positive and finite: " +
                       std::to_string(options.linearDeflection) +
                       " mm; pass about a quarter of the voxel size");
  }
  if (!(options.angularDeflection > 0.0) || !std::isfinite(options.angularDeflection)) {
    throw InvalidInput("tessellation angular deflection must be positive and finite: " +
                       std::to_string(options.angularDeflection) + " rad; pass e.g. 0.5");
  }
}

TopoDS_Shape readBrepText(std::string_view brep) {
  TopoDS_Shape shape;
  try {
    std::istringstream in{std::string(brep)};
    BRep_Builder builder;
    BRepTools::Read(shape, in, builder);
  } catch (const Standard_Failure& failure) {
    throw InvalidInput("BREP text could not be read: " + describeFailure(failure) +
                       "; pass the output of shape.exportBrepToString()");
  }
  if (shape.IsNull()) {
    throw InvalidInput("BREP text holds no shape: " + std::to_string(brep.size()) +
                       " characters; pass the output of shape.exportBrepToString()");
  }
  return shape;
}

// The shape's faces in FreeCAD's FaceN order (index 1..n).
TopTools_IndexedMapOfShape mapFaces(const TopoDS_Shape& shape) {
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  if (faces.Extent() == 0) {
    throw InvalidInput(
        "shape has no faces: 0 faces; pass a solid, shell or face (not a wire or points)");
  }
  return faces;
}

TriMesh tessellateShape(TopoDS_Shape shape, const TessellationOptions& options) {
  checkOptions(options);
  const TopTools_IndexedMapOfShape faces = mapFaces(shape);
  TriMesh soup;
  try {
    // Drop triangulations stored with the shape so the result depends only on the options.
    BRepTools::Clean(shape);
    BRepMesh_IncrementalMesh mesher(shape, options.linearDeflection, Standard_False,
                                    options.angularDeflection, Standard_False);
    (void)mesher;
    for (int faceId = 1; faceId <= faces.Extent(); ++faceId) {
      const TopoDS_Face& face = TopoDS::Face(faces(faceId));
      TopLoc_Location location;
      const Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
      if (triangulation.IsNull() || triangulation->NbTriangles() == 0) {
        throw InvalidInput("face could not be triangulated: Face" + std::to_string(faceId) +
                           "; check the shape (Part > Check geometry) or use a larger deflection");
      }
      const gp_Trsf transform = location.Transformation();
      const bool reversed = face.Orientation() == TopAbs_REVERSED;
      const int base = static_cast<int>(soup.vertices.size());
      for (int n = 1; n <= triangulation->NbNodes(); ++n) {
        const gp_Pnt p = triangulation->Node(n).Transformed(transform);
        soup.vertices.emplace_back(p.X(), p.Y(), p.Z());
      }
      for (int t = 1; t <= triangulation->NbTriangles(); ++t) {
        int a = 0, b = 0, c = 0;
        triangulation->Triangle(t).Get(a, b, c);
        if (reversed) std::swap(b, c);
        soup.triangles.emplace_back(base + a - 1, base + b - 1, base + c - 1);
        soup.faceIds.push_back(faceId);
      }
    }
  } catch (const Standard_Failure& failure) {
    throw InvalidInput("OpenCASCADE failed to tessellate the shape: " + describeFailure(failure) +
                       "; check the shape (Part > Check geometry) or change the deflection");
  }
  // Weld the edge nodes shared by neighbouring faces: bit-identical on plain edges, a tolerance
  // apart on edges of boolean results (each face evaluates its own surface there).
  CleanOptions weld;
  weld.relativeWeldTolerance = kRelativeWeldTolerance;
  weld.removeDuplicates = false;
  TriMesh mesh = std::move(cleanMesh(soup, weld).mesh);
  return mesh;
}

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

CadFormat detectCadFormat(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".step" || ext == ".stp") return CadFormat::Step;
  if (ext == ".iges" || ext == ".igs") return CadFormat::Iges;
  if (ext == ".brep" || ext == ".brp") return CadFormat::Brep;
  std::ifstream in(path, std::ios::binary);
  std::string head(256, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (head.find("ISO-10303-21") != std::string::npos) return CadFormat::Step;
  if (head.find("CASCADE Topology") != std::string::npos) return CadFormat::Brep;
  // IGES: fixed 80-column records with the section letter in column 73 ('S' for the start).
  if (head.size() >= 73 && head[72] == 'S') return CadFormat::Iges;
  throw InvalidInput("CAD file format not recognised: " + path.string() +
                     "; use a .step/.stp, .iges/.igs or .brep file");
}

}  // namespace

std::string_view toString(CadFormat format) {
  switch (format) {
    case CadFormat::Auto:
      return "auto";
    case CadFormat::Step:
      return "step";
    case CadFormat::Iges:
      return "iges";
    case CadFormat::Brep:
      return "brep";
  }
  return "auto";
}

CadFormat parseCadFormat(std::string_view name) {
  for (CadFormat f : {CadFormat::Auto, CadFormat::Step, CadFormat::Iges, CadFormat::Brep}) {
    if (name == toString(f)) return f;
  }
  throw InvalidInput("unknown CAD format: '" + std::string(name) +
                     "'; use 'auto', 'step', 'iges' or 'brep'");
}

double deflectionForVoxelSize(double voxelSize) {
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize)) {
    throw InvalidInput("voxel size must be positive and finite: " + std::to_string(voxelSize) +
                       " mm; pass a value such as 0.5");
  }
  return 0.25 * voxelSize;
}

TriMesh tessellateBrepText(std::string_view brep, const TessellationOptions& options) {
  checkOptions(options);
  return tessellateShape(readBrepText(brep), options);
}

int countBrepFaces(std::string_view brep) {
  return mapFaces(readBrepText(brep)).Extent();
}

TriMesh tessellateCadFile(const std::filesystem::path& path, CadFormat format,
                          const TessellationOptions& options) {
  checkOptions(options);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InvalidInput("CAD file not found: " + path.string() + "; check the path");
  }
  if (format == CadFormat::Auto) format = detectCadFormat(path);
  TopoDS_Shape shape;
  try {
    if (format == CadFormat::Brep) {
      BRep_Builder builder;
      if (!BRepTools::Read(shape, path.string().c_str(), builder)) shape.Nullify();
    } else if (format == CadFormat::Step) {
      STEPControl_Reader reader;
      if (reader.ReadFile(path.string().c_str()) == IFSelect_RetDone) {
        reader.TransferRoots();
        shape = reader.OneShape();
      }
    } else {
      IGESControl_Reader reader;
      if (reader.ReadFile(path.string().c_str()) == IFSelect_RetDone) {
        reader.TransferRoots();
        shape = reader.OneShape();
      }
    }
  } catch (const Standard_Failure& failure) {
    throw InvalidInput("CAD file could not be read: " + path.string() + " (" +
                       describeFailure(failure) + "); export it again from the CAD program");
  }
  if (shape.IsNull()) {
    throw InvalidInput("CAD file holds no shape: " + path.string() +
                       "; check that it is a valid STEP/IGES/BREP file with a solid");
  }
  return tessellateShape(shape, options);
}

}  // namespace curvedslicer
