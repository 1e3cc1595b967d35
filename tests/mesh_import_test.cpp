// Mesh import: every format reads the same 10 mm cube; faces come from groups or sharp
// edges; real meshes of the shared data set.

#include "support.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>

#include <cstring>
#include <sstream>

namespace scanplan {
namespace {

constexpr double kSize = 10;

TriangleMesh cube() {
  TriangleMesh mesh;
  test::addCube(mesh, Vec3::Zero(), kSize, 1);
  return mesh;
}

std::string asciiStl(const TriangleMesh& mesh) {
  std::ostringstream out;
  out << "solid cube\n";
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Vec3 n = mesh.normal(t);
    out << " facet normal " << n.x() << ' ' << n.y() << ' ' << n.z() << "\n  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.vertices[mesh.triangles[t][k]];
      out << "   vertex " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    }
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid cube\n";
  return out.str();
}

std::string binaryStl(const TriangleMesh& mesh) {
  std::string out(80, ' ');
  auto put = [&](const void* data, std::size_t size) {
    out.append(static_cast<const char*>(data), size);
  };
  auto count = static_cast<std::uint32_t>(mesh.triangles.size());
  put(&count, 4);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Vec3 n = mesh.normal(t);
    float values[12];
    for (int k = 0; k < 3; ++k) values[k] = static_cast<float>(n[k]);
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k)
        values[3 + 3 * v + k] = static_cast<float>(mesh.vertices[mesh.triangles[t][v]][k]);
    put(values, sizeof values);
    std::uint16_t attributes = 0;
    put(&attributes, 2);
  }
  return out;
}

// OBJ with one group per side ("side0".."side5") and quads.
std::string groupedObj(const TriangleMesh& mesh) {
  std::ostringstream out;
  for (const Vec3& p : mesh.vertices) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (std::size_t q = 0; q < 6; ++q) {
    const Vec3i& a = mesh.triangles[2 * q];
    const Vec3i& b = mesh.triangles[2 * q + 1];
    out << "g side" << q << "\nf " << a[0] + 1 << ' ' << a[1] + 1 << ' ' << a[2] + 1 << ' '
        << b[2] + 1 << '\n';
  }
  return out.str();
}

std::string ply(const TriangleMesh& mesh, bool binary, bool with_groups) {
  std::ostringstream out;
  out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
      << "comment a cube\nelement vertex " << mesh.vertices.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\n";
  if (with_groups) out << "property int group\n";
  out << "end_header\n";
  for (const Vec3& p : mesh.vertices) {
    if (binary) {
      float xyz[3] = {static_cast<float>(p.x()), static_cast<float>(p.y()),
                      static_cast<float>(p.z())};
      out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
    } else {
      out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    }
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    // Sides bottom, top, front, back, left, right in groups 0, 1, 0, 1, 2, 2: bottom and
    // front meet, top and back meet, left and right are apart.
    const int side_group[6] = {0, 1, 0, 1, 2, 2};
    int group = side_group[t / 2];
    if (binary) {
      unsigned char n = 3;
      out.write(reinterpret_cast<const char*>(&n), 1);
      for (int k = 0; k < 3; ++k)
        out.write(reinterpret_cast<const char*>(&mesh.triangles[t][k]), 4);
      if (with_groups) out.write(reinterpret_cast<const char*>(&group), 4);
    } else {
      out << "3 " << mesh.triangles[t][0] << ' ' << mesh.triangles[t][1] << ' '
          << mesh.triangles[t][2];
      if (with_groups) out << ' ' << group;
      out << '\n';
    }
  }
  return out.str();
}

std::string off(const TriangleMesh& mesh) {
  std::ostringstream out;
  out << "OFF\n# a cube\n" << mesh.vertices.size() << ' ' << mesh.triangles.size() << " 0\n";
  for (const Vec3& p : mesh.vertices) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const Vec3i& t : mesh.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  return out.str();
}

void expectCube(const Part& part, std::size_t faces, bool equal_faces = true) {
  EXPECT_EQ(part.faces.size(), faces);
  EXPECT_EQ(part.mesh.triangles.size(), 12u);
  EXPECT_EQ(part.mesh.vertices.size(), 8u);  // coincident STL corners welded
  EXPECT_NEAR(part.area(), 6 * kSize * kSize, 1e-9);
  ASSERT_EQ(part.solids.size(), 1u);
  EXPECT_NEAR(part.volume(), kSize * kSize * kSize, 1e-9);
  EXPECT_NEAR(signedVolume(part.mesh), kSize * kSize * kSize, 1e-9);
  for (const Face& face : part.faces) {
    EXPECT_EQ(face.type, SurfaceType::Mesh);
    if (equal_faces) {
      EXPECT_NEAR(face.area, 6 * kSize * kSize / static_cast<double>(faces), 1e-9);
    }
    for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t)
      EXPECT_EQ(part.mesh.triangle_faces[t], face.id);
  }
}

