#pragma once
// A nanoflann k-d tree over sample positions (private to the library).

#include <scanplan/sampling.h>

#include <nanoflann.hpp>

#include <vector>

namespace scanplan::detail {

// nanoflann's dataset adaptor over Sample::position.
struct SampleCloud {
  const std::vector<Sample>& samples;
  std::size_t kdtree_get_point_count() const { return samples.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return samples[i].position[static_cast<int>(dim)];
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using SampleTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, SampleCloud>,
                                        SampleCloud, 3>;

// Indices and squared distances of a radius search.
using Neighbours = std::vector<std::pair<unsigned, double>>;

}  // namespace scanplan::detail
