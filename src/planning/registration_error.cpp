// Each view's registration error (docs/capability.md, "Error budget"):
// - the reference view fixes its setup's frame: none;
// - reference points: the rigid fit of the known markers it sees, their centres measured
//   with registration.marker_sigma;
// - markers shared with the view it registers to: the same fit, both views' centres noisy,
//   then each group of views joined by markers adjusted together (marker_adjustment.h);
// - ICP: point-to-plane ICP on the overlap, each overlap point standing for the points the
//   views lay there with both views' noise, and moved by where the tangent planes at the
//   fixed view's points stand off the overlap's curved faces (samplingBias);
// - the robot: its pose accuracy, taken as the radius holding 95% of a view's position
//   errors (isotropic, no turn);
// and along a chain the errors of the links add: views registered through the same link
// move by the same draw of its error.

#include "planning/registration_error.h"

#include "planning/marker_adjustment.h"
#include "registration/overlaps.h"

#include <scanplan/cad/elementary.h>
#include <scanplan/planning/planner.h>
#include <scanplan/registration/registration.h>
#include <scanplan/scanner/simulation.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

namespace scanplan::detail {
namespace {

// The radius holding 95% of a 3-D isotropic Gaussian's draws, in its sigmas (the chi
// distribution with 3 degrees of freedom).
constexpr double kRadius95 = 2.7955;

// A covariance that marks a view whose error cannot be told (the plan's markers or overlap
// not found again): it is left out, as a view registered to nothing.
constexpr double kUnknown = -1;

// The rigid fit's covariance over the markers, unknown for fewer than 3.
TwistCovariance markerFit(const std::vector<Vec3>& positions, double sigma) {
  if (positions.size() < 3) return TwistCovariance::Identity() * kUnknown;
  return rigidFitCovariance(positions, sigma);
}

std::vector<Vec3> positionsOf(const std::vector<Vec3>& all, const std::vector<int>& indices) {
  std::vector<Vec3> chosen;
  for (int i : indices)
    if (i >= 0 && static_cast<std::size_t>(i) < all.size()) chosen.push_back(all[i]);
  return chosen;
}

// An ICP link's overlap is sampled this share of the field's height apart (2.25 mm for the
// generic head), at most. At the registration's overlap spacing (a fortieth), the arcs of a
// bore that two views share fall between a few samples: on a plate whose views share its
// top, one side and such arcs, a bore's position registered by those links came out at 2.2
// times the virtual inspection's with ICP run on the views' clouds (docs/capability.md),
// and at 1.18 times at this spacing.
constexpr double kIcpOverlapSpacing = 1.0 / 100;

// A view's own link: the error of its registration to the view `parent` (none: to its
// setup's frame), and whether it is placed at all.
struct Link {
  TwistCovariance own = TwistCovariance::Zero();
  Twist bias = Twist::Zero();  // ViewError::bias
  std::optional<std::size_t> parent;
  bool placed = true;
  std::shared_ptr<const Eigen::MatrixXd> adjusted;  // ViewError::adjusted
  std::size_t slot = 0;
};

// The sum of a face's principal curvatures at a point, signed for the face's outward normal
// (part frame): 0 on a face without an elementary surface. Each face's surface, and which
// way its outward normal points from it (as `normal` at the face's first point met), is
// found once.
class Curvatures {
 public:
  explicit Curvatures(const Part& part) : part_(part) {}
  double at(int face, const Vec3& p, const Vec3& normal) {
    auto [found, added] = faces_.try_emplace(face);
    Face& f = found->second;
    if (added && (f.surface = elementarySurface(part_, face)))
      f.side = nearestOn(*f.surface, p).second.dot(normal) >= 0 ? 1 : -1;
    return f.surface ? f.side * curvatureSum(*f.surface, p) : 0;
  }

