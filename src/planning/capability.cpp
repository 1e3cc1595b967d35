// Measurement capability per characteristic (docs/capability.md). The characteristics'
// faces are sampled once; each sample stands for its area, and each view that measures it
// puts there as many points as its pixel grid lays on that area, each with the part along
// the surface normal of the simulation's noise at its distance and incidence. The ideal
// geometry is fitted to the points by least squares (linearised: an offset along the
// normals, a shift and a small turn), and the noise's effect on the fitted geometry is
// drawn by Monte Carlo:
// - form, orientation and runout: the peak-to-valley of the fitted geometry's
//   displacement over the faces, with the highest and lowest noise of the points read
//   there (evaluationSpacing);
// - profile and position: twice its largest displacement, so widened (zones about the
//   nominal);
// - diameter and radius: the fitted offset (twice for a diameter); a distance between
//   features: the features' own offsets together; an angle between two features: their
//   fits' turns apart, each fitted on its own, in degrees. A feature is the faces of one
//   plane or cylinder, as the evaluation groups them.
// U is the error that 95% of the draws stay under.

#include "core/kd_tree.h"
#include "planning/evaluation.h"
#include "planning/registration_error.h"

#include <scanplan/cad/elementary.h>
#include <scanplan/cad/localization.h>
#include <scanplan/planning/capability.h>
#include <scanplan/planning/evidence.h>
#include <scanplan/planning/planner.h>
#include <scanplan/scanner/simulation.h>
#include <scanplan/solve/fits.h>

#include <tbb/parallel_for.h>
#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>

namespace scanplan {
namespace {

constexpr double kMinPoints = 25;  // fewer points cannot fit a feature soundly
constexpr double kMostlyUncovered = 0.5;
constexpr int kLeastCurveDraws = 20;  // Monte Carlo draws of a point of capableByViews

// What a view measures at a sample: the noise of its points and how many there are.
struct Look {
  double sigma = 0, points = 0;
  std::size_t view = 0;                                  // into the plan's views
  Vec3 position = Vec3::Zero(), normal = Vec3::UnitZ();  // in the view's world
};

// A sample of a characteristic's faces (part frame) and the views' looks at it.
struct Patch {
  SurfacePoint point;
  double area = 0;
  std::vector<Look> looks;
  int feature = 0;  // its face's feature: faces of one plane, cylinder or sphere share one
  double points() const {
    double n = 0;
    for (const Look& l : looks) n += l.points;
    return n;
  }
  // The noise of the points' mean, each point alike as the evaluation's least squares
  // weighs them.
  double meanSigma() const {
    double variance = 0;
    for (const Look& l : looks) variance += l.points * l.sigma * l.sigma;
    return std::sqrt(variance) / points();
  }
};

// How the noise shows in a characteristic's value; profile stands for every zone about
// the nominal (profile, position, symmetry, concentricity); an angle is in degrees. The
// orientation of cylinders is their fitted axes' turn (AxisTilt), their position,
// concentricity and coaxiality their fitted axes' place (AxisPlace).
enum class Effect { Form, Profile, Size, Diameter, Radius, Angle, AxisTilt, AxisPlace };

// `on_cylinders`: the characteristic's features are cylinders.
Effect effectOf(const Characteristic& c, bool on_cylinders) {
  if (c.dimension)
    return c.kind == "diameter" || c.kind == "spherical_diameter" ? Effect::Diameter
           : c.kind == "radius" || c.kind == "spherical_radius"   ? Effect::Radius
           : c.kind.find("angular") != c.kind.npos                ? Effect::Angle
                                                                  : Effect::Size;
  if (on_cylinders && detail::orientationKind(c.kind)) return Effect::AxisTilt;
  const bool place = c.kind == "position" || c.kind == "concentricity" || c.kind == "coaxiality";
  if (on_cylinders && place) return Effect::AxisPlace;
  if (place || c.kind == "profile_of_surface" || c.kind == "profile_of_line" ||
      c.kind == "symmetry")
    return Effect::Profile;
  return Effect::Form;
}

// A feature's B-Rep surface (none where its face has no elementary surface) and, for a
// cylinder, the band its faces span along the axis (from the surface's origin), mm.
struct FeatureSurface {
  std::optional<ElementarySurface> surface;
  double low = 0, high = 0;
  bool cylinder() const { return surface && surface->type == SurfaceType::Cylinder; }
};
using FeatureSurfaces = std::vector<FeatureSurface>;  // by Patch::feature

using Row = Eigen::Matrix<double, 7, 1>;
using Normal = Eigen::Matrix<double, 7, 7>;

// The least-squares fit of the ideal geometry to a characteristic's measured patches,
// linearised: an offset along the normals (a size), a shift and a small turn. Each
// patch's row maps the parameters to its displacement along its normal; each weighs as its
// points, every point alike, as the evaluation fits them.
struct Fit {
  std::vector<Row> rows;
  std::vector<double> weights;  // each patch's points
  Eigen::LDLT<Normal> normal;
  Vec3 centre = Vec3::Zero();  // the turn's, the patches' mean
  double extent = 0;           // the patches' largest distance apart (their box's diagonal), mm
};

// How a cylinder's fit sees its patches: its axis, how far each patch's points spread along
// it (its square's side, within the band its faces span), and whether the axis is held to
// its designed direction.
struct AlongAxis {
  Vec3 axis;
  double band = 0;
  bool held = false;
};

// `cylinder`: the points of each patch spread along the axis, which turns the axis however
// few rows of samples a short band holds.
Fit fitOf(const std::vector<const Patch*>& patches,
          const std::optional<AlongAxis>& cylinder = std::nullopt) {
  Vec3 centre = Vec3::Zero();
  for (const Patch* p : patches) centre += p->point.position / static_cast<double>(patches.size());
  Fit fit;
  fit.centre = centre;
  Box box;
  for (const Patch* p : patches) box.add(p->point.position);
  fit.extent = std::max(box.diagonal(), 1e-9);
  Normal normal = Normal::Zero();
  for (const Patch* p : patches) {
    Row row;
    row << 1, p->point.normal, (p->point.position - centre).cross(p->point.normal);
    normal += row * row.transpose() * p->points();
    fit.rows.push_back(row);
    fit.weights.push_back(p->points());
    if (cylinder) {  // a point `along` from the centre turns by (along axis) x normal more
      const double along = std::min(std::sqrt(p->area), cylinder->band);
      Row spread = Row::Zero();
      spread.tail<3>() = cylinder->axis.cross(p->point.normal);
      normal += spread * spread.transpose() * p->points() * along * along / 12;
    }
  }
  // Directions the faces leave free (along a plane, about a cylinder's axis) stay at 0.
  normal += 1e-9 * (normal.trace() + 1) * Normal::Identity();
  if (cylinder && cylinder->held) {
    const Vec3& a = cylinder->axis;
    const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - a * a.transpose();
    normal.bottomRightCorner<3, 3>() += 1e9 * (normal.trace() + 1) * across;
  }
  fit.normal.compute(normal);
  return fit;
}

// A cylinder's axis as the evaluation fits it to the cylinder's own points: the fit of its
// patches, and the ends of the band measured along the axis.
struct AxisFit {
  std::vector<std::size_t> members;                 // its patches, into the characteristic's
  Vec3 point = Vec3::Zero(), axis = Vec3::UnitZ();  // the designed axis
  double low = 0, high = 0;                         // the band's ends along it, from `point`
  Fit fit;
};

// The axis of cylinder `s` fitted to `members` of `patches`; `hold_short` as the
// evaluation's (detail::kShortBand).
AxisFit axisOf(const std::vector<const Patch*>& patches, std::vector<std::size_t> members,
               const FeatureSurface& s, bool hold_short) {
  AxisFit a;
  a.members = std::move(members);
  a.point = s.surface->origin;
  a.axis = s.surface->axis.normalized();
  a.low = std::numeric_limits<double>::infinity();
  a.high = -a.low;
  double pitch = 0;  // each patch stands for a square of its area about its centre
  std::vector<const Patch*> on;
  for (std::size_t i : a.members) {
    on.push_back(patches[i]);
    a.low = std::min(a.low, (patches[i]->point.position - a.point).dot(a.axis));
    a.high = std::max(a.high, (patches[i]->point.position - a.point).dot(a.axis));
    pitch = std::max(pitch, std::sqrt(patches[i]->area));
  }
  a.low -= pitch / 2;
  a.high += pitch / 2;
  double band = a.high - a.low;
  if (s.high > s.low) {  // within the faces' band (a face without triangles has none)
    a.low = std::max(a.low, s.low);
    a.high = std::min(a.high, s.high);
    band = s.high - s.low;
  }
  const bool short_band = a.high - a.low < detail::kShortBand * s.surface->radius;
  a.fit = fitOf(on, AlongAxis{a.axis, band, hold_short && short_band});
  return a;
}

// The patches of each cylinder among `patches`' features, by feature; `others` gets the
// rest.
std::map<int, std::vector<std::size_t>> onCylinders(const std::vector<const Patch*>& patches,
                                                    const FeatureSurfaces& surfaces,
                                                    std::vector<std::size_t>& others) {
  std::map<int, std::vector<std::size_t>> cylinders;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    if (surfaces[patches[i]->feature].cylinder())
      cylinders[patches[i]->feature].push_back(i);
    else
      others.push_back(i);
  }
  return cylinders;
}

// The characteristic's cylinders' axes, each fitted to its own patches; none unless every
// patch lies on a cylinder.
std::vector<AxisFit> axesOf(const std::vector<const Patch*>& patches,
                            const FeatureSurfaces& surfaces, bool hold_short) {
  std::vector<std::size_t> others;
  std::map<int, std::vector<std::size_t>> cylinders = onCylinders(patches, surfaces, others);
  if (!others.empty()) return {};
  std::vector<AxisFit> axes;
  for (auto& [feature, members] : cylinders)
    axes.push_back(axisOf(patches, std::move(members), surfaces[feature], hold_short));
  return axes;
}

// How a cylinder's axis moves under displacements `d` of the characteristic's patches: its
// ends, across it.
std::pair<Vec3, Vec3> endShifts(const AxisFit& a, const std::vector<double>& d) {
  Row pull = Row::Zero();
  for (std::size_t k = 0; k < a.members.size(); ++k)
    pull += a.fit.rows[k] * d[a.members[k]] * a.fit.weights[k];
  const Row x = a.fit.normal.solve(pull);
  const Vec3 shift = x.segment<3>(1), turn = x.tail<3>();
  const auto across = [&](double along) {
    const Vec3 u = shift + turn.cross(a.point + along * a.axis - a.fit.centre);
    return Vec3(u - u.dot(a.axis) * a.axis);
  };
  return {across(a.low), across(a.high)};
}

// The change of the cylinders' orientation (`tilt`: an axis' ends apart across it) or
// position (twice the farther end from where it was) under `d`: of several, the largest,
// as the evaluation takes a pattern's.
double axisChange(const std::vector<AxisFit>& axes, const std::vector<double>& d, bool tilt) {
  double largest = 0;
  for (const AxisFit& a : axes) {
    const auto [low, high] = endShifts(a, d);
    largest = std::max(largest, tilt ? (high - low).norm() : 2 * std::max(low.norm(), high.norm()));
  }
  return largest;
}

using Row6 = Eigen::Matrix<double, 1, 6>;
using Normal6 = Eigen::Matrix<double, 6, 6>;

// The rigid motion that best explains patches' displacements `d` along their normals
// (least squares, each point alike), the directions the patches leave free held at 0: one
// face's fitted motion.
class RigidFit {
 public:
  explicit RigidFit(const std::vector<const Patch*>& patches) {
    Normal6 normal = Normal6::Zero();
    for (const Patch* p : patches) {
      const Row6 row = detail::alongNormal(p->point.position, p->point.normal);
      rows_.push_back(row);
      weights_.push_back(p->points());
      normal += row.transpose() * row * p->points();
    }
    normal += 1e-9 * (normal.trace() + 1) * Normal6::Identity();
    normal_.compute(normal);
  }
  detail::Twist motion(const std::vector<double>& d) const {
    detail::Twist pull = detail::Twist::Zero();
    for (std::size_t j = 0; j < rows_.size(); ++j)
      pull += rows_[j].transpose() * d[j] * weights_[j];
    return normal_.solve(pull);
  }

