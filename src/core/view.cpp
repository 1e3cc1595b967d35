#include <scanplan/core/view.h>

namespace scanplan {

bool isRigid(const Eigen::Matrix4d& m, double tolerance) {
  if (!m.allFinite()) return false;
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > tolerance) return false;
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  return (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= tolerance &&
         std::abs(r.determinant() - 1) <= tolerance;
}

}  // namespace scanplan