 private:
  struct Face {
    std::optional<ElementarySurface> surface;
    double side = 1;
  };
  const Part& part_;
  std::map<int, Face> faces_;
};

// The motion point-to-plane ICP settles at where the fixed view's tangent planes stand off
// its overlap (`shifts`, along the normals): least squares on the overlap's rows, each
// sample weighing as the moved view's points there (`weights`), the directions the overlap
// leaves free held as ICP's steps hold them.
Twist samplingBias(std::span<const Vec3> points, std::span<const Vec3> normals,
                   std::span<const double> weights, std::span<const double> shifts) {
  TwistCovariance information = TwistCovariance::Zero();
  Twist pull = Twist::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto row = alongNormal(points[i], normals[i]);
    information += weights[i] * row.transpose() * row;
    pull += weights[i] * shifts[i] * row.transpose();
  }
  return heldInverse(information) * pull;
}

// The ICP covariance of every view of orientation `k` registered by ICP, against the view
// it registers to: the overlap sampled as the registration samples it.
void icpErrors(const Part& part, const ResolvedSpec& spec, const Plan& plan, std::size_t k,
               const std::vector<std::size_t>& orientation, std::vector<Link>& links) {
  const Registration& registration = *plan.registration;
  std::map<int, std::size_t> index;  // view id: its place in the plan
  std::vector<View> views;
  std::vector<std::size_t> places;
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    index[plan.views[v].id] = v;
    if (orientation[v] != k) continue;
    views.push_back(plan.views[v]);
    places.push_back(v);
  }
  const bool any = std::any_of(places.begin(), places.end(), [&](std::size_t v) {
    return registration.views[v].method == RegistrationMethod::Icp;
  });
  if (!any) return;
  const RegistrationOptions options = registrationOptions(spec.spec);
  const double spacing =
      std::min(overlapSpacing(options, plan.scanner), plan.scanner.fov_height * kIcpOverlapSpacing);
  const Pose placement = orientationPlacement(plan, k), to_part = placement.inverse();
  const Simulator simulator(part, plan.scanner, simulationOptionsFor(spec, part, placement));
  Curvatures curvatures(part);
  const std::vector<SurfacePoint> points = simulator.surfacePoints(spacing, options.seed);
  const std::vector<std::vector<int>> measured = measuredPoints(simulator, views, points);
  std::map<std::size_t, std::size_t> local;  // plan index: index into views
  for (std::size_t i = 0; i < places.size(); ++i) local[places[i]] = i;
  for (std::size_t i = 0; i < places.size(); ++i) {
    const std::size_t v = places[i];
    const ViewRegistration& r = registration.views[v];
    if (r.method != RegistrationMethod::Icp || !index.count(r.to)) continue;
    const auto to = local.find(index[r.to]);
    if (to == local.end()) continue;
    const std::vector<int> both = shared(measured[i], measured[to->second]);
    std::vector<Vec3> p, n;
    std::vector<double> variances, weights, shifts;
    for (int s : both) {
      const SurfacePoint& at = points[s];
      const PointQuality a = pointQuality(plan.scanner, views[i], at.position, at.normal);
      const PointQuality b = pointQuality(plan.scanner, views[to->second], at.position, at.normal);
      const double count = std::max(std::min(a.density, b.density) * spacing * spacing, 1.0);
      p.push_back(at.position);
      n.push_back(at.normal);
      variances.push_back((a.along_normal * a.along_normal + b.along_normal * b.along_normal) /
                          count);
      weights.push_back(a.density);
      const double curvature =
          curvatures.at(at.face, to_part * at.position, to_part.linear() * at.normal);
      shifts.push_back(samplingShift(curvature, 1 / b.density));
    }
    if (p.size() < 6) {  // too little overlap to say: the view is left out
      links[v].own = TwistCovariance::Identity() * kUnknown;
      continue;
    }
    links[v].own = icpCovariance(p, n, variances);
    links[v].bias = samplingBias(p, n, weights, shifts);
  }
}

}  // namespace

std::vector<Vec3> markerPositions(const Plan& plan, std::size_t k, std::size_t v) {
  std::vector<Marker> markers =
      plan.orientations.empty() ? plan.markers : plan.orientations[k].markers;
  if (plan.cell && plan.cell->table && v < plan.cell_poses.size() && plan.cell_poses[v]) {
    const TableTurn table{plan.cell->table->origin, plan.cell->table->axis, {}};
    markers = markersAtTableAngle(std::move(markers), table, plan.cell_poses[v]->table_angle);
  }
  std::vector<Vec3> positions;
  for (const Marker& m : markers) positions.push_back(m.position);
  return positions;
}

Vec3 displacement(const Twist& twist, const Vec3& p) {
  return Vec3(twist.head<3>()).cross(p) + twist.tail<3>();
}

