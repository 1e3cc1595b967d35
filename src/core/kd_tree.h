#pragma once
// nanoflann k-d trees over point positions, or the positions of items that have one
// (private to the library).

#include <scanplan/core/geometry.h>

#include <nanoflann.hpp>

#include <vector>

namespace scanplan::detail {

inline const Vec3& positionOf(const Vec3& point) { return point; }
template <class Item>
const Vec3& positionOf(const Item& item) {
  return item.position;
}

// nanoflann's dataset adaptor over the positions of `items`.
template <class Item>
struct PositionCloud {
  const std::vector<Item>& items;
  std::size_t kdtree_get_point_count() const { return items.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return positionOf(items[i])[static_cast<int>(dim)];
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

template <class Item>
using PositionTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PositionCloud<Item>>,
                                        PositionCloud<Item>, 3>;

using PointCloudAdaptor = PositionCloud<Vec3>;
using PointTree = PositionTree<Vec3>;

// Indices and squared distances of a radius search.
using Neighbours = std::vector<std::pair<unsigned, double>>;

}  // namespace scanplan::detail
