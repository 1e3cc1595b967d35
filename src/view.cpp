#include <scanplan/view.h>

namespace scanplan {

Pose lookAt(const Vec3& camera, const Vec3& target, const Vec3& baseline_hint) {
  const Vec3 z = (target - camera).normalized();
  Vec3 x = baseline_hint - baseline_hint.dot(z) * z;
  if (x.norm() < 1e-9) x = z.unitOrthogonal();
  x.normalize();
  Pose pose = Pose::Identity();
  pose.linear() << x, z.cross(x), z;
  pose.translation() = camera;
  return pose;
}

bool isRigid(const Eigen::Matrix4d& m, double tolerance) {
  if (!m.allFinite()) return false;
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > tolerance) return false;
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  return (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= tolerance &&
         std::abs(r.determinant() - 1) <= tolerance;
}

}  // namespace scanplan
