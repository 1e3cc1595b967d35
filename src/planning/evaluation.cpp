// Characteristics evaluated from points by their definitions (docs/capability.md,
// "Virtual inspection").

#include "planning/evaluation.h"

#include "cad/face_triangles.h"
#include "core/kd_tree.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <set>

namespace scanplan::detail {

namespace {

// Cross-sections of circularity and circular runout, mm along the axis.
constexpr double kSlice = 3;
constexpr std::size_t kLeastPoints = 12;

// A feature: faces of one geometry (one plane, one cylinder), as designed.
struct Feature {
  SurfaceType type = SurfaceType::Other;
  std::vector<int> faces;
  const NominalFace* nominal = nullptr;  // its first face's
  // As designed, fitted to its faces' designed points as the measured ones are fitted.
  PlaneFit plane;
  CylinderFit cylinder;
};

// Faces of one feature lie along one another within kAlong (1 - |cos|) and apart by less
// than kApart mm, as the mesh gives them (each face's chords its own).
constexpr double kAlong = 1e-3, kApart = 0.1;

// A face as designed as the surface its points were fitted to (planes and cylinders), or
// a sphere's as the B-Rep gives it.
ElementarySurface surfaceOf(const NominalFace& f) {
  if (f.type == SurfaceType::Cylinder)
    return {SurfaceType::Cylinder, f.cylinder.point, f.cylinder.axis, f.cylinder.radius};
  if (f.sphere) return *f.sphere;
  return {f.type, f.centroid, f.normal};
}

bool sameGeometry(const NominalFace& a, const NominalFace& b) {
  return oneFeature(surfaceOf(a), surfaceOf(b));
}

}  // namespace

bool oneFeature(const ElementarySurface& a, const ElementarySurface& b) {
  if (a.type != b.type) return false;
  const bool along = std::abs(std::abs(a.axis.dot(b.axis)) - 1) < kAlong;
  const Vec3 apart = b.origin - a.origin;
  if (a.type == SurfaceType::Plane) return along && std::abs(a.axis.dot(apart)) < kApart;
  if (a.type == SurfaceType::Cylinder)
    return along && (apart - apart.dot(a.axis) * a.axis).norm() < kApart &&
           std::abs(a.radius - b.radius) < kApart;
  if (a.type == SurfaceType::Sphere)
    return apart.norm() < kApart && std::abs(a.radius - b.radius) < kApart;
  return false;
}

namespace {

// `faces` grouped into features.
std::vector<Feature> featuresOf(const std::vector<int>& faces, const Nominal& nominal) {
  std::vector<Feature> features;
  for (int f : faces) {
    const NominalFace* face = nominal.face(f);
    if (!face) continue;
    const auto same = std::find_if(features.begin(), features.end(), [&](const Feature& g) {
      return sameGeometry(*g.nominal, *face);
    });
    if (same != features.end())
      same->faces.push_back(f);
    else
      features.push_back({face->type, {f}, face, {}, {}});
  }
  for (Feature& g : features) {
    std::vector<Vec3> points;
    for (int f : g.faces)
      points.insert(points.end(), nominal.face(f)->points.begin(), nominal.face(f)->points.end());
    g.plane = fitPlane(points, g.nominal->normal);
    if (g.type == SurfaceType::Cylinder) g.cylinder = fitCylinder(points, g.nominal->cylinder);
  }
  return features;
}

std::vector<Vec3> pointsOn(const std::vector<int>& faces, const FacePoints& points) {
  std::vector<Vec3> all;
  for (int f : faces)
    if (const auto found = points.find(f); found != points.end())
      all.insert(all.end(), found->second.begin(), found->second.end());
  return all;
}

// The feature's cylinder fitted to its points, if they fix it. `hold_short`: a band shorter
// than kShortBand keeps its designed axis' direction (not for an orientation, which is that
// direction).
std::optional<CylinderFit> cylinderOf(const Feature& f, const std::vector<Vec3>& points,
                                      bool hold_short = true) {
  if (f.type != SurfaceType::Cylinder || points.size() < kLeastPoints) return std::nullopt;
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const Vec3& p : points) {
    low = std::min(low, p.dot(f.cylinder.axis));
    high = std::max(high, p.dot(f.cylinder.axis));
  }
  const CylinderFit fit =
      fitCylinder(points, f.cylinder, hold_short && high - low < kShortBand * f.cylinder.radius);
  if (!fit.determined || arcAbout(fit, points) < kLeastArc) return std::nullopt;
  return fit;
}

// Along the axis, the points' extent: the fitted axis' ends.
std::pair<Vec3, Vec3> axisEnds(const CylinderFit& c, const std::vector<Vec3>& points) {
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const Vec3& p : points) {
    low = std::min(low, (p - c.point).dot(c.axis));
    high = std::max(high, (p - c.point).dot(c.axis));
  }
  return {c.point + low * c.axis, c.point + high * c.axis};
}