 private:
  std::vector<Row6> rows_;
  std::vector<double> weights_;
  Eigen::LDLT<Normal6> normal_;
};

// The rows that hold a datum cylinder's axis: each of its two ends across the axis, along
// two directions, as the evaluation's datum alignment holds it.
std::array<std::pair<Row6, Vec3>, 4> endRows(const AxisFit& a) {
  const Vec3 e1 = a.axis.unitOrthogonal(), e2 = a.axis.cross(e1);
  std::array<std::pair<Row6, Vec3>, 4> rows;
  std::size_t k = 0;
  for (const double along : {a.low, a.high})
    for (const Vec3& e : {e1, e2})
      rows[k++] = {detail::alongNormal(a.point + along * a.axis, e), e};
  return rows;
}

// The datum reference frame's motion under displacements `d` of its features' patches,
// fitted as the evaluation aligns it (evaluation.h, datumAlignment): a plane by its points
// along its normal, a cylinder by its fitted axis' ends across it (its radius free, so
// an arc that leaves the axis loose leaves the frame loose), each datum weighing
// kDatumPrecedence times the next.
class DatumFit {
 public:
  // `shares`: each patch's weight over its points'.
  DatumFit(const std::vector<const Patch*>& patches, const std::vector<double>& shares,
           const FeatureSurfaces& surfaces) {
    std::vector<std::size_t> planes;
    Normal6 normal = Normal6::Zero();
    for (auto& [feature, members] : onCylinders(patches, surfaces, planes)) {
      double weight = 0;
      for (std::size_t i : members) weight += shares[i] * patches[i]->points();
      AxisFit axis = axisOf(patches, std::move(members), surfaces[feature], true);
      const std::array<std::pair<Row6, Vec3>, 4> rows = endRows(axis);
      for (const auto& [row, e] : rows) normal += row.transpose() * row * weight;
      axes_.push_back({std::move(axis), rows, weight});
    }
    for (std::size_t i : planes) {
      const Row6 row = detail::alongNormal(patches[i]->point.position, patches[i]->point.normal);
      planes_.push_back({i, row, shares[i] * patches[i]->points()});
      normal += row.transpose() * row * planes_.back().weight;
    }
    inverse_ = detail::heldInverse(normal);
  }
  bool empty() const { return planes_.empty() && axes_.empty(); }
  detail::Twist motion(const std::vector<double>& d) const {
    detail::Twist pull = detail::Twist::Zero();
    for (const PlaneRow& p : planes_) pull += p.row.transpose() * d[p.patch] * p.weight;
    for (const AxisRows& a : axes_) {
      const auto [low, high] = endShifts(a.axis, d);
      for (std::size_t k = 0; k < 4; ++k)
        pull += a.rows[k].first.transpose() * a.rows[k].second.dot(k < 2 ? low : high) * a.weight;
    }
    return inverse_ * pull;
  }

