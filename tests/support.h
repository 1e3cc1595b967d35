#pragma once
// Shared helpers of the test suite: where the test parts are, temporary folders.

#include <scanplan/cad/import.h>
#include <scanplan/cad/part.h>
#include <scanplan/core/errors.h>

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <string>

namespace scanplan::test {

inline std::string testData(const std::string& name) {
  return std::string(SCANPLAN_TEST_DATA) + "/" + name;
}
inline std::string example(const std::string& name) {
  return std::string(SCANPLAN_EXAMPLES) + "/" + name;
}

// A file of the bundled example's plan, planned once per test run (the PlanBundledExample
// test, or here when a test runs on its own): plan.json, summary.txt.
inline std::string examplePlan(const std::string& name = "plan.json") {
  const std::string folder = SCANPLAN_EXAMPLE_PLAN;
  if (!std::filesystem::exists(folder + "/plan.json")) {
    const std::string command = std::string(SCANPLAN_PLAN_EXAMPLE_SCRIPT) + " '" + SCANPLAN_EXE +
                                "' '" + SCANPLAN_EXAMPLES + "' '" + folder + "'";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
  }
  return folder + "/" + name;
}

// The part at `path` as importPart reads it, imported once per test process: the tests
// that only read a part (each parameter of the NIST suites runs in one process) share it.
inline const Part& importedOnce(const std::string& path) {
  static std::map<std::string, Part> parts;
  auto it = parts.find(path);
  if (it == parts.end()) it = parts.emplace(path, importPart(path)).first;
  return it->second;
}

// True when the shared data must be there (SCANPLAN_REQUIRE_SHARED_DATA set, as
// scripts/check.sh sets it in CI and wherever ../shared/data exists): a test that needs a
// missing file then fails.
inline bool sharedDataRequired() {
  const char* value = std::getenv("SCANPLAN_REQUIRE_SHARED_DATA");
  return value != nullptr && *value != '\0';
}

// The test needs the file `path` of ../shared/data: it fails when the file is missing and
// the shared data is required, and is skipped, saying so, otherwise.
#define SHARED_FILE_OR_SKIP(path)                                                                \
  if (!std::filesystem::exists(path)) {                                                          \
    if (test::sharedDataRequired())                                                              \
      FAIL() << "shared data not found: " << (path) << " (SCANPLAN_REQUIRE_SHARED_DATA is set)"; \
    GTEST_SKIP() << "shared data not found: " << (path)                                          \
                 << " (set SCANPLAN_REQUIRE_SHARED_DATA to make this a failure)";                \
  }

// A file of ../shared/data, as SHARED_FILE_OR_SKIP needs it.
#define SHARED_DATA_OR_SKIP(var, relative)                                \
  std::string var = std::string(SCANPLAN_SHARED_DATA) + "/" + (relative); \
  SHARED_FILE_OR_SKIP(var)

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

inline std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
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

// A Part made of `mesh` alone, one face per distinct triangle face id (ids 1..n, each
// face's triangles contiguous), as the importer would give it.
inline Part meshPart(const TriangleMesh& mesh) {
  Part part;
  part.file = "test mesh";
  part.format = "MESH";
  part.mesh = mesh;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int id = mesh.triangle_faces[t];
    if (static_cast<int>(part.faces.size()) < id) {
      part.faces.resize(id);
      part.faces[id - 1].id = id;
      part.faces[id - 1].type = SurfaceType::Mesh;
      part.faces[id - 1].first_triangle = static_cast<int>(t);
    }
    Face& face = part.faces[id - 1];
    ++face.triangle_count;
    face.area += mesh.area(t);
    for (int k = 0; k < 3; ++k) face.bounds.add(mesh.vertices[mesh.triangles[t][k]]);
  }
  return part;
}

// Adds the rectangle centred at `centre` spanned by the half-extents `u` and `v` (normal
// u x v) to `mesh` as face `face`.
inline void addRectangle(TriangleMesh& mesh, const Vec3& centre, const Vec3& u, const Vec3& v,
                         int face) {
  const int base = static_cast<int>(mesh.vertices.size());
  mesh.vertices.push_back(centre - u - v);
  mesh.vertices.push_back(centre + u - v);
  mesh.vertices.push_back(centre + u + v);
  mesh.vertices.push_back(centre - u + v);
  mesh.triangles.emplace_back(base, base + 1, base + 2);
  mesh.triangles.emplace_back(base, base + 2, base + 3);
  mesh.triangle_faces.insert(mesh.triangle_faces.end(), 2, face);
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The reason of the InputError `read` throws naming `path` (exit code 2, what() as
// "<path>: <reason>"); fails the test if nothing is thrown.
inline std::string inputError(const std::string& path, const std::function<void()>& read) {
  try {
    read();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.exitCode(), kExitInput);
    EXPECT_EQ(std::string(e.what()), path + ": " + e.reason());
    return e.reason();
  }
  ADD_FAILURE() << "no InputError for " << path;
  return {};
}

// Imports `path` and returns the error's reason.
inline std::string importError(const std::string& path, const ImportOptions& options = {}) {
  return inputError(path, [&] { importPart(path, options); });
}

// Seconds an axis takes over `distance` from rest to rest, at most `speed` and
// `acceleration`, by stepping time in steps of `dt`: full acceleration until its speed,
// on at it until it must brake to stop at the end, then braking until it stands. A
// reference for motion-profile formulas that shares none of their algebra.
inline double steppedMoveSeconds(double distance, double speed, double acceleration,
                                 double dt = 1e-5) {
  double x = 0, v = 0, t = 0;
  bool braking = false;
  while (!braking || v > 0) {  // until it stands still again
    braking = braking || distance - x <= v * v / (2 * acceleration);
    const double next =
        braking ? std::max(v - acceleration * dt, 0.0) : std::min(v + acceleration * dt, speed);
    x += 0.5 * (v + next) * dt;
    v = next;
    t += dt;
  }
  return t;
}

}  // namespace scanplan::test
