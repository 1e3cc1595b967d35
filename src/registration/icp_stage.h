#pragma once
// One stage of the ICP check (checkIcp, registration/icp.h), apart so that it can be held
// against Open3D's own RegistrationICP (private to the library).

#include "registration/icp.h"

#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/Registration.h>

namespace scanplan::detail {

// Open3D's RegistrationICP of `source` onto `target` (`fixed`'s points with their normals)
// within `distance`, point to plane with Tukey's weights (kTukey), at most 30 iterations,
// stopping when fitness and RMSE change by less than 1e-4 (0.1 µm of RMSE); but against
// fixed's tree made once, each point's nearest fixed point sought from the one it had.
// `source` is moved along, and the motion is added to `transformation`.
open3d::pipelines::registration::RegistrationResult icpStage(
    const IndexedCloud& fixed, const open3d::geometry::PointCloud& target,
    open3d::geometry::PointCloud& source, double distance, Eigen::Matrix4d& transformation);

}  // namespace scanplan::detail