double perpendicular(const Vec3& d, const Vec3& axis) { return (d - d.dot(axis) * axis).norm(); }

// The largest range of the radial distances about `axis` over cross-sections along it.
double largestSectionRange(const CylinderFit& axis, const std::vector<Vec3>& points) {
  std::map<long, std::pair<double, double>> sections;  // low, high radial distance
  std::map<long, std::size_t> counts;
  for (const Vec3& p : points) {
    const long k = std::lround((p - axis.point).dot(axis.axis) / kSlice);
    const double r = axisDistance(axis, p);
    auto [it, fresh] = sections.try_emplace(k, r, r);
    it->second = {std::min(it->second.first, r), std::max(it->second.second, r)};
    ++counts[k];
  }
  double largest = 0;
  for (const auto& [k, range] : sections)
    if (counts[k] >= kLeastPoints / 2) largest = std::max(largest, range.second - range.first);
  return largest;
}

double radialRange(const CylinderFit& axis, const std::vector<Vec3>& points) {
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const Vec3& p : points) {
    low = std::min(low, axisDistance(axis, p));
    high = std::max(high, axisDistance(axis, p));
  }
  return high - low;
}

// `points` moved by `twist`.
FacePoints moved(const FacePoints& points, const Twist& twist) {
  FacePoints result = points;
  for (auto& [face, list] : result)
    for (Vec3& p : list) p += displacement(twist, p);
  return result;
}

// The least-squares motion that brings the points of `features` onto them as designed:
// what a best fit does before a profile without datums is judged.
Twist bestFit(const std::vector<Feature>& features, const Nominal& nominal,
              const FacePoints& points) {
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  Twist pull = Twist::Zero();
  for (const Feature& f : features)
    for (int face : f.faces)
      if (const auto found = points.find(face); found != points.end())
        for (const Vec3& p : found->second) {
          const auto [normal_at, distance] = nominal.nearest(face, p);
          const auto row = alongNormal(p, normal_at);
          normal += row.transpose() * row;
          pull -= row.transpose() * distance;
        }
  normal += 1e-12 * (normal.trace() + 1) * Eigen::Matrix<double, 6, 6>::Identity();
  return normal.ldlt().solve(pull);
}

// Twice the largest distance of the features' points from their faces as designed.
double profileZone(const std::vector<Feature>& features, const Nominal& nominal,
                   const FacePoints& points) {
  double largest = 0;
  for (const Feature& f : features)
    for (int face : f.faces)
      if (const auto found = points.find(face); found != points.end())
        for (const Vec3& p : found->second)
          largest = std::max(largest, std::abs(nominal.nearest(face, p).second));
  return 2 * largest;
}

// Where a feature lies for a distance: a plane's measured centroid, a cylinder's axis.
struct Located {
  Vec3 point = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ();  // a plane's normal, a cylinder's axis
  bool plane = false;
};
std::optional<Located> locate(const Feature& f, const std::vector<Vec3>& points) {
  if (f.type == SurfaceType::Plane) {
    if (points.size() < kLeastPoints) return std::nullopt;
    const PlaneFit fit = fitPlane(points, f.plane.normal);
    if (!fit.determined) return std::nullopt;
    return Located{fit.point, fit.normal, true};
  }
  if (const auto c = cylinderOf(f, points)) return Located{c->point, c->axis, false};
  return std::nullopt;
}

double distanceBetween(const Located& a, const Located& b) {
  const Vec3 d = b.point - a.point;
  if (a.plane) return std::abs(a.direction.dot(d));
  if (b.plane) return std::abs(b.direction.dot(d));
  return perpendicular(d, a.direction);
}

Evaluation notFound(const std::string& why) { return {std::nullopt, why}; }

