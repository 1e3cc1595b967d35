#include <scanplan/cad/mesh.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace scanplan {

Vec3 TriangleMesh::normal(std::size_t t) const {
  const Vec3i& tri = triangles[t];
  Vec3 n = (vertices[tri[1]] - vertices[tri[0]]).cross(vertices[tri[2]] - vertices[tri[0]]);
  double len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

double TriangleMesh::area(std::size_t t) const {
  const Vec3i& tri = triangles[t];
  return 0.5 *
         (vertices[tri[1]] - vertices[tri[0]]).cross(vertices[tri[2]] - vertices[tri[0]]).norm();
}

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

static double tetraVolume(const TriangleMesh& mesh, std::size_t t) {
  const Vec3i& tri = mesh.triangles[t];
  return mesh.vertices[tri[0]].dot(mesh.vertices[tri[1]].cross(mesh.vertices[tri[2]])) / 6.0;
}

void TriangleMesh::append(const TriangleMesh& other, int face) {
  const int base = static_cast<int>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const Vec3i& t : other.triangles) triangles.push_back(t + Vec3i::Constant(base));
  triangle_faces.insert(triangle_faces.end(), other.triangles.size(), face);
}

double signedVolume(const TriangleMesh& mesh) {
  double volume = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) volume += tetraVolume(mesh, t);
  return volume;
}

double signedVolume(const TriangleMesh& mesh, const std::vector<int>& triangles) {
  double volume = 0;
  for (int t : triangles) volume += tetraVolume(mesh, t);
  return volume;
}

std::vector<int> weldVertices(const std::vector<Vec3>& vertices, double tolerance) {
  std::vector<int> representative(vertices.size());
  std::iota(representative.begin(), representative.end(), 0);
  if (tolerance <= 0) {
    // Exact positions only.
    std::unordered_map<std::size_t, std::vector<int>> buckets;
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      const Vec3& p = vertices[i];
      std::size_t h = std::hash<double>()(p.x()) ^ (std::hash<double>()(p.y()) * 31) ^
                      (std::hash<double>()(p.z()) * 961);
      auto& bucket = buckets[h];
      auto same =
          std::find_if(bucket.begin(), bucket.end(), [&](int j) { return vertices[j] == p; });
      if (same != bucket.end())
        representative[i] = *same;
      else
        bucket.push_back(static_cast<int>(i));
    }
    return representative;
  }
  // Uniform grid of cell size `tolerance`: a vertex's equals lie in the 27 cells around it.
  auto cellOf = [&](const Vec3& p) {
    return Eigen::Vector3<long long>((p / tolerance).array().floor().cast<long long>());
  };
  auto key = [](const Eigen::Vector3<long long>& c) {
    return static_cast<std::size_t>(c.x() * 73856093LL ^ c.y() * 19349663LL ^ c.z() * 83492791LL);
  };
  std::unordered_multimap<std::size_t, int> grid;
  grid.reserve(vertices.size());
  const double tol2 = tolerance * tolerance;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Vec3& p = vertices[i];
    auto cell = cellOf(p);
    int found = -1;
    for (int dx = -1; dx <= 1 && found < 0; ++dx)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dz = -1; dz <= 1 && found < 0; ++dz) {
          auto range = grid.equal_range(key(cell + Eigen::Vector3<long long>(dx, dy, dz)));
          for (auto it = range.first; it != range.second; ++it)
            if ((vertices[it->second] - p).squaredNorm() <= tol2) {
              found = it->second;
              break;
            }
        }
    if (found >= 0) {
      representative[i] = found;
    } else {
      grid.emplace(key(cell), static_cast<int>(i));
    }
  }
  return representative;
}

EdgeReport edgeReport(const TriangleMesh& mesh, double weld_tolerance) {
  std::vector<int> rep = weldVertices(mesh.vertices, weld_tolerance);
  // Per undirected edge: uses in each direction.
  struct Uses {
    int forward = 0, backward = 0;
  };
  std::unordered_map<std::uint64_t, Uses> edges;
  edges.reserve(mesh.triangles.size() * 2);
  for (const Vec3i& tri : mesh.triangles) {
    // A triangle with two coincident corners (at a cone apex or a seam) bounds nothing.
    if (rep[tri[0]] == rep[tri[1]] || rep[tri[1]] == rep[tri[2]] || rep[tri[2]] == rep[tri[0]])
      continue;
    for (int k = 0; k < 3; ++k) {
      int a = rep[tri[k]], b = rep[tri[(k + 1) % 3]];
      auto lo = static_cast<std::uint64_t>(std::min(a, b));
      auto hi = static_cast<std::uint64_t>(std::max(a, b));
      Uses& uses = edges[(lo << 32) | hi];
      (a < b ? uses.forward : uses.backward)++;
    }
  }
  EdgeReport report;
  report.edges = edges.size();
  for (const auto& [key, uses] : edges) {
    int total = uses.forward + uses.backward;
    if (total == 1)
      ++report.boundary;
    else if (total > 2)
      ++report.non_manifold;
    else if (uses.forward != 1)
      ++report.misoriented;
  }
  return report;
}

}  // namespace scanplan
