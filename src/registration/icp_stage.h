#pragma once
// One stage of the ICP check (checkIcp, registration/icp.h), apart so that it can be held
// against Open3D's own RegistrationICP (private to the library).

#include "registration/icp.h"

#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/Registration.h>

#include <vector>

namespace scanplan::detail {

// What a source point's last search found: its nearest fixed point within the distance
// searched, if any, and the least distance from where the point was then to every other
// fixed point; and how far the point has moved since.
struct Found {
  int nearest = -1;
  double others = 0;  // mm
  double moved = 0;   // mm
};

// Open3D's RegistrationICP of `source` onto `target` (`fixed`'s points with their normals)
// within `distance`, point to plane with Tukey's weights (kTukey), at most 30 iterations,
// stopping when fitness and RMSE change by less than 1e-4 (0.1 µm of RMSE); but against
// fixed's tree made once, each point's nearest fixed point sought from what it had
// `found` (per source point, kept up to date; default-made for none). `source` is moved
// along, and the motion is added to `transformation`.
open3d::pipelines::registration::RegistrationResult icpStage(
    const IndexedCloud& fixed, const open3d::geometry::PointCloud& target,
    open3d::geometry::PointCloud& source, double distance, Eigen::Matrix4d& transformation,
    std::vector<Found>& found);

}  // namespace scanplan::detail