// A dimension between two features: their distance, or the angle between them.
Evaluation dimensionBetween(const Characteristic& c, const std::vector<Feature>& features,
                            const FacePoints& points) {
  if (features.size() != 2) return notFound("its faces are not two features");
  const auto a = locate(features[0], pointsOn(features[0].faces, points));
  const auto b = locate(features[1], pointsOn(features[1].faces, points));
  if (!a || !b) return notFound("a feature is not measured enough to fit");
  if (c.kind.find("angular") != std::string::npos)
    return {degrees(std::acos(std::clamp(std::abs(a->direction.dot(b->direction)), 0.0, 1.0))), {}};
  return {distanceBetween(*a, *b), {}};
}

// The datum axis of a characteristic's frame, as designed: its first cylindrical datum.
std::optional<CylinderFit> datumAxis(const Characteristic& c, const Gdt& gdt,
                                     const Nominal& nominal) {
  for (const std::string& reference : c.datums)
    for (const Feature& f : featuresOf(datumFaces(gdt, reference), nominal))
      if (f.type == SurfaceType::Cylinder) return f.cylinder;
  return std::nullopt;
}

// A section's share of turning its normals must hold in each direction across the axis
// for its centre to be found: the smaller eigenvalue of the mean n nᵀ, about 0.18 for a
// 90° arc (kLeastArc), 0.5 all round.
constexpr double kLeastTurn = 0.15;

// The straightness of a cylinder's axis (its derived median line): each cross-section's
// centre, as the shift across the axis that best explains its points' radial distances at
// the fitted radius; the diameter of the smallest circle holding the centres' offsets.
Evaluation axisStraightness(const CylinderFit& cylinder, const std::vector<Vec3>& points) {
  struct Section {
    Eigen::Matrix2d turn = Eigen::Matrix2d::Zero();
    Eigen::Vector2d pull = Eigen::Vector2d::Zero();
    std::size_t count = 0;
  };
  const Vec3 e1 = cylinder.axis.unitOrthogonal(), e2 = cylinder.axis.cross(e1);
  std::map<long, Section> sections;
  for (const Vec3& p : points) {
    const Vec3 d = p - cylinder.point;
    const Eigen::Vector2d radial(d.dot(e1), d.dot(e2));
    if (radial.norm() <= 0) continue;
    Section& s = sections[std::lround(d.dot(cylinder.axis) / kSlice)];
    const Eigen::Vector2d n = radial.normalized();
    s.turn += n * n.transpose();
    s.pull += n * (radial.norm() - cylinder.radius);
    ++s.count;
  }
  std::vector<double> along;
  std::vector<Eigen::Vector2d> centres;
  for (const auto& [k, s] : sections) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(s.turn);
    if (s.count < kLeastPoints / 2 ||
        eigen.eigenvalues()[0] < kLeastTurn * static_cast<double>(s.count))
      continue;
    along.push_back(static_cast<double>(k) * kSlice);
    centres.push_back(s.turn.ldlt().solve(s.pull));
  }
  if (centres.size() < 2) return notFound("fewer than two of its sections are measured all round");
  // Offsets from the centres' own least-squares line, so that what the fitted axis leaves
  // of a turn does not count.
  Eigen::MatrixXd a(static_cast<Eigen::Index>(centres.size()), 2);
  Eigen::MatrixXd b(static_cast<Eigen::Index>(centres.size()), 2);
  for (std::size_t i = 0; i < centres.size(); ++i) {
    a.row(static_cast<Eigen::Index>(i)) << 1, along[i];
    b.row(static_cast<Eigen::Index>(i)) = centres[i].transpose();
  }
  const Eigen::MatrixXd line = a.colPivHouseholderQr().solve(b);
  const Eigen::MatrixXd offsets = b - a * line;
  for (std::size_t i = 0; i < centres.size(); ++i)
    centres[i] = offsets.row(static_cast<Eigen::Index>(i)).transpose();
  return {enclosingCircleDiameter(centres), {}};
}