Pose poseOf(const Twist& twist) {
  Pose pose = Pose::Identity();
  const Vec3 w = twist.head<3>();
  if (w.norm() > 0) pose.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  pose.translation() = twist.tail<3>();
  return pose;
}

Eigen::Matrix<double, 1, 6> alongNormal(const Vec3& p, const Vec3& n) {
  Eigen::Matrix<double, 1, 6> row;
  row << p.cross(n).transpose(), n.transpose();
  return row;
}

double samplingShift(double curvature, double area) { return curvature * area / 24; }

TwistCovariance icpCovariance(std::span<const Vec3> points, std::span<const Vec3> normals,
                              std::span<const double> variances) {
  TwistCovariance information = TwistCovariance::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto row = alongNormal(points[i], normals[i]);
    information += row.transpose() * row / variances[i];
  }
  return inverted(information);
}

namespace {

// The link of view `v` by the markers it registers by (the ICP links' errors are found
// beforehand, into `link.own`).
void markLink(const Plan& plan, std::size_t v, std::size_t orientation,
              const std::map<int, std::size_t>& index, double sigma, Link& link) {
  const Registration& registration = *plan.registration;
  const ViewRegistration& r = registration.views[v];
  const auto to = index.find(r.to);
  switch (r.method) {
    case RegistrationMethod::None: link.placed = false; break;
    case RegistrationMethod::Reference: break;
    case RegistrationMethod::Robot: {
      const double s = registration.robot_accuracy / kRadius95;
      link.own.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * s * s;
      break;
    }
    case RegistrationMethod::ReferencePoints:
      link.own = markerFit(positionsOf(markerPositions(plan, orientation, v), r.markers), sigma);
      break;
    case RegistrationMethod::Markers: {
      if (to == index.end()) break;
      std::vector<int> mine = r.markers, theirs = registration.views[to->second].markers;
      std::sort(mine.begin(), mine.end());
      std::sort(theirs.begin(), theirs.end());
      link.own = markerFit(positionsOf(markerPositions(plan, orientation, v), shared(mine, theirs)),
                           std::sqrt(2.0) * sigma);
      link.parent = to->second;
      break;
    }
    case RegistrationMethod::Icp:
      if (to != index.end()) link.parent = to->second;
      break;
  }
  if (link.own(0, 0) == kUnknown) {
    link.placed = false;
    link.own.setZero();
  }
}

// Along each chain, to the view that fixes the frame, the links' errors add.
void chain(const std::vector<Link>& links, std::vector<ViewError>& errors) {
  for (std::size_t v = 0; v < links.size(); ++v) {
    errors[v].covariance = errors[v].link = links[v].own;
    errors[v].bias = links[v].bias;
    errors[v].parent = links[v].parent;
    errors[v].placed = links[v].placed;
    errors[v].adjusted = links[v].adjusted;
    errors[v].slot = links[v].slot;
  }
  const Chains chains = chainsOf(errors);
  for (std::size_t v : chains.order)
    if (const std::optional<std::size_t>& parent = chains.parents[v]) {
      errors[v].covariance += errors[*parent].covariance;
      errors[v].placed = errors[v].placed && errors[*parent].placed;
    }
}

// The views registered by markers, adjusted in groups (marker_adjustment.h): each one's
// link runs to its group's root, with the group's covariance for its motion.
void adjust(const Plan& plan, double sigma, std::vector<Link>& links) {
  std::vector<std::optional<std::size_t>> parents;
  std::vector<char> placed;
  for (const Link& link : links) {
    parents.push_back(link.parent);
    placed.push_back(link.placed);
  }
  for (const MarkerGroup& group : markerGroups(plan, parents, placed)) {
    const Eigen::MatrixXd covariance = adjustedCovariance(plan, group, sigma);
    const auto factor = std::make_shared<const Eigen::MatrixXd>(
        Eigen::MatrixXd(Eigen::LLT<Eigen::MatrixXd>(covariance).matrixL()));
    for (std::size_t i = 0; i < group.members.size(); ++i) {
      Link& link = links[group.members[i]];
      const auto at = static_cast<Eigen::Index>(6 * i);
      link.own = covariance.block<6, 6>(at, at);
      link.parent = group.root;
      link.adjusted = factor;
      link.slot = i;
    }
  }
}

}  // namespace