 private:
  struct PlaneRow {
    std::size_t patch;
    Row6 row;
    double weight;
  };
  struct AxisRows {  // a datum cylinder: its axis, the rows that hold it, its weight
    AxisFit axis;
    std::array<std::pair<Row6, Vec3>, 4> rows;
    double weight;
  };
  std::vector<PlaneRow> planes_;
  std::vector<AxisRows> axes_;
  Normal6 inverse_;
};

// The two features of an angle between faces, each fitted apart as a rigid motion that
// best explains its patches' displacements, as the inspection fits a plane to each: the
// angle between them changes under displacements `d` of the patches by the two fits' turns
// apart about the axis across both features' normals. Empty unless the patches lie on
// exactly two features that are not parallel.
class FacePair {
 public:
  explicit FacePair(const std::vector<const Patch*>& patches) {
    std::map<int, std::vector<std::size_t>> by_feature;
    for (std::size_t i = 0; i < patches.size(); ++i) by_feature[patches[i]->feature].push_back(i);
    if (by_feature.size() != 2) return;
    Vec3 normals[2] = {Vec3::Zero(), Vec3::Zero()};
    std::size_t k = 0;
    for (const auto& [feature, members] : by_feature) {
      for (std::size_t i : members) normals[k] += patches[i]->point.normal;
      normals[k++].normalize();
    }
    const Vec3 across = normals[0].cross(normals[1]);
    if (across.norm() < std::sin(radians(1))) return;  // parallel faces: no axis to turn about
    axis_ = across.normalized();
    for (auto& [feature, members] : by_feature) {
      std::vector<const Patch*> on;
      for (std::size_t i : members) on.push_back(patches[i]);
      fits_.emplace_back(on);
      members_.push_back(std::move(members));
    }
  }
  bool empty() const { return fits_.empty(); }
  // The angle's change, degrees.
  double change(const std::vector<double>& d) const {
    Vec3 turns[2];
    for (std::size_t k = 0; k < 2; ++k) {
      std::vector<double> on;
      for (std::size_t i : members_[k]) on.push_back(d[i]);
      turns[k] = fits_[k].motion(on).head<3>();
    }
    return degrees(std::abs((turns[0] - turns[1]).dot(axis_)));
  }

 private:
  std::vector<std::vector<std::size_t>> members_;  // per feature: its patches' indices
  std::vector<RigidFit> fits_;
  Vec3 axis_ = Vec3::Zero();
};

// Each datum patch's share in the datum reference frame's fit, as the inspection aligns it
// (evaluation.h): each datum weighs kDatumPrecedence times the next, shared among its
// patches by their points.
std::vector<double> datumShares(const Gdt& gdt, const Characteristic& c,
                                const std::vector<const Patch*>& datum) {
  std::map<int, std::size_t> rank;  // each datum face's place in the frame, the first naming it
  for (std::size_t k = c.datums.size(); k-- > 0;)
    for (int face : datumFaces(gdt, c.datums[k])) rank[face] = k;
  std::vector<std::size_t> order;
  std::vector<double> totals(c.datums.size() + 1, 0.0);
  for (const Patch* p : datum) {
    const auto found = rank.find(p->point.face);
    order.push_back(found == rank.end() ? c.datums.size() : found->second);
    totals[order.back()] += p->points();
  }
  std::vector<double> shares;
  for (std::size_t i = 0; i < datum.size(); ++i)
    shares.push_back(std::pow(detail::kDatumPrecedence, -static_cast<double>(order[i])) /
                     totals[order[i]]);
  return shares;
}

std::vector<double> sigmasOf(const std::vector<const Patch*>& patches) {
  std::vector<double> sigmas;
  for (const Patch* p : patches) sigmas.push_back(p->meanSigma());
  return sigmas;
}

// The points a zone is read from on a patch (evaluationSpacing): how many, and the noise
// along the normal left on each, the mean of the scanner's points it stands for; `share`
// the scanner's point spacing over the evaluation's (at most 1).
struct ZonePoints {
  double count = 0, sigma = 0;
};
std::vector<ZonePoints> zonePointsOf(const std::vector<const Patch*>& patches, double share) {
  std::vector<ZonePoints> zone;
  for (const Patch* p : patches) {
    // Each point's noise before the mean: the root mean square of the looks'.
    const double points = p->points();
    zone.push_back(
        {share * share * points, points > 0 ? share * p->meanSigma() * std::sqrt(points) : 0});
  }
  return zone;
}

// Each feature's patches among `patches` (their indices), with their own fit.
std::vector<std::pair<std::vector<std::size_t>, Fit>> apartOf(
    const std::vector<const Patch*>& patches) {
  std::map<int, std::vector<std::size_t>> features;
  for (std::size_t i = 0; i < patches.size(); ++i) features[patches[i]->feature].push_back(i);
  std::vector<std::pair<std::vector<std::size_t>, Fit>> apart;
  for (auto& [feature, members] : features) {
    std::vector<const Patch*> on;
    for (std::size_t i : members) on.push_back(patches[i]);
    apart.emplace_back(std::move(members), fitOf(on));
  }
  return apart;
}

// What a characteristic's draws read: its measured patches, their features (faces of one
// plane, cylinder or sphere alike) and their fit, its cylinders' axes, each feature's own
// fit, and its datum features' patches (none without datums).
struct Measured {
  std::vector<const Patch*> feature, datum;
  std::vector<double> feature_sigmas, datum_sigmas;  // each patch's meanSigma()
  std::vector<ZonePoints> feature_zone;
  Fit fit;
  std::vector<AxisFit> axes;
  // Each feature's patches (indices into `feature`) fitted apart, as a pattern's sizes are.
  std::vector<std::pair<std::vector<std::size_t>, Fit>> apart;
  DatumFit datum_motion;
  FacePair faces;
  bool planar;  // the patches lie on one plane
  // `orientation`: the characteristic tolerances an orientation, so its cylinders' axes
  // turn however short their bands.
  Measured(std::vector<const Patch*> f, std::vector<const Patch*> d,
           const std::vector<double>& datum_shares, const FeatureSurfaces& surfaces,
           bool orientation, double zone_share)
      : feature(std::move(f)),
        datum(std::move(d)),
        feature_sigmas(sigmasOf(feature)),
        datum_sigmas(sigmasOf(datum)),
        feature_zone(zonePointsOf(feature, zone_share)),
        fit(fitOf(feature)),
        axes(axesOf(feature, surfaces, !orientation)),
        apart(apartOf(feature)),
        datum_motion(datum, datum_shares, surfaces),
        faces(feature),
        planar(std::all_of(feature.begin(), feature.end(), [&](const Patch* p) {
          return p->point.normal.dot(feature.front()->point.normal) > std::cos(radians(1));
        })) {}
};

// `d` (per feature patch) less the datum features' fitted motion under their `datum_d`.
void relativeToDatums(const Measured& m, const std::vector<double>& datum_d,
                      std::vector<double>& d) {
  if (m.datum_motion.empty()) return;
  const detail::Twist motion = m.datum_motion.motion(datum_d);
  for (std::size_t i = 0; i < d.size(); ++i)
    d[i] -= detail::alongNormal(m.feature[i]->point.position, m.feature[i]->point.normal) * motion;
}

// The fitted geometry's displacement at each patch, and what it leaves of `d`.
struct Fitted {
  std::vector<double> at, residual;
  double offset = 0;  // the fitted size offset
};
Fitted fitted(const Fit& fit, const std::vector<double>& d) {
  Row pull = Row::Zero();
  for (std::size_t i = 0; i < d.size(); ++i) pull += fit.rows[i] * d[i] * fit.weights[i];
  const Row x = fit.normal.solve(pull);
  Fitted f;
  f.offset = x[0];
  for (std::size_t i = 0; i < d.size(); ++i) {
    f.at.push_back(fit.rows[i].dot(x));
    f.residual.push_back(d[i] - f.at.back());
  }
  return f;
}

double range(const std::vector<double>& values) {
  if (values.empty()) return 0;
  const auto [low, high] = std::minmax_element(values.begin(), values.end());
  return *high - *low;
}
double largestMagnitude(const std::vector<double>& values) {
  double m = 0;
  for (double v : values) m = std::max(m, std::abs(v));
  return m;
}

// The size offset `fit` of the patches `members` gives under displacements `d` (of all).
double offsetOn(const Fit& fit, const std::vector<std::size_t>& members,
                const std::vector<double>& d) {
  std::vector<double> mine;
  for (std::size_t k : members) mine.push_back(d[k]);
  return fitted(fit, mine).offset;
}

// The change of a diameter (`times` 2) or a radius (1) under the patches' displacements
// `d`: the fitted size offset `whole`; of a pattern (of cylinders or spheres), each fitted
// to its own patches, the largest, as each is evaluated.
double sizeChange(const Measured& m, const std::vector<double>& d, const Fitted& whole,
                  double times) {
  double largest = 0;
  if (m.axes.size() > 1) {
    for (const AxisFit& a : m.axes)
      largest = std::max(largest, std::abs(offsetOn(a.fit, a.members, d)));
  } else if (m.apart.size() > 1) {
    for (const auto& [members, fit] : m.apart)
      largest = std::max(largest, std::abs(offsetOn(fit, members, d)));
  } else {
    largest = std::abs(whole.offset);
  }
  return times * largest;
}

// The change of an angle between faces under the patches' displacements `d`, degrees: as
// the two faces' own fits see it; else (not two faces at an angle) the tilt the whole fit
// leaves over its extent, `f` its displacements.
double angleChange(const Measured& m, const std::vector<double>& d, const std::vector<double>& f) {
  return m.faces.empty() ? degrees(std::atan(range(f) / m.fit.extent)) : m.faces.change(d);
}

// Per feature of the patches, the weighted mean of `d` (a feature's offset, as the
// evaluation fits each feature whole) and of the patches' normals.
std::vector<std::pair<double, Vec3>> featureOffsets(const Measured& m,
                                                    const std::vector<double>& d) {
  struct Sums {
    double offset = 0, weight = 0;
    Vec3 normal = Vec3::Zero();
  };
  std::map<int, Sums> features;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double w = m.fit.weights[i];
    Sums& f = features[m.feature[i]->feature];
    f.offset += w * d[i];
    f.weight += w;
    f.normal += w * m.feature[i]->point.normal;
  }
  std::vector<std::pair<double, Vec3>> offsets;
  for (const auto& [feature, f] : features)
    offsets.push_back({f.offset / f.weight, f.normal.normalized()});
  return offsets;
}