// The straightness of a plane's line elements, along the direction its designed points
// spread farthest: strips kSlice wide across it, the largest minimum zone of a strip.
Evaluation lineStraightness(const Feature& f, const Nominal& nominal,
                            const std::vector<Vec3>& points) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int face : f.faces)
    for (const Vec3& q : nominal.face(face)->points)
      scatter += (q - f.plane.point) * (q - f.plane.point).transpose();
  const Vec3 along = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(2);
  const Vec3 strip = f.plane.normal.cross(along);
  std::map<long, std::vector<Vec3>> strips;
  for (const Vec3& p : points)
    strips[std::lround((p - f.plane.point).dot(strip) / kSlice)].push_back(p);
  double largest = -1;
  for (const auto& [k, list] : strips)
    if (list.size() >= kLeastPoints / 2)
      largest = std::max(largest, minimumZoneStraightness(list, along, f.plane.normal));
  if (largest < 0) return notFound("no line element of it is measured");
  return {largest, {}};
}

// Twice the farther of an axis' two ends from `about`: the diameter of the zone about it
// that holds the axis.
double axisZone(const std::pair<Vec3, Vec3>& ends, const CylinderFit& about) {
  return 2 * std::max(perpendicular(ends.first - about.point, about.axis),
                      perpendicular(ends.second - about.point, about.axis));
}

// A form tolerance of one feature: flatness, straightness, circularity, cylindricity.
std::optional<Evaluation> formValue(const std::string& kind, const Feature& f,
                                    const Nominal& nominal, const std::vector<Vec3>& on,
                                    const std::optional<CylinderFit>& cylinder) {
  if (kind == "flatness") {
    if (f.type != SurfaceType::Plane) return notFound("flatness of a face that is not a plane");
    return Evaluation{minimumZoneFlatness(on, f.plane.normal), {}};
  }
  if (kind == "straightness") {
    if (f.type == SurfaceType::Plane) return lineStraightness(f, nominal, on);
    if (!cylinder) return notFound("its axis is not measured enough to fit");
    return axisStraightness(*cylinder, on);
  }
  if (kind == "circularity" || kind == "cylindricity") {
    if (!cylinder) return notFound("its cylinder is not measured enough to fit");
    return Evaluation{
        kind == "circularity" ? largestSectionRange(*cylinder, on) : radialRange(*cylinder, on),
        {}};
  }
  return std::nullopt;
}

// An orientation, location or runout tolerance of one feature, on points in its frame.
Evaluation locationValue(const Characteristic& c, const Gdt& gdt, const Nominal& nominal,
                         const Feature& f, const std::vector<Vec3>& on,
                         const std::optional<CylinderFit>& cylinder) {
  const std::string& kind = c.kind;
  const bool orientation = orientationKind(kind);
  if ((orientation || kind == "position") && f.type == SurfaceType::Plane) {
    // The zone of planes at the designed orientation; for a position, about the designed place.
    double low = std::numeric_limits<double>::infinity(), high = -low, largest = 0;
    for (const Vec3& p : on) {
      low = std::min(low, f.plane.normal.dot(p));
      high = std::max(high, f.plane.normal.dot(p));
      largest = std::max(largest, std::abs(f.plane.normal.dot(p - f.plane.point)));
    }
    return {orientation ? high - low : 2 * largest, {}};
  }
  if (orientation || kind == "position") {
    if (!cylinder) return notFound("its axis is not measured enough to fit");
    const auto ends = axisEnds(*cylinder, on);
    if (orientation)  // a cylinder's zone about the designed axis' direction
      return {perpendicular(ends.second - ends.first, f.cylinder.axis), {}};
    return {axisZone(ends, f.cylinder), {}};
  }
  if (kind.find("runout") != std::string::npos || kind == "concentricity" || kind == "coaxiality") {
    const auto axis = datumAxis(c, gdt, nominal);
    if (!axis) return notFound("no cylindrical datum gives its axis");
    if (kind == "circular_runout") return {largestSectionRange(*axis, on), {}};
    if (kind == "total_runout") return {radialRange(*axis, on), {}};
    if (!cylinder) return notFound("its axis is not measured enough to fit");
    return {axisZone(axisEnds(*cylinder, on), *axis), {}};
  }
  return notFound(kind + " is not evaluated");
}

