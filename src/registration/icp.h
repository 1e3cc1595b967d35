#pragma once
// A view's ICP cloud with a k-d tree over its points, made once and used by every pair the
// view is in as the fixed cloud (private to the library; checkIcp in registration.h).

#include "core/kd_tree.h"

#include <scanplan/registration/registration.h>

#include <cstddef>
#include <random>

namespace scanplan::detail {

// Correspondences are weighted by Tukey's biweight, zero past this share of the distance
// they are sought within. The simulated clouds are far sparser than the scanner's: a point
// next to an edge is often matched to the face across it, and those pairs, left at full
// weight, bias the result by more than the tolerance.
constexpr double kTukey = 0.2;
// A cloud with fewer points than this is not registered.
constexpr std::size_t kIcpLeastPoints = 100;
// The stages before the last, which only bring the moved cloud near, run on every this
// many-th point of it.
constexpr std::size_t kIcpCoarseStride = 4;

// Where the robot puts a view before ICP: a rigid motion of `distance` mm in a random
// direction and `angle` degrees about a random axis through `centre`, drawn from `random`.
Pose perturbation(const Vec3& centre, double distance, double angle, std::mt19937_64& random);

struct IndexedCloud {
  explicit IndexedCloud(IcpCloud made);
  IndexedCloud(const IndexedCloud&) = delete;  // the tree refers to `cloud`
  IndexedCloud& operator=(const IndexedCloud&) = delete;

  IcpCloud cloud;
  PointCloudAdaptor adaptor{cloud.points};
  PointTree tree;
};

// checkIcp with `fixed` indexed beforehand.
IcpCheck checkIcp(const Simulator& simulator, const IndexedCloud& fixed, const IcpCloud& moved,
                  const RegistrationOptions& options);

}  // namespace scanplan::detail
