#include <scanplan/solve/fits.h>

#include <ClpSimplex.hpp>
#include <CoinPackedMatrix.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
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

namespace {

// The narrowest zone w = a u + b v + d +- t/2 holding the points `rows` of (u, v, w): the
// linear programme's columns a, b, d, t; rows 2i and 2i+1 the zone's two sides.
Eigen::Vector4d zoneOf(const std::vector<Vec3>& uvw, const std::vector<std::size_t>& rows) {
  const auto count = static_cast<int>(2 * rows.size());
  std::vector<int> row_index, column_start{0};
  std::vector<double> element, row_lower(count), row_upper(count);
  std::vector<std::vector<double>> column(4, std::vector<double>(count));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Vec3& p = uvw[rows[k]];
    for (int side = 0; side < 2; ++side) {
      const std::size_t r = 2 * k + side;
      column[0][r] = -p.x();
      column[1][r] = -p.y();
      column[2][r] = -1;
      column[3][r] = side == 0 ? -0.5 : 0.5;
      row_lower[r] = side == 0 ? -COIN_DBL_MAX : -p.z();
      row_upper[r] = side == 0 ? -p.z() : COIN_DBL_MAX;
    }
  }
  for (const std::vector<double>& values : column) {
    for (int r = 0; r < count; ++r) {
      row_index.push_back(r);
      element.push_back(values[r]);
    }
    column_start.push_back(static_cast<int>(row_index.size()));
  }
  const std::vector<int> lengths(4, count);
  const CoinPackedMatrix matrix(true, count, 4, static_cast<CoinBigIndex>(element.size()),
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
  return {x[0], x[1], x[2], x[3]};
}

}  // namespace

double minimumZoneFlatness(std::span<const Vec3> points, const Vec3& normal) {
  if (points.size() < 3) return 0;
  const Vec3 n = normal.normalized();
  const auto [e1, e2] = across(n);
  const Vec3 centre = centroidOf(points);
  std::vector<Vec3> uvw;
  for (const Vec3& p : points) {
    const Vec3 d = p - centre;
    uvw.push_back({d.dot(e1), d.dot(e2), d.dot(n)});
  }
  // The zone of a few points first, those farthest from the points' mean height on either
  // side; then of those and the points left outside it, until none is: the same zone as of
  // all the points, from much smaller programmes.
  constexpr std::size_t kBatch = 400;
  std::vector<std::size_t> order(uvw.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return uvw[a].z() < uvw[b].z(); });
  std::vector<char> taken(uvw.size(), 0);
  std::vector<std::size_t> rows;
  for (std::size_t k = 0; k < std::min(kBatch, order.size()); ++k)
    for (const std::size_t i : {order[k], order[order.size() - 1 - k]})
      if (!taken[i]) taken[i] = 1, rows.push_back(i);
  while (true) {
    const Eigen::Vector4d zone = zoneOf(uvw, rows);
    std::vector<std::pair<double, std::size_t>> outside;  // (how far, point)
    for (std::size_t i = 0; i < uvw.size(); ++i) {
      const double off =
          std::abs(uvw[i].z() - zone[0] * uvw[i].x() - zone[1] * uvw[i].y() - zone[2]) -
          zone[3] / 2;
      if (!taken[i] && off > 1e-12 * (1 + zone[3])) outside.push_back({off, i});
    }
    if (outside.empty())  // the zone measured along n, across the planes' own normal instead
      return zone[3] / std::sqrt(1 + zone[0] * zone[0] + zone[1] * zone[1]);
    std::sort(outside.rbegin(), outside.rend());
    for (std::size_t k = 0; k < std::min(kBatch, outside.size()); ++k) {
      taken[outside[k].second] = 1;
      rows.push_back(outside[k].second);
    }
  }
}