// A geometric tolerance's value on points already in its datums' frame; of a pattern of
// features, the largest of theirs.
Evaluation toleranceValue(const Characteristic& c, const Gdt& gdt, const Nominal& nominal,
                          const std::vector<Feature>& features, const FacePoints& points) {
  const std::vector<Vec3> on = pointsOn(c.faces, points);
  if (on.size() < kLeastPoints) return notFound("too few points on its faces");
  if (c.kind == "profile_of_surface" || c.kind == "profile_of_line")
    return {
        profileZone(features, nominal,
                    c.datums.empty() ? moved(points, bestFit(features, nominal, points)) : points),
        {}};
  if (features.size() > 1) {  // a pattern (2X, say): each feature within the zone
    double largest = 0;
    for (const Feature& g : features) {
      Characteristic one = c;
      one.faces = g.faces;
      const Evaluation e = toleranceValue(one, gdt, nominal, {g}, points);
      if (!e.value) return e;
      largest = std::max(largest, *e.value);
    }
    return {largest, {}};
  }
  const Feature& f = features.front();
  const auto cylinder = cylinderOf(f, on, !orientationKind(c.kind));
  if (const auto form = formValue(c.kind, f, nominal, on, cylinder)) return *form;
  return locationValue(c, gdt, nominal, f, on, cylinder);
}

}  // namespace

struct Nominal::Trees {
  std::map<int, std::unique_ptr<PointCloudAdaptor>> clouds;
  std::map<int, std::unique_ptr<PointTree>> trees;
  std::map<int, FaceTriangles> facets;
};

