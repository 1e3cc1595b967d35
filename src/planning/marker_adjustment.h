#pragma once
// Views registered by shared markers, adjusted together (docs/capability.md, "Error
// budget"): as a cell registers scans by their markers, every view's pose and every
// marker's position are fitted at once to all the markers' centres the views measured,
// not view by view along a chain. A view seeing markers that several others see is held
// by all of them.

#include "planning/registration_error.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace scanplan::detail {

// Views joined by marker links to one root: the first view up their chain that is not
// registered by markers to a view of its own setup (the reference, a view registered
// otherwise, or across setups), whose pose the group's fit holds fixed.
struct MarkerGroup {
  std::size_t root = 0;
  std::vector<std::size_t> members;  // in the plan's order
};

// The groups of `plan`'s views registered by markers: `parents`, per view, the view its
// link runs to; `placed`, whether its link is known at all.
std::vector<MarkerGroup> markerGroups(const Plan& plan,
                                      const std::vector<std::optional<std::size_t>>& parents,
                                      const std::vector<char>& placed);

// The covariance of the members' motions relative to the root's (6 rows per member, in
// their order), every view of the group measuring the centre of each marker it sees with
// `sigma` mm per axis, and the members' poses and the markers' positions fitted together
// by least squares (first order); a marker seen by one view alone holds nothing.
Eigen::MatrixXd adjustedCovariance(const Plan& plan, const MarkerGroup& group, double sigma);

}  // namespace scanplan::detail