double arcAbout(const CylinderFit& cylinder, std::span<const Vec3> points) {
  constexpr int kBins = 36;
  const auto [e1, e2] = across(cylinder.axis);
  std::vector<char> bins(kBins, 0);
  for (const Vec3& p : points) {
    const Vec3 d = p - cylinder.point;
    const double turn =
        (std::atan2(d.dot(e2), d.dot(e1)) + std::numbers::pi) / (2 * std::numbers::pi);
    bins[std::clamp(static_cast<int>(turn * kBins), 0, kBins - 1)] = 1;
  }
  return 360.0 / kBins * static_cast<double>(std::count(bins.begin(), bins.end(), 1));
}

double axisDistance(const CylinderFit& cylinder, const Vec3& p) {
  const Vec3 d = p - cylinder.point;
  return (d - d.dot(cylinder.axis) * cylinder.axis).norm();
}

CylinderFit fitCylinder(std::span<const Vec3> points, const CylinderFit& start, bool hold_axis) {
  CylinderFit fit = start;
  fit.axis.normalize();
  fit.determined = false;
  if (points.size() < 5) return fit;
  const Vec3 centre = centroidOf(points);
  using Vec5 = Eigen::Matrix<double, 5, 1>;
  using Mat5 = Eigen::Matrix<double, 5, 5>;
  constexpr int kIterations = 50;
  double last = std::numeric_limits<double>::infinity();  // the last step's size
  for (int iteration = 0; iteration < kIterations && last > 1e-12 * (1 + std::abs(fit.radius));
       ++iteration) {
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
    if (hold_axis) {  // the shift across the axis and the radius alone: a circle's fit
      for (int k : {2, 3}) {
        normal.row(k).setZero();
        normal.col(k).setZero();
        normal(k, k) = normal.trace();
        gradient[k] = 0;
      }
    }
    const Eigen::SelfAdjointEigenSolver<Mat5> eigen(normal);
    if (!(eigen.eigenvalues()[0] > 1e-12 * eigen.eigenvalues()[4])) return fit;
    const Vec5 step = -normal.ldlt().solve(gradient);
    fit.point += step[0] * e1 + step[1] * e2;
    fit.axis = (fit.axis + step[2] * e1 + step[3] * e2).normalized();
    fit.radius += step[4];
    fit.point += (centre - fit.point).dot(fit.axis) * fit.axis;
    last = step.norm();
  }
  // Converged: its steps have shrunk to nothing against the radius.
  fit.determined = last < 1e-9 * (1 + std::abs(fit.radius));
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

double minimumZoneStraightness(std::span<const Vec3> points, const Vec3& along,
                               const Vec3& across) {
  if (points.size() < 3) return 0;
  std::vector<Eigen::Vector2d> uw;
  for (const Vec3& p : points) uw.push_back({p.dot(along), p.dot(across)});
  // The zone's height across lines of slope a is convex in a: a golden-section search over
  // slopes up to 45° either way, then the height measured square to the lines.
  const auto width = [&](double a) {
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (const Eigen::Vector2d& q : uw) {
      low = std::min(low, q.y() - a * q.x());
      high = std::max(high, q.y() - a * q.x());
    }
    return high - low;
  };
  double lo = -1, hi = 1;
  const double golden = (std::sqrt(5.0) - 1) / 2;
  for (int k = 0; k < 200 && hi - lo > 1e-12; ++k) {
    const double a = hi - golden * (hi - lo), b = lo + golden * (hi - lo);
    if (width(a) < width(b))
      hi = b;
    else
      lo = a;
  }
  const double slope = (lo + hi) / 2;
  return width(slope) / std::sqrt(1 + slope * slope);
}

namespace {

struct Circle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0;
  bool holds(const Eigen::Vector2d& p) const {
    return (p - centre).norm() <= radius * (1 + 1e-12) + 1e-15;
  }
};

Circle circleThrough(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return {(a + b) / 2, (a - b).norm() / 2};
}

// The circle through three points; for points on one line, that through the farthest two.
Circle circleThrough(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d ab = b - a, ac = c - a;
  const double d = 2 * (ab.x() * ac.y() - ab.y() * ac.x());
  if (std::abs(d) < 1e-15 * (ab.squaredNorm() + ac.squaredNorm())) {
    Circle best = circleThrough(a, b);
    for (const Circle& other : {circleThrough(a, c), circleThrough(b, c)})
      if (other.radius > best.radius) best = other;
    return best;
  }
  const Eigen::Vector2d centre(ac.y() * ab.squaredNorm() - ab.y() * ac.squaredNorm(),
                               ab.x() * ac.squaredNorm() - ac.x() * ab.squaredNorm());
  return {a + centre / d, (centre / d).norm()};
}

}  // namespace