Nominal::Nominal(const Part& part, std::span<const SurfacePoint> points)
    : trees_(std::make_unique<Trees>()) {
  for (const SurfacePoint& p : points) {
    if (p.face < 1 || p.face > static_cast<int>(part.faces.size())) continue;
    if (faces_.count(p.face) == 0) {
      faces_[p.face].type = part.faces[p.face - 1].type;
      const auto surface = elementarySurface(part, p.face);
      if (surface && surface->type != SurfaceType::Plane)
        exact_[p.face] = {*surface,
                          nearestOn(*surface, p.position).second.dot(p.normal) < 0 ? -1.0 : 1.0};
      if (surface && surface->type == SurfaceType::Sphere) faces_[p.face].sphere = *surface;
    }
    NominalFace& f = faces_[p.face];
    const SurfacePoint on = onDesigned(p.face, p.position, p.normal);
    f.points.push_back(on.position);
    f.normals.push_back(on.normal);
  }
  for (auto& [id, f] : faces_) {
    Vec3 mean_normal = Vec3::Zero();
    for (const Vec3& n : f.normals) mean_normal += n;
    const PlaneFit plane = fitPlane(f.points, mean_normal);
    f.centroid = plane.point;
    f.normal = plane.normal;
    for (const Vec3& p : f.points) f.rim = std::max(f.rim, perpendicular(p - f.centroid, f.normal));
    if (f.type == SurfaceType::Cylinder) f.cylinder = cylinderFromNormals(f.points, f.normals);
    if (part.face(id).triangle_count > 0) trees_->facets.try_emplace(id, part, id);
    auto& cloud = trees_->clouds[id] =
        std::make_unique<PointCloudAdaptor>(PointCloudAdaptor{f.points});
    auto& tree = trees_->trees[id] =
        std::make_unique<PointTree>(3, *cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree->buildIndex();
  }
}

Nominal::~Nominal() = default;

const NominalFace* Nominal::face(int id) const {
  const auto found = faces_.find(id);
  return found == faces_.end() ? nullptr : &found->second;
}

std::optional<SurfacePoint> Nominal::onTriangles(int id, const Vec3& p) const {
  const auto found = trees_->facets.find(id);
  if (found == trees_->facets.end()) return std::nullopt;
  const auto on = found->second.nearest(p);
  if (!on) return std::nullopt;
  return SurfacePoint{on->position, on->normal, id};
}

bool Nominal::withinBounds(int id, const Vec3& p, double distance) const {
  const auto found = trees_->facets.find(id);
  return found == trees_->facets.end() || found->second.within(p, distance);
}

SurfacePoint Nominal::closest(int id, const Vec3& p) const {
  if (const auto on = onExact(id, p)) return *on;
  if (const auto on = onTriangles(id, p)) return *on;
  const NominalFace& f = faces_.at(id);
  unsigned index = 0;
  double squared = 0;
  trees_->trees.at(id)->knnSearch(p.data(), 1, &index, &squared);
  return {f.points[index], f.normals[index], id};
}

std::pair<Vec3, double> Nominal::nearest(int id, const Vec3& p) const {
  const SurfacePoint on = closest(id, p);
  return {on.normal, on.normal.dot(p - on.position)};
}

std::optional<SurfacePoint> Nominal::onExact(int id, const Vec3& p) const {
  const auto exact = exact_.find(id);
  if (exact == exact_.end()) return std::nullopt;
  const auto [q, out] = nearestOn(exact->second.surface, p);
  return SurfacePoint{q, exact->second.side * out, id};
}

std::optional<std::pair<ElementarySurface, double>> Nominal::exactSurface(int id) const {
  const auto exact = exact_.find(id);
  if (exact == exact_.end()) return std::nullopt;
  return std::pair{exact->second.surface, exact->second.side};
}

double Nominal::curvature(int id, const Vec3& p) const {
  const auto exact = exact_.find(id);
  return exact == exact_.end() ? 0 : exact->second.side * curvatureSum(exact->second.surface, p);
}

SurfacePoint Nominal::onDesigned(int id, const Vec3& p, const Vec3& n) const {
  return onExact(id, p).value_or(SurfacePoint{p, n, id});
}

namespace {

// The least-squares normal equations of a datum alignment.
struct Constraints {
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  Twist pull = Twist::Zero();
  void add(const Eigen::Matrix<double, 1, 6>& row, double residual, double weight) {
    normal += weight * row.transpose() * row;
    pull -= weight * row.transpose() * residual;
  }
};

// Constrains the alignment by datum `letter` at `weight`: a plane by its points' distances
// from the designed plane, a cylinder by its fitted axis' ends off the designed axis. Why
// not, when it cannot.
std::string constrain(const std::string& letter, double weight, const Gdt& gdt,
                      const Nominal& nominal, const FacePoints& points, Constraints& into) {
  const std::vector<int> faces = datumFaces(gdt, letter);
  const std::vector<Feature> features = featuresOf(faces, nominal);
  if (features.empty()) return "datum " + letter + " is linked to no face";
  const Feature& f = features.front();
  const std::vector<Vec3> on = pointsOn(faces, points);
  const std::string unfit = "datum " + letter + " is not measured enough to fit";
  if (f.type == SurfaceType::Plane) {
    if (on.size() < kLeastPoints) return unfit;
    for (const Vec3& p : on)
      into.add(alongNormal(p, f.plane.normal), f.plane.normal.dot(p - f.plane.point),
               weight / static_cast<double>(on.size()));
    return {};
  }
  const auto cylinder = cylinderOf(f, on);
  if (!cylinder) return unfit;
  const CylinderFit& designed = f.cylinder;
  const Vec3 e1 = designed.axis.unitOrthogonal(), e2 = designed.axis.cross(e1);
  const auto [a, b] = axisEnds(*cylinder, on);
  for (const Vec3& end : {a, b})
    for (const Vec3& e : {e1, e2})
      into.add(alongNormal(end, e), e.dot(end - designed.point), weight);
  return {};
}

}  // namespace

Alignment datumAlignment(const std::vector<std::string>& datums, const Gdt& gdt,
                         const Nominal& nominal, const FacePoints& points) {
  Constraints constraints;
  double weight = 1;
  for (const std::string& reference : datums) {
    // A common datum's features together, each at a share of the reference's weight.
    const std::vector<std::string> letters = datumLetters(reference);
    for (const std::string& letter : letters)
      if (const std::string why = constrain(letter, weight / static_cast<double>(letters.size()),
                                            gdt, nominal, points, constraints);
          !why.empty())
        return {std::nullopt, why};
    weight /= kDatumPrecedence;
  }
  return {Twist(heldInverse(constraints.normal) * constraints.pull), {}};
}

namespace {

// A radius on a torus (a fillet's): its designed minor radius changed by the uniform offset
// along the face's normals that, with a small rigid motion, best explains the points'
// distances from it (least squares); the ring's radius held as designed. None where the
// points leave the offset loose: no better known than a cylinder's radius from a 90° arc
// (kLeastArc) of its circle, as the evaluation fits cylinders.
std::optional<double> tubeRadius(const Feature& f, const Nominal& nominal,
                                 const FacePoints& points) {
  using Row = Eigen::Matrix<double, 7, 1>;
  Eigen::Matrix<double, 7, 7> normal = Eigen::Matrix<double, 7, 7>::Zero();
  Row pull = Row::Zero();
  std::optional<std::pair<ElementarySurface, double>> torus;
  double count = 0;
  for (int id : f.faces) {
    torus = nominal.exactSurface(id);
    const auto on = points.find(id);
    if (!torus || torus->first.type != SurfaceType::Torus || on == points.end()) continue;
    for (const Vec3& p : on->second) {
      const auto [n, d] = nominal.nearest(id, p);
      Row row;
      row << torus->second, n, p.cross(n);
      normal += row * row.transpose();
      pull += row * d;
      ++count;
    }
  }
  if (!torus || count < kLeastPoints) return std::nullopt;
  normal += 1e-9 * (normal.trace() + 1) * Eigen::Matrix<double, 7, 7>::Identity();
  // The most the offset's variance may be, in variances of the points' mean: a cylinder's
  // radius from a 90° arc, 1/(1 - c²/m), c = sin 45° / (π/4) and m = 1/2 + 1/π the means of
  // cos and cos² over the arc (about 105).
  const double c = std::sin(std::numbers::pi / 4) / (std::numbers::pi / 4),
               loosest = 1 / (1 - c * c / (0.5 + 1 / std::numbers::pi));
  const Eigen::LDLT<Eigen::Matrix<double, 7, 7>> solved(normal);
  const Row unit = Row::Unit(0);
  if (count * solved.solve(unit)[0] > loosest) return std::nullopt;
  return torus->first.minor_radius + solved.solve(pull)[0];
}

// A diameter's or a radius' value: its cylinder's (a spherical one's, its sphere's), fitted
// to its points; of a pattern of them (6X, say), each fitted to its own, the one farthest
// from the nominal value, as each must lie within the limits.
Evaluation sizeValue(const Characteristic& c, const std::vector<Feature>& features,
                     const Nominal& nominal, const FacePoints& points) {
  const bool spherical = c.kind.starts_with("spherical");
  const double times = c.kind.ends_with("diameter") ? 2 : 1;
  std::optional<double> farthest;
  for (const Feature& f : features) {
    const bool tube = c.kind == "radius" && f.type == SurfaceType::Torus;
    if (!tube && f.type != (spherical ? SurfaceType::Sphere : SurfaceType::Cylinder))
      return notFound("a " + c.kind + " of faces that are not " +
                      (spherical ? "spheres" : "cylinders or tori") + " is not evaluated");
    const std::vector<Vec3> on = pointsOn(f.faces, points);
    std::optional<double> radius;
    if (tube) {
      radius = tubeRadius(f, nominal, points);
    } else if (spherical) {
      const SphereFit sphere = on.size() >= kLeastPoints ? fitSphere(on) : SphereFit{};
      if (sphere.determined) radius = sphere.radius;
    } else if (const auto cylinder = cylinderOf(f, on)) {
      radius = cylinder->radius;
    }
    if (!radius)
      return notFound(std::string(features.size() == 1 ? "its " : "a ") +
                      (spherical ? "sphere"
                       : tube    ? "torus"
                                 : "cylinder") +
                      (features.size() == 1 ? "" : " of its pattern") +
                      " is not measured enough to fit");
    const double size = times * *radius;
    if (!farthest || std::abs(size - c.value) > std::abs(*farthest - c.value)) farthest = size;
  }
  return {farthest, {}};
}

}  // namespace

bool orientationKind(const std::string& kind) {
  return kind == "perpendicularity" || kind == "parallelism" || kind == "angularity";
}

Evaluation evaluate(const Characteristic& c, const Gdt& gdt, const Nominal& nominal,
                    const FacePoints& points) {
  if (c.faces.empty()) return notFound("linked to no face");
  const std::vector<Feature> features = featuresOf(c.faces, nominal);
  if (features.empty()) return notFound("its faces are not known");
  if (c.dimension) {
    if (c.kind == "diameter" || c.kind == "radius" || c.kind == "spherical_diameter" ||
        c.kind == "spherical_radius")
      return sizeValue(c, features, nominal, points);
    return dimensionBetween(c, features, points);
  }
  if (c.datums.empty()) return toleranceValue(c, gdt, nominal, features, points);
  const Alignment alignment = datumAlignment(c.datums, gdt, nominal, points);
  if (!alignment.motion) return notFound(alignment.why_not);
  return toleranceValue(c, gdt, nominal, features, moved(points, *alignment.motion));
}

}  // namespace scanplan::detail
