// Coverage as area (docs/planning.md, "Coverage by area").

#include <scanplan/planning/coverage_area.h>
#include <scanplan/planning/evidence.h>

#include <algorithm>
#include <cmath>

namespace scanplan {

namespace {

// How many parts each side of triangle t is cut into at `spacing`.
int cutsOf(const TriangleMesh& mesh, std::size_t t, double spacing) {
  const Vec3& a = mesh.vertices[mesh.triangles[t][0]];
  const Vec3& b = mesh.vertices[mesh.triangles[t][1]];
  const Vec3& c = mesh.vertices[mesh.triangles[t][2]];
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  return std::max(1, static_cast<int>(std::ceil(longest / spacing)));
}

// The number of area points at `spacing`.
std::size_t countAt(const TriangleMesh& mesh, double spacing) {
  std::size_t count = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto n = static_cast<std::size_t>(cutsOf(mesh, t, spacing));
    count += n * n;
  }
  return count;
}

}  // namespace

AreaPoints areaPoints(const TriangleMesh& mesh, double spacing) {
  AreaPoints result;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3& a = mesh.vertices[mesh.triangles[t][0]];
    const Vec3 u = mesh.vertices[mesh.triangles[t][1]] - a;
    const Vec3 v = mesh.vertices[mesh.triangles[t][2]] - a;
    const int n = cutsOf(mesh, t, spacing);
    const double share = mesh.area(t) / (n * n);
    const Vec3 normal = mesh.normal(t);
    auto add = [&](double i, double j) {
      result.points.push_back({a + (i / n) * u + (j / n) * v, normal, mesh.triangle_faces[t]});
      result.area.push_back(share);
    };
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        add(i + 1.0 / 3, j + 1.0 / 3);                     // the sub-triangle pointing up
        if (i + j < n - 1) add(i + 2.0 / 3, j + 2.0 / 3);  // and the one pointing down
      }
  }
  return result;
}

std::vector<FaceArea> measuredArea(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                                   std::size_t points) {
  std::vector<FaceArea> faces(part.faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) faces[f].face = static_cast<int>(f + 1);
  double total = 0;
  for (std::size_t t = 0; t < part.mesh.triangles.size(); ++t) total += part.mesh.area(t);
  if (total <= 0 || points == 0) return faces;
  // The spacing that gives about `points` points; once more if slivers made many more.
  double spacing = std::sqrt(2 * total / static_cast<double>(points));
  if (const std::size_t count = countAt(part.mesh, spacing); count > 2 * points)
    spacing *= std::sqrt(static_cast<double>(count) / static_cast<double>(points));
  const AreaPoints area = areaPoints(part.mesh, spacing);
  std::vector<char> measured(area.points.size(), 0);
  for (const std::vector<int>& by_view : measuredByViews(plan, part, spec, area.points))
    for (int i : by_view) measured[i] = 1;
  for (std::size_t i = 0; i < area.points.size(); ++i) {
    const int face = area.points[i].face;
    if (face < 1 || face > static_cast<int>(faces.size())) continue;
    faces[face - 1].area += area.area[i];
    if (measured[i]) faces[face - 1].measured += area.area[i];
  }
  return faces;
}

}  // namespace scanplan
