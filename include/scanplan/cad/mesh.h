#pragma once
// The part's triangle mesh: the geometry that ray casting, simulation and export work on.

#include <scanplan/core/geometry.h>

#include <vector>

namespace scanplan {

// An indexed triangle mesh in millimetres. Triangles wind counter-clockwise seen from
// outside the material, so (v1 - v0) x (v2 - v0) is the outward normal. Each triangle
// carries the 1-based id of the part face it belongs to; the triangles of one face are
// contiguous.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<Vec3i> triangles;     // vertex indices
  std::vector<int> triangle_faces;  // face id per triangle, 1-based

  bool empty() const { return triangles.empty(); }
  // Adds `other`'s vertices and triangles, each triangle as face `face`.
  void append(const TriangleMesh& other, int face);
  Vec3 normal(std::size_t t) const;  // unit outward normal; zero for a degenerate triangle
  double area(std::size_t t) const;  // mm²
};

// Signed volume enclosed by the triangles (mm³): positive when a closed mesh winds
// outward. Only meaningful for closed meshes.
double signedVolume(const TriangleMesh& mesh);
double signedVolume(const TriangleMesh& mesh, const std::vector<int>& triangles);

// Edge counts after welding vertices closer than `weld_tolerance` (mm): an edge used by
// one triangle is a boundary edge, by more than two a non-manifold one. A closed,
// consistently wound mesh has neither, and no edge used twice in the same direction.
// Triangles with two coincident corners after welding are left out.
struct EdgeReport {
  std::size_t edges = 0;
  std::size_t boundary = 0;
  std::size_t non_manifold = 0;
  std::size_t misoriented = 0;  // manifold edges traversed twice in the same direction
};
EdgeReport edgeReport(const TriangleMesh& mesh, double weld_tolerance);

// The point of triangle (a, b, c) closest to p (Ericson, Real-Time Collision Detection,
// 5.1.5).
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Vertex index map that merges vertices closer than `tolerance` (mm): result[i] is the
// representative of vertex i, the lowest index of its group.
std::vector<int> weldVertices(const std::vector<Vec3>& vertices, double tolerance);

}  // namespace scanplan