// How far the distance between two features changes when they move by their offsets
// along their own normals: apart by both where they face away from each other (a
// thickness), by the difference where they face alike (a step). With other than two
// features, the offsets added.
double distanceChange(const std::vector<std::pair<double, Vec3>>& offsets) {
  if (offsets.size() == 2)
    return std::abs(offsets[0].first - offsets[1].first * offsets[1].second.dot(offsets[0].second));
  double sum = 0;
  for (const auto& [offset, normal] : offsets) sum += offset;
  return std::abs(sum);
}

// The standard normal quantile of p in (0, 1): Acklam's rational approximation, refined
// by one step of Halley's method.
double normalQuantile(double p) {
  constexpr std::array<double, 6> a{-3.969683028665376e+01, 2.209460984245205e+02,
                                    -2.759285104469687e+02, 1.383577518672690e+02,
                                    -3.066479806614716e+01, 2.506628277459239e+00};
  constexpr std::array<double, 5> b{-5.447609879822406e+01, 1.615858368580409e+02,
                                    -1.556989798598866e+02, 6.680131188771972e+01,
                                    -1.328068155288572e+01};
  constexpr std::array<double, 6> c{-7.784894002430293e-03, -3.223964580411365e-01,
                                    -2.400758277161838e+00, -2.549732539343734e+00,
                                    4.374664141464968e+00,  2.938163982698783e+00};
  constexpr std::array<double, 4> d{7.784695709041462e-03, 3.224671290700398e-01,
                                    2.445134137142996e+00, 3.754408661907416e+00};
  constexpr double low = 0.02425;
  const auto tail = [&](double q) {  // the quantile of a lower tail q
    const double r = std::sqrt(-2 * std::log(q));
    return (((((c[0] * r + c[1]) * r + c[2]) * r + c[3]) * r + c[4]) * r + c[5]) /
           ((((d[0] * r + d[1]) * r + d[2]) * r + d[3]) * r + 1);
  };
  double x;
  if (p < low) {
    x = tail(p);
  } else if (p > 1 - low) {
    x = -tail(1 - p);
  } else {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  }
  const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
  const double u = e * std::sqrt(2 * std::numbers::pi) * std::exp(x * x / 2);
  return x - u / (1 + x * u / 2);
}

// The largest of `count` draws of the standard normal: the quantile of u^(1 / count), its
// upper tail 1 - u^(1 / count) taken without cancellation.
double largestOf(double count, std::mt19937_64& random) {
  std::uniform_real_distribution<double> uniform(std::numeric_limits<double>::min(), 1.0);
  return -normalQuantile(-std::expm1(std::log(uniform(random)) / count));
}

// The band a zone read from the points spans: at each patch the fitted geometry's
// displacement `at` with the highest and with the lowest noise of one draw of its points
// (a patch that holds less than one point holds one as often as its count says).
std::vector<double> withPointNoise(const std::vector<double>& at,
                                   const std::vector<ZonePoints>& zone, std::mt19937_64& random) {
  std::uniform_real_distribution<double> uniform;
  std::normal_distribution<double> normal;
  std::vector<double> band;
  for (std::size_t i = 0; i < at.size(); ++i) {
    const ZonePoints& z = zone[i];
    if (z.count < 1 && uniform(random) >= z.count) continue;
    if (z.count < 2) {  // one point: its noise is both extremes
      band.push_back(at[i] + z.sigma * normal(random));
      continue;
    }
    band.push_back(at[i] + z.sigma * largestOf(z.count, random));
    band.push_back(at[i] - z.sigma * largestOf(z.count, random));
  }
  return band.empty() ? at : band;
}