std::vector<ViewError> registrationErrors(const Part& part, const ResolvedSpec& spec,
                                          const Plan& plan) {
  const std::size_t n = plan.views.size();
  std::vector<ViewError> errors(n);
  const std::vector<std::size_t> orientation = viewOrientations(plan);
  for (std::size_t v = 0; v < n; ++v)
    if (!plan.orientations.empty()) errors[v].frame = plan.orientations[orientation[v]].frame;
  if (!plan.registration || plan.registration->views.size() != n) return errors;
  const RegistrationOptions options = registrationOptions(spec.spec);
  const double sigma = markerSigma(options, plan.scanner);
  std::vector<Link> links(n);
  for (std::size_t k = 0; k < std::max<std::size_t>(1, plan.orientations.size()); ++k)
    icpErrors(part, spec, plan, k, orientation, links);
  std::map<int, std::size_t> index;
  for (std::size_t v = 0; v < n; ++v) index[plan.views[v].id] = v;
  for (std::size_t v = 0; v < n; ++v) markLink(plan, v, orientation[v], index, sigma, links[v]);
  adjust(plan, sigma, links);
  chain(links, errors);
  return errors;
}

Chains chainsOf(const std::vector<ViewError>& errors) {
  const std::size_t n = errors.size();
  Chains chains;
  chains.parents.resize(n);
  std::vector<char> state(n, 0);  // 1: on the chain being followed, 2: ordered
  const auto visit = [&](std::size_t v, auto& self) -> void {
    if (state[v]) return;
    state[v] = 1;
    const std::optional<std::size_t>& parent = errors[v].parent;
    if (parent && *parent < n && state[*parent] != 1) {  // a loop is cut where it closes
      self(*parent, self);
      chains.parents[v] = parent;
    }
    state[v] = 2;
    chains.order.push_back(v);
  };
  for (std::size_t v = 0; v < n; ++v) visit(v, visit);
  return chains;
}

TwistCovariance squareRoot(const TwistCovariance& covariance) {
  const Eigen::SelfAdjointEigenSolver<TwistCovariance> eigen(covariance);
  return eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0).cwiseSqrt().asDiagonal();
}

TwistDraws::TwistDraws(const std::vector<ViewError>& errors)
    : chains_(chainsOf(errors)), group_of_(errors.size(), -1) {
  for (std::size_t v = 0; v < errors.size(); ++v) {
    roots_.push_back(squareRoot(errors[v].link));
    biases_.push_back(errors[v].bias);
    slots_.push_back(errors[v].slot);
    if (!errors[v].adjusted) continue;
    const auto same = std::find_if(groups_.begin(), groups_.end(),
                                   [&](const auto& g) { return g.first == errors[v].adjusted; });
    group_of_[v] = static_cast<int>(same - groups_.begin());
    if (same == groups_.end()) groups_.push_back({errors[v].adjusted, {}});
    groups_[static_cast<std::size_t>(group_of_[v])].second.push_back(v);
  }
}

std::vector<Twist> TwistDraws::draw(std::mt19937_64& random) const {
  std::normal_distribution<double> normal;
  std::vector<Twist> own(roots_.size(), Twist::Zero());
  std::vector<char> drawn(groups_.size(), 0);
  for (std::size_t v = 0; v < roots_.size(); ++v) {
    const int g = group_of_[v];
    if (g < 0) {
      Twist z;
      for (int i = 0; i < 6; ++i) z[i] = normal(random);
      own[v] = biases_[v] + roots_[v] * z;
    } else if (!drawn[static_cast<std::size_t>(g)]) {  // the whole group at its first view
      drawn[static_cast<std::size_t>(g)] = 1;
      const auto& [factor, views] = groups_[static_cast<std::size_t>(g)];
      Eigen::VectorXd z(factor->rows());
      for (Eigen::Index i = 0; i < z.size(); ++i) z[i] = normal(random);
      const Eigen::VectorXd joint = factor->triangularView<Eigen::Lower>() * z;
      for (std::size_t u : views)
        own[u] = joint.segment<6>(static_cast<Eigen::Index>(6 * slots_[u]));
    }
  }
  std::vector<Twist> draws = own;
  for (std::size_t v : chains_.order)
    if (chains_.parents[v]) draws[v] += draws[*chains_.parents[v]];
  return draws;
}

}  // namespace scanplan::detail
