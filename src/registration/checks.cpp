// Reference markers and the two pair tests: shared markers, ICP stability.

#include <scanplan/cad/raycast.h>
#include <scanplan/core/errors.h>
#include <scanplan/registration/registration.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <optional>

namespace scanplan {

std::string_view toString(MarkerCarrier carrier) {
  switch (carrier) {
    case MarkerCarrier::Plane: return "plane";
    case MarkerCarrier::Table: return "table";
    case MarkerCarrier::Part: return "part";
  }
  return "unknown";
}

std::shared_ptr<const TableTurn> tableTurnFor(const Vec3& origin, const Vec3& axis,
                                              const std::vector<Marker>& markers,
                                              std::function<double(const View&)> angle) {
  if (std::none_of(markers.begin(), markers.end(),
                   [](const Marker& m) { return m.on == MarkerCarrier::Plane; }))
    return nullptr;
  return std::make_shared<const TableTurn>(TableTurn{origin, axis, std::move(angle)});
}

std::vector<Marker> markersAtTableAngle(std::vector<Marker> markers, const TableTurn& table,
                                        double angle) {
  const Pose turn = turnAbout(table.origin, table.axis, -angle);
  for (Marker& m : markers)
    if (m.on == MarkerCarrier::Plane) {
      m.position = turn * m.position;
      m.normal = turn.linear() * m.normal;
    }
  return markers;
}

std::vector<Marker> markerGrid(const Box& footprint, double step, double margin) {
  if (!(step > 0)) throw InputError("markers", "the marker grid step must be positive");
  if (!(margin >= 0)) throw InputError("markers", "the marker grid margin must not be negative");
  std::vector<Marker> markers;
  if (footprint.empty()) return markers;
  const double x0 = footprint.min.x() - margin, y0 = footprint.min.y() - margin;
  const auto columns = static_cast<int>(std::floor((footprint.max.x() + margin - x0) / step));
  const auto rows = static_cast<int>(std::floor((footprint.max.y() + margin - y0) / step));
  for (int r = 0; r <= rows; ++r)
    for (int c = 0; c <= columns; ++c) {
      const Vec3 p(x0 + c * step, y0 + r * step, 0);
      const bool under_part = p.x() >= footprint.min.x() && p.x() <= footprint.max.x() &&
                              p.y() >= footprint.min.y() && p.y() <= footprint.max.y();
      if (!under_part) markers.push_back({p, Vec3::UnitZ()});
    }
  return markers;
}

std::vector<Marker> markersOnPart(const TriangleMesh& mesh, double step) {
  if (!(step > 0)) throw InputError("markers", "the marker grid step must be positive");
  Box box;
  for (const Vec3& v : mesh.vertices) box.add(v);
  std::vector<Marker> markers;
  if (box.empty()) return markers;
  std::vector<Ray> rays;
  for (double y = box.min.y() + step / 2; y < box.max.y(); y += step)
    for (double x = box.min.x() + step / 2; x < box.max.x(); x += step)
      rays.push_back(Ray{Vec3(x, y, box.max.z() + 1), -Vec3::UnitZ()});
  for (const auto& hit : castRays(mesh, rays))
    if (hit && hit->normal.z() >= std::cos(M_PI / 4))
      markers.push_back({hit->point, hit->normal, MarkerCarrier::Part, hit->face});
  return markers;
}

bool markersRegister(std::span<const Vec3> positions, int min_count, double spread) {
  if (positions.size() < static_cast<std::size_t>(std::max(min_count, 3))) return false;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : positions) centre += p;
  centre /= static_cast<double>(positions.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Vec3& p : positions) scatter += (p - centre) * (p - centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  const Vec3 axis = solver.eigenvectors().col(2);  // the line of best fit
  for (const Vec3& p : positions) {
    const Vec3 d = p - centre;
    if ((d - d.dot(axis) * axis).norm() > spread) return true;
  }
  return false;
}

namespace {

// The covariance icpCondition takes the eigenvalues of; none where the condition is
// infinite before them (fewer than 6 points, no weight, no spread).
std::optional<Eigen::Matrix<double, 6, 6>> icpCovariance(std::span<const Vec3> points,
                                                         std::span<const Vec3> normals,
                                                         std::span<const double> weights) {
  const std::size_t n = std::min(points.size(), normals.size());
  if (n < 6) return std::nullopt;
  auto weight = [&](std::size_t i) { return weights.empty() ? 1.0 : weights[i]; };
  Vec3 centre = Vec3::Zero();
  double total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    centre += weight(i) * points[i];
    total += weight(i);
  }
  if (!(total > 0)) return std::nullopt;
  centre /= total;
  double scale = 0;
  for (std::size_t i = 0; i < n; ++i) scale += weight(i) * (points[i] - centre).norm();
  scale /= total;
  if (!(scale > 0)) return std::nullopt;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Matrix<double, 6, 1> row;
    row << ((points[i] - centre) / scale).cross(normals[i]), normals[i];
    covariance += weight(i) * row * row.transpose();
  }
  return covariance;
}

double conditionOf(const Eigen::Matrix<double, 6, 6>& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> solver(covariance,
                                                                          Eigen::EigenvaluesOnly);
  const auto& eigenvalues = solver.eigenvalues();  // ascending
  const double largest = eigenvalues(5), smallest = eigenvalues(0);
  if (!(smallest > largest * 1e-12)) return std::numeric_limits<double>::infinity();
  return largest / smallest;
}

}  // namespace

double icpCondition(std::span<const Vec3> points, std::span<const Vec3> normals,
                    std::span<const double> weights) {
  const auto covariance = icpCovariance(points, normals, weights);
  return covariance ? conditionOf(*covariance) : std::numeric_limits<double>::infinity();
}

bool icpConditionWithin(std::span<const Vec3> points, std::span<const Vec3> normals, double limit,
                        std::span<const double> weights) {
  // By Cauchy's interlacing theorem the covariance's largest eigenvalue is at least that of
  // each diagonal block, and its smallest at most: the ratio of a block's, or of the two
  // blocks' together, bounds the condition from below. The translations' block needs no
  // centre, and alone exceeds any limit on a plane or a cylinder. The blocks' eigenvalues
  // in closed form.
  const auto exceeds = [&](double largest, double smallest) { return largest > limit * smallest; };
  Eigen::Matrix3d normal_block = Eigen::Matrix3d::Zero();
  const std::size_t n = std::min(points.size(), normals.size());
  for (std::size_t i = 0; i < n; ++i)
    normal_block += (weights.empty() ? 1.0 : weights[i]) * normals[i] * normals[i].transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> translations, rotations;
  translations.computeDirect(normal_block, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d& t = translations.eigenvalues();  // ascending
  if (n >= 6 && exceeds(t(2), t(0))) return false;
  const auto covariance = icpCovariance(points, normals, weights);
  if (!covariance) return false;
  rotations.computeDirect(covariance->topLeftCorner<3, 3>(), Eigen::EigenvaluesOnly);
  const Eigen::Vector3d& r = rotations.eigenvalues();
  if (exceeds(std::max(r(2), t(2)), std::min(r(0), t(0)))) return false;
  return conditionOf(*covariance) <= limit;
}

}  // namespace scanplan