// One draw of the noise's error on the characteristic's value: the fitted geometry's
// displacement from the true one (relative to its datums' fit), as the characteristic
// measures it; a zone (form, profile) read from the points spans their own noise too, drawn
// from `extremes`.
double noiseError(Effect effect, const Measured& m, std::mt19937_64& random,
                  std::mt19937_64& extremes) {
  std::normal_distribution<double> normal;
  std::vector<double> d, datum_d;
  for (double sigma : m.feature_sigmas) d.push_back(sigma * normal(random));
  for (double sigma : m.datum_sigmas) datum_d.push_back(sigma * normal(random));
  relativeToDatums(m, datum_d, d);
  const Fitted f = fitted(m.fit, d);
  switch (effect) {
    case Effect::Diameter: return sizeChange(m, d, f, 2);
    case Effect::Radius: return sizeChange(m, d, f, 1);
    case Effect::Size: return distanceChange(featureOffsets(m, d));
    case Effect::Angle: return angleChange(m, d, f.at);
    case Effect::Form: return range(withPointNoise(f.at, m.feature_zone, extremes));
    case Effect::Profile:
      return 2 * largestMagnitude(withPointNoise(f.at, m.feature_zone, extremes));
    case Effect::AxisTilt: return axisChange(m.axes, d, true);
    case Effect::AxisPlace: return axisChange(m.axes, d, false);
  }
  return 0;
}

// Each look's displacement at its patch under `moves`, less `less` (per patch): where the
// views that measure a patch lie apart, their points lie in layers, and a zone spans them
// all.
std::vector<double> lookDisplacements(const Measured& m, const std::vector<detail::Twist>& moves,
                                      const std::vector<double>& less) {
  std::vector<double> layers;
  for (std::size_t i = 0; i < m.feature.size(); ++i)
    for (const Look& l : m.feature[i]->looks)
      layers.push_back((detail::alongNormal(l.position, l.normal) * moves[l.view])(0) - less[i]);
  return layers;
}

// One draw of the registration's error on the value: each view moved by a draw of its
// error. A size or an angle is fitted to each patch moved by the mean of its points' motions;
// a zone (form, profile) holds every view's points, each patch's layers apart. A rigid motion
// of the whole does not change a form, a size or an angle: only the views' motions against
// one another, and against the datums' views, do.
double registrationError(Effect effect, const Measured& m,
                         const std::vector<detail::Twist>& moves) {
  const auto moved = [&](const Patch* p) {
    double sum = 0, weight = 0;
    for (const Look& l : p->looks) {
      sum += l.points * (detail::alongNormal(l.position, l.normal) * moves[l.view])(0);
      weight += l.points;
    }
    return weight > 0 ? sum / weight : 0.0;
  };
  std::vector<double> d, datum_d;
  for (const Patch* p : m.feature) d.push_back(moved(p));
  for (const Patch* p : m.datum) datum_d.push_back(moved(p));
  const bool relative = !m.datum.empty();
  std::vector<double> datum_shift(d.size(), 0.0);  // the datums' fitted motion at each patch
  if (relative) {
    std::vector<double> shifted = d;
    relativeToDatums(m, datum_d, shifted);
    for (std::size_t i = 0; i < d.size(); ++i) datum_shift[i] = d[i] - shifted[i];
    d = shifted;
  }
  const Fitted f = fitted(m.fit, d);
  std::vector<double> fitted_at = f.at;  // the fitted geometry, in the frame the layers lie
  for (std::size_t i = 0; i < d.size(); ++i) fitted_at[i] += datum_shift[i];
  switch (effect) {
    case Effect::Form:  // a plane's orientation: the layers in the datums' frame, place free
      if (relative && m.planar) return range(lookDisplacements(m, moves, datum_shift));
      return (relative ? range(f.at) : 0.0) + range(lookDisplacements(m, moves, fitted_at));
    case Effect::Profile:
      return 2 * largestMagnitude(lookDisplacements(m, moves, relative ? datum_shift : fitted_at));
    case Effect::Diameter: return sizeChange(m, d, f, 2);
    case Effect::Radius: return sizeChange(m, d, f, 1);
    case Effect::Size:  // features moved alike keep their distance
      return distanceChange(featureOffsets(m, d));
    case Effect::Angle: return angleChange(m, d, f.residual);
    case Effect::AxisTilt: return axisChange(m.axes, d, true);  // the fit holds the layers
    case Effect::AxisPlace: return axisChange(m.axes, d, false);
  }
  return 0;
}

// The value 95% of `errors` stay under.
double percentile95(std::vector<double> errors) {
  if (errors.empty()) return 0;
  const auto at =
      errors.begin() + static_cast<std::ptrdiff_t>(0.95 * static_cast<double>(errors.size() - 1));
  std::nth_element(errors.begin(), at, errors.end());
  return *at;
}

// The scanner's acceptance figure that bounds the characteristic's value (a maximum
// permissible error, mm; 0: the preset states none): the flatness error for the form and
// orientation of planes and axes, the probing error of form for curved form, of size for
// sizes, the sphere-spacing error for distances, locations and profiles.
double acceptanceFigure(const Characteristic& c, Effect effect, const Scanner& s) {
  switch (effect) {
    case Effect::Diameter: return s.probing_size;
    case Effect::Radius: return s.probing_size / 2;
    case Effect::Size: return s.sphere_spacing;
    case Effect::Angle: return 0;
    case Effect::Profile:
    case Effect::AxisPlace: return std::max(s.sphere_spacing, s.probing_form);
    case Effect::AxisTilt:
    case Effect::Form:
      return c.kind == "circularity" || c.kind == "cylindricity" ||
                     c.kind.find("runout") != c.kind.npos
                 ? s.probing_form
                 : s.flatness_error;
  }
  return 0;
}

// The budget and U of a characteristic measured as `m`: the noise's and the registration's
// by Monte Carlo, the scanner's from its acceptance figure as a uniform distribution
// within it (U = 2 MPE / sqrt 3); U their root sum of squares.
ErrorBudget budgetOf(const Characteristic& c, const Measured& m, const Scanner& scanner,
                     const detail::TwistDraws& moves, const CapabilityOptions& options,
                     std::uint64_t seed) {
  const Effect effect = effectOf(c, !m.axes.empty());
  std::mt19937_64 random(seed + static_cast<std::uint64_t>(c.id));
  std::mt19937_64 extremes(~(seed + static_cast<std::uint64_t>(c.id)));
  std::vector<double> noise, registration;
  for (int k = 0; k < options.draws; ++k) {
    noise.push_back(noiseError(effect, m, random, extremes));
    registration.push_back(registrationError(effect, m, moves.draw(random)));
  }
  return {percentile95(std::move(noise)), percentile95(std::move(registration)),
          2 * acceptanceFigure(c, effect, scanner) / std::sqrt(3.0)};
}

// The features of faces: faces whose B-Rep surfaces are one plane, cylinder or sphere
// share one (detail::oneFeature); a face without such a surface has its own.
struct Features {
  std::map<int, int> of_face;  // face id: its feature's index
  FeatureSurfaces surfaces;    // each feature's first face's surface
};

// Where face `id`'s triangles lie along the axis of `s` (from its origin), added to `f`.
void extendBand(const Part& part, int id, FeatureSurface& f) {
  const Face& face = part.face(id);
  for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t)
    for (const int v : part.mesh.triangles[static_cast<std::size_t>(t)]) {
      const double at = (part.mesh.vertices[v] - f.surface->origin).dot(f.surface->axis);
      f.low = std::min(f.low, at);
      f.high = std::max(f.high, at);
    }
}

