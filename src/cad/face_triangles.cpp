// One face's triangles, indexed by their centres.

#include "cad/face_triangles.h"

#include <scanplan/cad/mesh.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace scanplan::detail {

FaceTriangles::FaceTriangles(const Part& part, int id) {
  const Face& face = part.face(id);
  for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
    const Vec3i& tri = part.mesh.triangles[static_cast<std::size_t>(t)];
    const std::array<Vec3, 3> corners{part.mesh.vertices[tri[0]], part.mesh.vertices[tri[1]],
                                      part.mesh.vertices[tri[2]]};
    const Vec3 centre = (corners[0] + corners[1] + corners[2]) / 3;
    for (const Vec3& c : corners) reach_ = std::max(reach_, (c - centre).norm());
    corners_.push_back(corners);
    normals_.push_back(part.mesh.normal(t));
    centres_.push_back(centre);
  }
  if (empty()) return;
  cloud_ = std::make_unique<PointCloudAdaptor>(PointCloudAdaptor{centres_});
  tree_ = std::make_unique<PointTree>(3, *cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree_->buildIndex();
}

FaceTriangles::~FaceTriangles() = default;

Neighbours FaceTriangles::near(const Vec3& p, double distance) const {
  const double within = distance + reach_ + 1e-9;
  Neighbours found;
  nanoflann::SearchParams unsorted;
  unsorted.sorted = false;
  tree_->radiusSearch(p.data(), within * within, found, unsorted);
  return found;
}

Vec3 FaceTriangles::onTriangle(unsigned t, const Vec3& p) const {
  const auto& c = corners_[t];
  return closestPointOnTriangle(p, c[0], c[1], c[2]);
}

std::optional<FaceTriangles::Nearest> FaceTriangles::nearest(const Vec3& p) const {
  if (empty()) return std::nullopt;
  // The nearest point of the triangle whose centre is nearest lies within that centre's
  // distance; the nearest of all, on a triangle whose centre lies within that and the
  // reach.
  unsigned index = 0;
  double squared = 0;
  tree_->knnSearch(p.data(), 1, &index, &squared);
  double best = std::numeric_limits<double>::infinity();
  Nearest result{p, normals_[index]};
  for (const auto& [t, d2] : near(p, std::sqrt(squared))) {
    const Vec3 q = onTriangle(t, p);
    const double d = (p - q).norm();
    if (d >= best) continue;
    best = d;
    result = {q, normals_[t]};
  }
  return result;
}

bool FaceTriangles::within(const Vec3& p, double distance) const {
  if (empty()) return false;
  const Neighbours found = near(p, distance);
  return std::any_of(found.begin(), found.end(), [&](const auto& candidate) {
    return (p - onTriangle(candidate.first, p)).norm() <= distance;
  });
}

}  // namespace scanplan::detail
