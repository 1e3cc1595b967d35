#pragma once
// Shared helpers of the test suite: where the test parts are, temporary folders.

#include <scanplan/cad/mesh.h>

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>

namespace scanplan::test {

inline std::string testData(const std::string& name) {
  return std::string(SCANPLAN_TEST_DATA) + "/" + name;
}
inline std::string example(const std::string& name) {
  return std::string(SCANPLAN_EXAMPLES) + "/" + name;
}

// A file of ../shared/data; the test is skipped when the shared data is not there.
#define SHARED_DATA_OR_SKIP(var, relative)                                \
  std::string var = std::string(SCANPLAN_SHARED_DATA) + "/" + (relative); \
  if (!std::filesystem::exists(var)) GTEST_SKIP() << "shared data not found: " << var

// A fresh folder under the system temp dir, removed with the object.
class TempDir {
 public:
  TempDir() {
    auto base = std::filesystem::temp_directory_path();
    for (int i = 0;; ++i) {
      path_ = base / ("scanplan_test_" + std::to_string(::getpid()) + "_" + std::to_string(i));
      if (std::filesystem::create_directory(path_)) break;
    }
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// Adds the axis-aligned cube [lo, lo + size]^3 to `mesh` as face `face`, two triangles a
// side, wound counter-clockwise seen from outside.
inline void addCube(TriangleMesh& mesh, const Vec3& lo, double size, int face) {
  const int base = static_cast<int>(mesh.vertices.size());
  for (int i = 0; i < 8; ++i)
    mesh.vertices.push_back(lo + size * Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(base + q[0], base + q[1], base + q[2]);
    mesh.triangles.emplace_back(base + q[0], base + q[2], base + q[3]);
    mesh.triangle_faces.insert(mesh.triangle_faces.end(), 2, face);
  }
}

}  // namespace scanplan::test