// The features of the characteristics' faces and their datums'.
Features featuresOf(const Part& part, const std::vector<Characteristic>& list) {
  std::set<int> faces;
  for (const Characteristic& c : list) {
    faces.insert(c.faces.begin(), c.faces.end());
    if (!c.dimension)
      for (int f : datumFaces(part.gdt, c)) faces.insert(f);
  }
  Features features;
  FeatureSurfaces& firsts = features.surfaces;
  for (int f : faces) {
    const std::optional<ElementarySurface> surface = elementarySurface(part, f);
    auto same = std::find_if(firsts.begin(), firsts.end(), [&](const FeatureSurface& first) {
      return surface && first.surface && detail::oneFeature(*first.surface, *surface);
    });
    if (same == firsts.end()) {
      const double inf = std::numeric_limits<double>::infinity();
      same = firsts.insert(firsts.end(), {surface, inf, -inf});
    }
    features.of_face[f] = static_cast<int>(same - firsts.begin());
    if (same->cylinder()) extendBand(part, f, *same);
  }
  return features;
}

// The faces of `features`, sampled once (part frame), each sample a patch.
std::vector<Patch> patchesOf(const Part& part, const Features& features) {
  std::vector<int> faces;
  for (const auto& [face, feature] : features.of_face) faces.push_back(face);
  std::vector<Patch> patches;
  for (const Sample& s : sampleSurface(part, faces, Role::Priority, TaskType::Gdt))
    patches.push_back({{s.position, s.normal, s.face}, s.weight, {}, features.of_face.at(s.face)});
  return patches;
}

// The looks of every view of `plan` at the patches, each view in its orientation's world,
// setup by setup.
void look(const Part& part, const ResolvedSpec& spec, const Plan& plan,
          std::vector<Patch>& patches) {
  std::vector<SurfacePoint> points;
  for (const Patch& p : patches) points.push_back(p.point);
  const std::vector<std::vector<int>> measured = measuredByViews(plan, part, spec, points);
  const std::vector<std::size_t> orientation = viewOrientations(plan);
  for (std::size_t k = 0; k < std::max<std::size_t>(1, plan.orientations.size()); ++k) {
    const Pose placed = orientationPlacement(plan, k);
    for (std::size_t v = 0; v < plan.views.size(); ++v) {
      if (orientation[v] != k) continue;
      for (int i : measured[v]) {
        const Vec3 position = placed * points[i].position;
        const Vec3 normal = placed.linear() * points[i].normal;
        const PointQuality q = pointQuality(plan.scanner, plan.views[v], position, normal);
        patches[i].looks.push_back(
            {q.along_normal, patches[i].area * q.density, v, position, normal});
      }
    }
  }
}

// Whether the measured patches of a diameter or radius on cylinders determine its fit:
// on each of its cylinders (one, or a pattern's), they span kLeastArc of the circle about
// the cylinder's axis.
bool cylinderFitted(const Part& part, const Characteristic& c, const std::vector<const Patch*>& all,
                    const std::vector<const Patch*>& measured) {
  if (!c.dimension || (c.kind != "diameter" && c.kind != "radius")) return false;
  for (int f : c.faces)
    if (f < 1 || f > static_cast<int>(part.faces.size()) ||
        part.faces[f - 1].type != SurfaceType::Cylinder)
      return false;
  std::map<int, std::vector<const Patch*>> cylinders, seen;
  for (const Patch* p : all) cylinders[p->feature].push_back(p);
  for (const Patch* p : measured) seen[p->feature].push_back(p);
  for (const auto& [feature, patches] : cylinders) {
    if (patches.size() < 5) return false;
    std::vector<Vec3> points, normals, on;
    for (const Patch* p : patches) {
      points.push_back(p->point.position);
      normals.push_back(p->point.normal);
    }
    for (const Patch* p : seen[feature]) on.push_back(p->point.position);
    const CylinderFit axis = cylinderFromNormals(points, normals);
    if (!axis.determined || arcAbout(axis, on) < kLeastArc) return false;
  }
  return !cylinders.empty();
}

// Whether `c` is not a distance or an angle between features, or is one whose faces'
// patches `all` lie on two features, as the evaluation's definition needs.
bool betweenTwo(const Characteristic& c, const std::vector<const Patch*>& all) {
  static const std::set<std::string> between = {"linear_distance", "thickness", "angular_location",
                                                "angular_size", "oriented_location"};
  if (!c.dimension || between.count(c.kind) == 0) return true;
  std::set<int> features;
  for (const Patch* p : all) features.insert(p->feature);
  return features.size() == 2;
}

// A characteristic's patches as the views placed in one frame measure them: the frame whose
// views measure most of its area (and its datums'). `lost_*`: the area measured otherwise,
// by views of other setups not joined to that one, or by views that register to nothing.
struct InOneFrame {
  std::vector<Patch> feature, datum;
  double lost_to_setups = 0, lost_unregistered = 0;
};
InOneFrame inOneFrame(const std::vector<const Patch*>& feature,
                      const std::vector<const Patch*>& datum,
                      const std::vector<detail::ViewError>& errors) {
  std::map<std::size_t, double> area_by_frame;
  for (const auto* list : {&feature, &datum})
    for (const Patch* p : *list) {
      std::set<std::size_t> frames;
      for (const Look& l : p->looks)
        if (errors[l.view].placed) frames.insert(errors[l.view].frame);
      for (std::size_t f : frames) area_by_frame[f] += p->area;
    }
  std::size_t frame = 0;
  double most = -1;
  for (const auto& [f, area] : area_by_frame)
    if (area > most) frame = f, most = area;
  InOneFrame result;
  const auto keep = [&](const Patch* p, bool count) {
    Patch kept = *p;
    kept.looks.clear();
    bool placed_elsewhere = false;
    for (const Look& l : p->looks)
      if (!errors[l.view].placed)
        continue;
      else if (errors[l.view].frame == frame)
        kept.looks.push_back(l);
      else
        placed_elsewhere = true;
    if (count && kept.looks.empty() && !p->looks.empty())
      (placed_elsewhere ? result.lost_to_setups : result.lost_unregistered) += p->area;
    return kept;
  };
  for (const Patch* p : feature) result.feature.push_back(keep(p, true));
  for (const Patch* p : datum) result.datum.push_back(keep(p, false));
  return result;
}

// The farthest a patch lies from a measured one, and the measured points' own pitch.
double largestGap(const std::vector<const Patch*>& patches) {
  double gap = 0;
  std::vector<Vec3> measured;
  for (const Patch* p : patches)
    if (!p->looks.empty()) {
      measured.push_back(p->point.position);
      gap = std::max(gap, std::sqrt(p->area / p->points()));
    }
  if (measured.size() == patches.size()) return gap;
  if (measured.empty()) return std::numeric_limits<double>::infinity();
  const detail::PointCloudAdaptor cloud{measured};
  detail::PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  for (const Patch* p : patches) {
    if (!p->looks.empty()) continue;
    unsigned nearest = 0;
    double squared = 0;
    tree.knnSearch(p->point.position.data(), 1, &nearest, &squared);
    gap = std::max(gap, std::sqrt(squared));
  }
  return gap;
}