namespace {

// The algebraic sphere of `points`: |p|² = 2 c·p + k by least squares, r² = k + |c|².
SphereFit algebraicSphere(std::span<const Vec3> points) {
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::Vector4d right = Eigen::Vector4d::Zero();
  const Vec3 centre = centroidOf(points);
  for (const Vec3& point : points) {
    const Vec3 p = point - centre;
    const Eigen::Vector4d row(2 * p.x(), 2 * p.y(), 2 * p.z(), 1);
    normal += row * row.transpose();
    right += row * p.squaredNorm();
  }
  const Eigen::Vector4d x = normal.ldlt().solve(right);
  SphereFit fit;
  fit.centre = centre + x.head<3>();
  fit.radius = std::sqrt(std::max(x[3] + x.head<3>().squaredNorm(), 0.0));
  return fit;
}

// The smallest eigenvalue of the mean outer product of the points' directions from `c`.
double capSpread(std::span<const Vec3> points, const Vec3& c) {
  Eigen::Matrix3d mean = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) {
    const Vec3 u = (p - c).normalized();
    mean += u * u.transpose() / static_cast<double>(points.size());
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(mean).eigenvalues()[0];
}

}  // namespace

SphereFit fitSphere(std::span<const Vec3> points) {
  if (points.size() < 5) return {};
  SphereFit fit = algebraicSphere(points);
  constexpr int kIterations = 50;
  double last = std::numeric_limits<double>::infinity();  // the last step's size
  for (int iteration = 0; iteration < kIterations && last > 1e-12 * (1 + fit.radius); ++iteration) {
    Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
    Eigen::Vector4d gradient = Eigen::Vector4d::Zero();
    for (const Vec3& p : points) {
      const Vec3 d = p - fit.centre;
      const double rho = std::max(d.norm(), 1e-12);
      const Eigen::Vector4d row(-d.x() / rho, -d.y() / rho, -d.z() / rho, -1);
      normal += row * row.transpose();
      gradient += row * (rho - fit.radius);
    }
    const Eigen::Vector4d step = -normal.ldlt().solve(gradient);
    if (!step.allFinite()) return fit;
    fit.centre += step.head<3>();
    fit.radius += step[3];
    last = step.norm();
  }
  double squares = 0;
  for (const Vec3& p : points) squares += std::pow((p - fit.centre).norm() - fit.radius, 2);
  fit.rms = std::sqrt(squares / static_cast<double>(points.size()));
  fit.radius = std::abs(fit.radius);
  fit.determined = last < 1e-9 * (1 + fit.radius) && capSpread(points, fit.centre) >= kLeastCap;
  return fit;
}

double enclosingCircleDiameter(std::span<const Eigen::Vector2d> points) {
  if (points.empty()) return 0;
  // Welzl's incremental construction: each point outside the circle so far lies on the
  // smallest circle of the points up to it.
  Circle circle{points[0], 0};
  for (std::size_t i = 1; i < points.size(); ++i) {
    if (circle.holds(points[i])) continue;
    circle = {points[i], 0};
    for (std::size_t j = 0; j < i; ++j) {
      if (circle.holds(points[j])) continue;
      circle = circleThrough(points[i], points[j]);
      for (std::size_t k = 0; k < j; ++k)
        if (!circle.holds(points[k])) circle = circleThrough(points[i], points[j], points[k]);
    }
  }
  return 2 * circle.radius;
}

}  // namespace scanplan
