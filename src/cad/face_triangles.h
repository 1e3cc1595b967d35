#pragma once
// One face's triangles of the part's mesh, indexed for the point of them nearest a query
// point (private to the library).

#include "core/kd_tree.h"

#include <scanplan/cad/part.h>

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace scanplan::detail {

class FaceTriangles {
 public:
  // The triangles of face `face` of `part`. \throw InputError for an unknown face id.
  FaceTriangles(const Part& part, int face);
  ~FaceTriangles();
  // Its index refers to its own centres: built where it stays.
  FaceTriangles(const FaceTriangles&) = delete;
  FaceTriangles& operator=(const FaceTriangles&) = delete;

  bool empty() const { return corners_.empty(); }
  // The point of the triangles nearest `p`, with its triangle's outward normal; none for a
  // face without triangles.
  struct Nearest {
    Vec3 position = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ();
  };
  std::optional<Nearest> nearest(const Vec3& p) const;
  // Whether `p` lies within `distance` of the triangles (false without any).
  bool within(const Vec3& p, double distance) const;

 private:
  // The triangles that may have a point within `distance` of `p`: those whose centre lies
  // within that and the reach.
  Neighbours near(const Vec3& p, double distance) const;
  Vec3 onTriangle(unsigned t, const Vec3& p) const;

  std::vector<std::array<Vec3, 3>> corners_;
  std::vector<Vec3> normals_, centres_;
  double reach_ = 0;  // the farthest any vertex lies from its triangle's centre
  std::unique_ptr<PointCloudAdaptor> cloud_;
  std::unique_ptr<PointTree> tree_;
};

}  // namespace scanplan::detail