// Whether the patch lies face down on the working plane, the part placed by `pose`.
bool onPlane(const Pose& pose, const Patch& p) {
  return (pose.linear() * p.point.normal).z() < -0.9 && (pose * p.point.position).z() < 1;
}

// The rest orientation that turns up the most of the unmeasured area lying on the working
// plane, when that is most of the unmeasured area.
std::optional<std::size_t> restFor(const std::vector<const Patch*>& patches,
                                   const std::vector<RestOrientation>& rests, const Pose& placed) {
  double unmeasured = 0, down = 0;
  for (const Patch* p : patches)
    if (p->looks.empty()) {
      unmeasured += p->area;
      if (onPlane(placed, *p)) down += p->area;
    }
  if (unmeasured == 0 || down < 0.5 * unmeasured) return std::nullopt;
  std::optional<std::size_t> best;
  double best_up = 0;
  for (std::size_t r = 0; r < rests.size(); ++r) {
    double up = 0;
    for (const Patch* p : patches)
      if (onPlane(placed, *p) && (rests[r].part_to_world.linear() * p->point.normal).z() > -0.5)
        up += p->area;
    if (up > best_up) best = r, best_up = up;
  }
  return best;
}

// `fitted`: what is measured determines the size's fit whatever share of the faces it is
// (a cylinder's band measured all round), so the share measured does not judge it.
// `datums_covered`: the share of its datum features' area measured (1 without datums).
void judge(const Characteristic& c, Capability& k, const CapabilityOptions& options, bool fitted,
           double datums_covered) {
  k.ratio = k.uncertainty > 0 ? c.width() / (2 * k.uncertainty) : 0;
  const bool sparse = (!fitted && k.covered < kCoveredEnough) || k.points < kMinPoints;
  if (!(c.width() > 0)) {
    k.verdict = Verdict::Untoleranced;
  } else if (!fitted && k.covered < kMostlyUncovered) {
    k.verdict = Verdict::NotCapable;
    k.reason = Shortfall::Uncovered;
  } else if (datums_covered < kDatumsCoveredEnough) {
    k.verdict = Verdict::NotCapable;
    k.reason = Shortfall::DatumsUnmeasured;
  } else if (k.ratio >= options.capable_ratio && !sparse) {
    k.verdict = Verdict::Capable;
  } else {
    k.verdict = k.ratio >= options.marginal_ratio ? Verdict::Marginal : Verdict::NotCapable;
    k.reason = sparse ? Shortfall::TooSparse : Shortfall::TooUncertain;
  }
}

// The measured datum patches of `framed` (into `measured`), and the share of the datum
// features' area they cover (1 without datums). A patch face down on the working plane
// does not count: the plane the part stands on simulates it.
double datumShare(const InOneFrame& framed, const Pose& placed,
                  std::vector<const Patch*>& measured) {
  double area = 0, covered = 0;
  for (const Patch& p : framed.datum) {
    if (onPlane(placed, p)) continue;
    area += p.area;
    if (p.looks.empty()) continue;
    measured.push_back(&p);
    covered += p.area;
  }
  return area > 0 ? covered / area : 1;
}

// The ids of the views whose looks at `patches` count.
std::vector<int> servingViews(const InOneFrame& framed, const Plan& plan) {
  std::set<int> ids;
  for (const auto* list : {&framed.feature, &framed.datum})
    for (const Patch& p : *list)
      for (const Look& l : p.looks) ids.insert(plan.views[l.view].id);
  return {ids.begin(), ids.end()};
}

// Whether poses measure `enough` of `faces`, by the plan's samples on them: NotTargeted when
// it has none, NoPoseReaches when its search found poses for less than that share.
Limit reachOf(const std::vector<int>& faces, double enough, const Plan& plan) {
  double on = 0, reached = 0;
  for (const PlannedSample& s : plan.samples)
    if (std::binary_search(faces.begin(), faces.end(), s.sample.face)) {
      ++on;
      if (s.uncoverable == Uncoverable::None) ++reached;
    }
  if (on == 0) return Limit::NotTargeted;
  return reached < enough * on ? Limit::NoPoseReaches : Limit::None;
}

// Why `c`, judged `k`, is beyond what more views can do; Limit::None when it is capable or
// they may help.
Limit limitOf(const Part& part, const Characteristic& c, const Capability& k, const Plan& plan,
              const CapabilityOptions& options) {
  if (k.verdict == Verdict::Capable || k.verdict == Verdict::Untoleranced) return Limit::None;
  if (k.reason == Shortfall::NotLinked) return Limit::NotLinked;
  const double largest = c.width() / (2 * options.capable_ratio);  // U a capable one reaches
  // An axis' tilt and place take the figures of a plane's orientation and of a profile.
  const double scanner = 2 * acceptanceFigure(c, effectOf(c, false), plan.scanner) / std::sqrt(3.0);
  if (scanner > largest) return Limit::BelowScannerError;
  switch (k.reason) {
    case Shortfall::SetupsNotJoined: return Limit::SetupsNotJoined;
    case Shortfall::NotRegistered: return Limit::NotRegistered;
    case Shortfall::TooUncertain:
      return k.budget.registration > largest ? Limit::RegistrationError : Limit::None;
    case Shortfall::DatumsUnmeasured:
      return reachOf(datumFaces(part.gdt, c), kDatumsCoveredEnough, plan);
    default: return reachOf(c.faces, kCoveredEnough, plan);
  }
}

}  // namespace

std::string_view toString(Verdict verdict) {
  switch (verdict) {
    case Verdict::Capable: return "capable";
    case Verdict::Marginal: return "marginal";
    case Verdict::NotCapable: return "not_capable";
    case Verdict::Untoleranced: return "untoleranced";
  }
  return "?";
}

std::string_view toString(Limit limit) {
  switch (limit) {
    case Limit::None: return "none";
    case Limit::NotLinked: return "not_linked";
    case Limit::NotTargeted: return "not_targeted";
    case Limit::NoPoseReaches: return "no_pose_reaches";
    case Limit::SetupsNotJoined: return "setups_not_joined";
    case Limit::NotRegistered: return "not_registered";
    case Limit::BelowScannerError: return "below_scanner_error";
    case Limit::RegistrationError: return "registration_error";
  }
  return "?";
}

std::string_view toString(Shortfall reason) {
  switch (reason) {
    case Shortfall::None: return "none";
    case Shortfall::Uncovered: return "uncovered";
    case Shortfall::TooSparse: return "too_sparse";
    case Shortfall::TooUncertain: return "too_uncertain";
    case Shortfall::NotLinked: return "not_linked";
    case Shortfall::NotRegistered: return "not_registered";
    case Shortfall::SetupsNotJoined: return "setups_not_joined";
    case Shortfall::DatumsUnmeasured: return "datums_unmeasured";
  }
  return "?";
}