TEST(MeshImport, AsciiStlSplitsAtSharpEdges) {
  test::TempDir dir;
  test::writeText(dir.file("cube.stl"), asciiStl(cube()));
  Part part = importPart(dir.file("cube.stl"));
  EXPECT_EQ(part.format, "STL");
  expectCube(part, 6);
  for (const Face& face : part.faces) EXPECT_EQ(face.triangle_count, 2);
}

TEST(MeshImport, BinaryStl) {
  test::TempDir dir;
  test::writeText(dir.file("cube.stl"), binaryStl(cube()));
  expectCube(importPart(dir.file("cube.stl")), 6);
}

TEST(MeshImport, SharpAngleAboveNinetyKeepsTheCubeWhole) {
  test::TempDir dir;
  test::writeText(dir.file("cube.stl"), binaryStl(cube()));
  ImportOptions options;
  options.sharp_angle = 91;
  expectCube(importPart(dir.file("cube.stl"), options), 1);
}

TEST(MeshImport, ObjGroupsBecomeFaces) {
  test::TempDir dir;
  test::writeText(dir.file("cube.obj"), groupedObj(cube()));
  Part part = importPart(dir.file("cube.obj"));
  expectCube(part, 6);
  EXPECT_EQ(part.faces[0].name, "side0");
  EXPECT_EQ(part.faces[5].name, "side5");
}

TEST(MeshImport, PlyAsciiAndBinaryWithGroups) {
  test::TempDir dir;
  test::writeText(dir.file("a.ply"), ply(cube(), false, false));
  test::writeText(dir.file("b.ply"), ply(cube(), true, false));
  test::writeText(dir.file("c.ply"), ply(cube(), true, true));
  expectCube(importPart(dir.file("a.ply")), 6);
  expectCube(importPart(dir.file("b.ply")), 6);
  // A face is a connected region of one group: the two apart sides of group 2 are two.
  Part grouped = importPart(dir.file("c.ply"));
  expectCube(grouped, 4, false);
  std::vector<double> areas;
  for (const Face& face : grouped.faces) areas.push_back(face.area);
  std::sort(areas.begin(), areas.end());
  const double side = kSize * kSize;
  EXPECT_EQ(areas, (std::vector<double>{side, side, 2 * side, 2 * side}));
}

TEST(MeshImport, Off) {
  test::TempDir dir;
  test::writeText(dir.file("cube.off"), off(cube()));
  expectCube(importPart(dir.file("cube.off")), 6);
}

// An OFF face announcing two billion vertices in a file of a few bytes is refused, naming
// the file and the face, before anything is allocated for it.
TEST(MeshImport, OffFaceAnnouncingMoreVerticesThanTheFileHoldsIsRefused) {
  test::TempDir dir;
  test::writeText(dir.file("huge.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n");
  try {
    importPart(dir.file("huge.off"));
    ADD_FAILURE() << "read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("huge.off"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("face 1 announces 2000000000 vertices"), std::string::npos)
        << e.what();
  }
}

TEST(MeshImport, InwardMeshIsTurnedOutward) {
  TriangleMesh inward = cube();
  for (Vec3i& t : inward.triangles) std::swap(t[1], t[2]);
  test::TempDir dir;
  test::writeText(dir.file("cube.off"), off(inward));
  Part part = importPart(dir.file("cube.off"));
  expectCube(part, 6);
  EXPECT_FALSE(part.warnings.empty());
}

TEST(MeshImport, MeshUnitScalesToMillimetres) {
  test::TempDir dir;
  test::writeText(dir.file("cube.off"), off(cube()));
  ImportOptions options;
  options.mesh_unit = 25.4;  // the file is in inches
  Part part = importPart(dir.file("cube.off"), options);
  EXPECT_NEAR(part.bounds().size().x(), kSize * 25.4, 1e-9);
}

TEST(MeshImport, FandiskFromSharedData) {
  SHARED_DATA_OR_SKIP(path, "mesh/libigl_fandisk.off");
  Part part = importPart(path);
  EXPECT_EQ(part.mesh.triangles.size(), 14454u);
  EXPECT_GT(part.faces.size(), 5u);  // a CAD-like part with several smooth patches
  ASSERT_EQ(part.solids.size(), 1u);
  EXPECT_GT(signedVolume(part.mesh), 0);
  std::size_t triangles = 0;
  for (const Face& face : part.faces) triangles += face.triangle_count;
  EXPECT_EQ(triangles, part.mesh.triangles.size());
}

TEST(MeshImport, BinaryStlFromSharedData) {
  SHARED_DATA_OR_SKIP(path, "mesh/asi_rocker_arm_mm_decimated.stl");
  Part part = importPart(path);
  EXPECT_EQ(part.mesh.triangles.size(), 10056u);
  EXPECT_GT(signedVolume(part.mesh), 0);
}

}  // namespace
}  // namespace scanplan
