#include <scanplan/solve/fits.h>

#include <ClpSimplex.hpp>
#include <CoinPackedMatrix.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <vector>

namespace scanplan {
namespace {

Vec3 centroidOf(std::span<const Vec3> points) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : points) c += p;
  return c / static_cast<double>(std::max<std::size_t>(1, points.size()));
}

// Two unit vectors completing `n` (unit) to a right-handed frame.
std::pair<Vec3, Vec3> across(const Vec3& n) {
  const Vec3 e1 = n.unitOrthogonal();
  return {e1, n.cross(e1)};
}

}  // namespace

PlaneFit fitPlane(std::span<const Vec3> points, const Vec3& towards) {
  PlaneFit fit;
  fit.point = centroidOf(points);
  if (points.size() < 3) return fit;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) scatter += (p - fit.point) * (p - fit.point).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  const Vec3 values = eigen.eigenvalues();  // ascending
  fit.normal = eigen.eigenvectors().col(0);
  if (fit.normal.dot(towards) < 0) fit.normal = -fit.normal;
  fit.rms = std::sqrt(std::max(0.0, values[0]) / static_cast<double>(points.size()));
  fit.determined = values[1] > 1e-12 * std::max(values[2], 1e-300);
  return fit;
}

double minimumZoneFlatness(std::span<const Vec3> points, const Vec3& normal) {
  if (points.size() < 3) return 0;
  const Vec3 n = normal.normalized();
  const auto [e1, e2] = across(n);
  const Vec3 centre = centroidOf(points);
  // Columns a, b, d, t: the plane w = a u + b v + d, the zone's height t along n.
  // Rows 2i and 2i+1: w_i - (a u_i + b v_i + d) within [-t/2, t/2].
  const auto rows = static_cast<int>(2 * points.size());
  std::vector<int> row_index, column_start{0};
  std::vector<double> element, row_lower(rows), row_upper(rows);
  std::vector<std::vector<double>> column(4, std::vector<double>(rows));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 d = points[i] - centre;
    const double u = d.dot(e1), v = d.dot(e2), w = d.dot(n);
    for (int side = 0; side < 2; ++side) {
      const std::size_t r = 2 * i + side;
      column[0][r] = -u;
      column[1][r] = -v;
      column[2][r] = -1;
      column[3][r] = side == 0 ? -0.5 : 0.5;
      row_lower[r] = side == 0 ? -COIN_DBL_MAX : -w;
      row_upper[r] = side == 0 ? -w : COIN_DBL_MAX;
    }
  }
  for (const std::vector<double>& values : column) {
    for (int r = 0; r < rows; ++r) {
      row_index.push_back(r);
      element.push_back(values[r]);
    }
    column_start.push_back(static_cast<int>(row_index.size()));
  }
  const std::vector<int> lengths(4, rows);
  const CoinPackedMatrix matrix(true, rows, 4, static_cast<CoinBigIndex>(element.size()),
                                element.data(), row_index.data(), column_start.data(),
                                lengths.data());
  const double column_lower[] = {-COIN_DBL_MAX, -COIN_DBL_MAX, -COIN_DBL_MAX, 0};
  const double column_upper[] = {COIN_DBL_MAX, COIN_DBL_MAX, COIN_DBL_MAX, COIN_DBL_MAX};
  const double objective[] = {0, 0, 0, 1};
  ClpSimplex lp;
  lp.setLogLevel(0);
  lp.loadProblem(matrix, column_lower, column_upper, objective, row_lower.data(), row_upper.data());
  lp.dual();
  const double* x = lp.primalColumnSolution();
  // The zone measured along n, across the plane's own normal (a, b, -1) instead.
  return x[3] / std::sqrt(1 + x[0] * x[0] + x[1] * x[1]);
}

double axisDistance(const CylinderFit& cylinder, const Vec3& p) {
  const Vec3 d = p - cylinder.point;
  return (d - d.dot(cylinder.axis) * cylinder.axis).norm();
}

CylinderFit fitCylinder(std::span<const Vec3> points, const CylinderFit& start) {
  CylinderFit fit = start;
  fit.axis.normalize();
  fit.determined = false;
  if (points.size() < 5) return fit;
  const Vec3 centre = centroidOf(points);
  using Vec5 = Eigen::Matrix<double, 5, 1>;
  using Mat5 = Eigen::Matrix<double, 5, 5>;
  constexpr int kIterations = 50;
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    const auto [e1, e2] = across(fit.axis);
    Mat5 normal = Mat5::Zero();
    Vec5 gradient = Vec5::Zero();
    for (const Vec3& p : points) {
      const Vec3 d = p - fit.point;
      const double s = d.dot(fit.axis);
      const Vec3 w = d - s * fit.axis;
      const double rho = std::max(w.norm(), 1e-12);
      const Vec3 u = w / rho;
      Vec5 row;
      row << -u.dot(e1), -u.dot(e2), -s * u.dot(e1), -s * u.dot(e2), -1;
      normal += row * row.transpose();
      gradient += row * (rho - fit.radius);
    }
    const Eigen::SelfAdjointEigenSolver<Mat5> eigen(normal);
    if (!(eigen.eigenvalues()[0] > 1e-12 * eigen.eigenvalues()[4])) return fit;
    const Vec5 step = -normal.ldlt().solve(gradient);
    fit.point += step[0] * e1 + step[1] * e2;
    fit.axis = (fit.axis + step[2] * e1 + step[3] * e2).normalized();
    fit.radius += step[4];
    fit.point += (centre - fit.point).dot(fit.axis) * fit.axis;
    if (step.norm() < 1e-12 * (1 + std::abs(fit.radius))) {
      fit.determined = true;
      break;
    }
  }
  double squares = 0;
  for (const Vec3& p : points) squares += std::pow(axisDistance(fit, p) - fit.radius, 2);
  fit.rms = std::sqrt(squares / static_cast<double>(points.size()));
  fit.radius = std::abs(fit.radius);
  return fit;
}

CylinderFit cylinderFromNormals(std::span<const Vec3> points, std::span<const Vec3> normals) {
  CylinderFit fit;
  if (points.size() < 5 || normals.size() != points.size()) return fit;
  Eigen::Matrix3d turning = Eigen::Matrix3d::Zero();
  for (const Vec3& n : normals) turning += n * n.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(turning);
  const Vec3 values = eigen.eigenvalues();
  fit.axis = eigen.eigenvectors().col(0);
  // Normals across the axis, turning through an arc: a plane's do not turn.
  if (!(values[0] < 1e-6 * values[2] && values[1] > 1e-4 * values[2])) return fit;
  const auto [e1, e2] = across(fit.axis);
  // q_i - rho m_i = c: the point, less the signed radius along the normal, on the axis.
  Eigen::MatrixXd a(2 * points.size(), 3);
  Eigen::VectorXd b(2 * points.size());
  double along = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 &p = points[i], &n = normals[i];
    a.row(2 * i) << 1, 0, n.dot(e1);
    a.row(2 * i + 1) << 0, 1, n.dot(e2);
    b[2 * i] = p.dot(e1);
    b[2 * i + 1] = p.dot(e2);
    along += p.dot(fit.axis) / static_cast<double>(points.size());
  }
  const Eigen::Vector3d x = a.colPivHouseholderQr().solve(b);
  fit.point = x[0] * e1 + x[1] * e2 + along * fit.axis;
  fit.radius = std::abs(x[2]);
  fit.determined = fit.radius > 0;
  return fit;
}

}  // namespace scanplan