namespace {

// What the capability of characteristics is judged from: the looks of the views of the
// plan at the characteristics' patches, their features' surfaces, its registration errors
// and the part's rest orientations, found once for every count of views judged.
struct Judging {
  std::vector<Patch> patches;
  FeatureSurfaces surfaces;
  std::vector<detail::ViewError> errors;
  std::vector<RestOrientation> rests;
};

// The capability of `c` under the views of `plan`, judged from `by`, the plan's registration
// errors drawn by `moves`.
Capability judgedOne(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                     const Characteristic& c, const Judging& by, const detail::TwistDraws& moves,
                     const CapabilityOptions& options) {
  const auto on = [&](const std::vector<int>& faces) {
    std::vector<const Patch*> mine;
    for (const Patch& p : by.patches)
      if (std::binary_search(faces.begin(), faces.end(), p.point.face)) mine.push_back(&p);
    return mine;
  };
  const std::vector<const Patch*> all = on(c.faces);
  const InOneFrame framed = inOneFrame(
      all, c.dimension ? std::vector<const Patch*>{} : on(datumFaces(part.gdt, c)), by.errors);
  std::vector<const Patch*> mine, measured, datum;
  for (const Patch& p : framed.feature) mine.push_back(&p);
  const double datums_covered = datumShare(framed, plan.part_to_world, datum);
  Capability k;
  k.characteristic = c.id;
  double covered = 0;
  for (const Patch* p : mine) {
    k.area += p->area;
    if (p->looks.empty()) continue;
    measured.push_back(p);
    covered += p->area;
    k.points += p->points();
  }
  k.covered = k.area > 0 ? covered / k.area : 0;
  k.density = covered > 0 ? k.points / covered : 0;
  k.largest_gap = largestGap(mine);
  if (!measured.empty()) {
    const Measured m(
        measured, datum, datumShares(part.gdt, c, datum), by.surfaces,
        detail::orientationKind(c.kind),
        std::min(1.0, plan.scanner.point_spacing / evaluationSpacing(plan.scanner, options)));
    k.budget = budgetOf(c, m, plan.scanner, moves, options, spec.spec.planner.seed);
    k.uncertainty = std::hypot(k.budget.noise, k.budget.registration, k.budget.scanner);
  }
  judge(c, k, options, cylinderFitted(part, c, mine, measured), datums_covered);
  // Nothing to fit, no frame to fit in, or a dimension between features linked to other
  // than two of them (a distance on one face): none the evaluation can find.
  if (c.faces.empty() || !datumsLinked(part.gdt, c) || !betweenTwo(c, all)) {
    k.verdict = c.width() > 0 ? Verdict::NotCapable : Verdict::Untoleranced;
    k.reason = Shortfall::NotLinked;
  } else if (k.reason == Shortfall::Uncovered || k.reason == Shortfall::TooSparse) {
    // Measured enough, but partly in views the frame cannot take.
    const double lost = framed.lost_to_setups + framed.lost_unregistered;
    const double enough = k.reason == Shortfall::Uncovered ? kMostlyUncovered : kCoveredEnough;
    if (lost > 0 && (covered + lost) / k.area >= enough)
      k.reason = framed.lost_to_setups >= framed.lost_unregistered ? Shortfall::SetupsNotJoined
                                                                   : Shortfall::NotRegistered;
  }
  if (k.covered < kCoveredEnough) k.rest = restFor(all, by.rests, plan.part_to_world);
  k.limit = limitOf(part, c, k, plan, options);
  k.views = servingViews(framed, plan);
  return k;
}

// The capability of each of `characteristics` under the views of `plan`, judged from `by`:
// each apart from the others (its own random draws), all at once.
std::vector<Capability> judged(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                               const std::vector<Characteristic>& characteristics,
                               const Judging& by, const CapabilityOptions& options) {
  const detail::TwistDraws moves(by.errors);
  std::vector<Capability> result(characteristics.size());
  tbb::parallel_for(std::size_t{0}, characteristics.size(), [&](std::size_t i) {
    result[i] = judgedOne(part, spec, plan, characteristics[i], by, moves, options);
  });
  return result;
}

std::size_t capableCount(const std::vector<Capability>& judged) {
  return static_cast<std::size_t>(
      std::count_if(judged.begin(), judged.end(),
                    [](const Capability& k) { return k.verdict == Verdict::Capable; }));
}

bool chained(RegistrationMethod m) {
  return m == RegistrationMethod::Markers || m == RegistrationMethod::Icp;
}

// Whether view `v` of `plan` is placed among its first `count` views: its chain of
// registrations ends, within them, at a view that fixes a frame.
bool placedWithin(const Plan& plan, std::size_t v, std::size_t count) {
  if (!plan.registration) return true;
  const std::vector<ViewRegistration>& views = plan.registration->views;
  std::size_t at = v;
  for (std::size_t hops = 0; chained(views[at].method) && hops <= count; ++hops) {
    if (views[at].to < 1 || static_cast<std::size_t>(views[at].to) > count) return false;
    at = static_cast<std::size_t>(views[at].to) - 1;
  }
  return views[at].method != RegistrationMethod::None;
}

// How many characteristics the first views of `plan` make capable, at `points` counts of
// views spread up to all `n` of them (capable_at_n at the last), judged from `all`, the
// whole plan's.
std::vector<CapableCount> capableByViews(const Part& part, const ResolvedSpec& spec,
                                         const Plan& plan,
                                         const std::vector<Characteristic>& characteristics,
                                         const Judging& all, std::size_t capable_at_n,
                                         std::size_t points) {
  const bool ordered = std::all_of(plan.views.begin(), plan.views.end(), [&](const View& v) {
    return v.id == static_cast<int>(&v - plan.views.data()) + 1;
  });
  if (plan.views.empty() || !plan.orientations.empty() || !ordered) return {};
  CapabilityOptions options = spec.spec.planner.capability;
  options.draws = std::max(kLeastCurveDraws, options.draws / 4);
  std::vector<CapableCount> result;
  const std::size_t n = plan.views.size();
  for (std::size_t step = 1; step < std::min(points, n); ++step) {
    const std::size_t count = (n * step + points - 1) / points;
    if (!result.empty() && result.back().views == count) continue;
    Judging first = all;
    for (Patch& p : first.patches)
      std::erase_if(p.looks, [&](const Look& l) { return l.view >= count; });
    // A link's error is the same in the first views: a view keeps its own, or, registering
    // through a later one, is placed nowhere.
    for (std::size_t v = 0; v < n; ++v)
      first.errors[v].placed = v < count && all.errors[v].placed && placedWithin(plan, v, count);
    result.push_back(
        {count, capableCount(judged(part, spec, plan, characteristics, first, options))});
  }
  result.push_back({n, capable_at_n});
  return result;
}

}  // namespace

double evaluationSpacing(const Scanner& scanner, const CapabilityOptions& options) {
  return options.evaluation_spacing > 0 ? std::min(options.evaluation_spacing, scanner.fov_height)
                                        : scanner.fov_height / 100;
}

std::vector<Capability> capabilities(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                                     const std::vector<Characteristic>& characteristics) {
  return judgeCapability(part, spec, plan, characteristics, 0).capabilities;
}

CapabilityJudgement judgeCapability(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                                    const std::vector<Characteristic>& characteristics,
                                    std::size_t points) {
  if (characteristics.empty()) return {};
  Features features = featuresOf(part, characteristics);
  Judging by{patchesOf(part, features), std::move(features.surfaces),
             detail::registrationErrors(part, spec, plan), restOrientations(part)};
  look(part, spec, plan, by.patches);
  CapabilityJudgement result;
  result.capabilities = judged(part, spec, plan, characteristics, by, spec.spec.planner.capability);
  if (points > 0)
    result.by_views = capableByViews(part, spec, plan, characteristics, by,
                                     capableCount(result.capabilities), points);
  return result;
}

}  // namespace scanplan
