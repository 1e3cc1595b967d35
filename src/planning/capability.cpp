// Measurement capability per characteristic (docs/capability.md). The characteristics'
// faces are sampled once; each sample stands for its area, and each view that measures it
// puts there as many points as its pixel grid lays on that area, each with the noise of
// the simulation at its distance and incidence. The ideal geometry is fitted to the points
// by least squares (linearised: an offset along the normals, a shift and a small turn),
// and the noise's effect on the fitted geometry is drawn by Monte Carlo:
// - form, orientation and runout: the peak-to-valley of the fitted geometry's
//   displacement over the faces;
// - profile and position: twice its largest displacement (zones about the nominal);
// - diameter and radius: the fitted offset (twice for a diameter); a distance between
//   faces: the faces' own offsets together; an angle between faces: the peak-to-valley
//   over the faces' extent, in degrees.
// U is the error that 95% of the draws stay under.

#include "core/kd_tree.h"

#include <scanplan/cad/localization.h>
#include <scanplan/planning/capability.h>
#include <scanplan/planning/planner.h>
#include <scanplan/scanner/simulation.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>

namespace scanplan {
namespace {

constexpr double kMinPoints = 25;       // fewer points cannot fit a feature soundly
constexpr double kCoveredEnough = 0.9;  // share of the area a capable characteristic has covered
constexpr double kMostlyUncovered = 0.5;

// What a view measures at a sample: the noise of its points and how many there are.
struct Look {
  double sigma = 0, points = 0;
};

// A sample of a characteristic's faces (part frame) and the views' looks at it.
struct Patch {
  SurfacePoint point;
  double area = 0;
  std::vector<Look> looks;
  double points() const {
    double n = 0;
    for (const Look& l : looks) n += l.points;
    return n;
  }
  // The noise of the points' mean (inverse-variance weighted), for least-squares fits.
  double meanSigma() const {
    double weight = 0;
    for (const Look& l : looks) weight += l.points / (l.sigma * l.sigma);
    return 1 / std::sqrt(weight);
  }
};

// How the noise shows in a characteristic's value; profile stands for every zone about
// the nominal (profile, position, symmetry, concentricity); an angle is in degrees.
enum class Effect { Form, Profile, Size, Diameter, Radius, Angle };

Effect effectOf(const Characteristic& c) {
  if (c.dimension)
    return c.kind == "diameter"                    ? Effect::Diameter
           : c.kind == "radius"                    ? Effect::Radius
           : c.kind.find("angular") != c.kind.npos ? Effect::Angle
                                                   : Effect::Size;
  if (c.kind == "profile_of_surface" || c.kind == "profile_of_line" || c.kind == "position" ||
      c.kind == "concentricity" || c.kind == "symmetry" || c.kind == "coaxiality")
    return Effect::Profile;
  return Effect::Form;
}

using Row = Eigen::Matrix<double, 7, 1>;
using Normal = Eigen::Matrix<double, 7, 7>;

// The least-squares fit of the ideal geometry to a characteristic's measured patches,
// linearised: an offset along the normals (a size), a shift and a small turn. Each
// patch's row maps the parameters to its displacement along its normal.
struct Fit {
  std::vector<Row> rows;
  std::vector<double> sigmas;  // of each patch's mean point
  Eigen::LDLT<Normal> normal;
  double extent = 0;  // the patches' largest distance apart (their box's diagonal), mm
};

Fit fitOf(const std::vector<const Patch*>& patches) {
  Vec3 centre = Vec3::Zero();
  for (const Patch* p : patches) centre += p->point.position / static_cast<double>(patches.size());
  Fit fit;
  Box box;
  for (const Patch* p : patches) box.add(p->point.position);
  fit.extent = std::max(box.diagonal(), 1e-9);
  Normal normal = Normal::Zero();
  for (const Patch* p : patches) {
    Row row;
    row << 1, p->point.normal, (p->point.position - centre).cross(p->point.normal);
    const double sigma = p->meanSigma();
    normal += row * row.transpose() / (sigma * sigma);
    fit.rows.push_back(row);
    fit.sigmas.push_back(sigma);
  }
  // Directions the faces leave free (along a plane, about a cylinder's axis) stay at 0.
  normal += 1e-9 * (normal.trace() + 1) * Normal::Identity();
  fit.normal.compute(normal);
  return fit;
}

// One draw of the noise's error on the characteristic's value: the fitted geometry's
// displacement from the true one, as the characteristic measures it.
double drawError(Effect effect, const std::vector<const Patch*>& patches, const Fit& fit,
                 std::mt19937_64& random) {
  std::normal_distribution<double> normal;
  std::vector<double> noise(patches.size());
  Row pull = Row::Zero();
  for (std::size_t i = 0; i < patches.size(); ++i) {
    noise[i] = fit.sigmas[i] * normal(random);
    pull += fit.rows[i] * noise[i] / (fit.sigmas[i] * fit.sigmas[i]);
  }
  const Row fitted = fit.normal.solve(pull);
  if (effect == Effect::Diameter) return 2 * std::abs(fitted[0]);
  if (effect == Effect::Radius) return std::abs(fitted[0]);
  if (effect == Effect::Size) {  // a distance between faces: each face's offset adds
    std::map<int, std::pair<double, double>> faces;  // weighted offset sum, weight
    for (std::size_t i = 0; i < patches.size(); ++i) {
      const double w = 1 / (fit.sigmas[i] * fit.sigmas[i]);
      faces[patches[i]->point.face].first += w * noise[i];
      faces[patches[i]->point.face].second += w;
    }
    double squares = 0;
    for (const auto& [face, f] : faces) squares += (f.first / f.second) * (f.first / f.second);
    return std::sqrt(squares);
  }
  double high = -std::numeric_limits<double>::infinity(), low = -high;
  for (const Row& row : fit.rows) {
    const double d = row.dot(fitted);
    high = std::max(high, d);
    low = std::min(low, d);
  }
  if (effect == Effect::Angle) return degrees(std::atan((high - low) / fit.extent));
  return effect == Effect::Form ? high - low : 2 * std::max(high, -low);
}

// U: the error 95% of the draws stay under.
double uncertainty(const Characteristic& c, const std::vector<const Patch*>& patches,
                   const CapabilityOptions& options, std::uint64_t seed) {
  const Fit fit = fitOf(patches);
  std::mt19937_64 random(seed + static_cast<std::uint64_t>(c.id));
  std::vector<double> errors;
  for (int k = 0; k < options.draws; ++k)
    errors.push_back(drawError(effectOf(c), patches, fit, random));
  const auto at =
      errors.begin() + static_cast<std::ptrdiff_t>(0.95 * static_cast<double>(errors.size() - 1));
  std::nth_element(errors.begin(), at, errors.end());
  return *at;
}

// The characteristics' faces, sampled once (part frame), each sample a patch.
std::vector<Patch> patchesOf(const Part& part, const std::vector<Characteristic>& list) {
  std::set<int> faces;
  for (const Characteristic& c : list) faces.insert(c.faces.begin(), c.faces.end());
  std::vector<Patch> patches;
  for (const Sample& s :
       sampleSurface(part, {faces.begin(), faces.end()}, Role::Priority, TaskType::Gdt))
    patches.push_back({{s.position, s.normal, s.face}, s.weight, {}});
  return patches;
}

// The looks of every view of `plan` at the patches, each view in its orientation's world.
void look(const Part& part, const ResolvedSpec& spec, const Plan& plan,
          std::vector<Patch>& patches) {
  const Scanner& scanner = plan.scanner;
  const std::vector<std::size_t> orientation = viewOrientations(plan);
  for (std::size_t k = 0; k < std::max<std::size_t>(1, plan.orientations.size()); ++k) {
    const Pose placed = orientationPlacement(plan, k);
    std::vector<View> views;
    for (std::size_t v = 0; v < plan.views.size(); ++v)
      if (orientation[v] == k) views.push_back(plan.views[v]);
    const Simulator simulator(part, scanner, simulationOptionsFor(spec, part, placed));
    std::vector<SurfacePoint> points;
    for (const Patch& p : patches)
      points.push_back({placed * p.point.position, placed.linear() * p.point.normal, p.point.face});
    const std::vector<std::vector<int>> measured = measuredPoints(simulator, views, points);
    for (std::size_t v = 0; v < views.size(); ++v)
      for (int i : measured[v]) {
        const PointQuality q =
            pointQuality(scanner, views[v], points[i].position, points[i].normal);
        patches[i].looks.push_back({q.sigma, patches[i].area * q.density});
      }
  }
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

// The rest orientation that turns up the most of the unmeasured area lying on the working
// plane, when that is most of the unmeasured area.
std::optional<std::size_t> restFor(const std::vector<const Patch*>& patches,
                                   const std::vector<RestOrientation>& rests, const Pose& placed) {
  auto onPlane = [](const Pose& pose, const Patch& p) {
    return (pose.linear() * p.point.normal).z() < -0.9 && (pose * p.point.position).z() < 1;
  };
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

void judge(const Characteristic& c, Capability& k, const CapabilityOptions& options) {
  k.ratio = k.uncertainty > 0 ? c.width() / (2 * k.uncertainty) : 0;
  const bool sparse = k.covered < kCoveredEnough || k.points < kMinPoints;
  if (!(c.width() > 0)) {
    k.verdict = Verdict::Untoleranced;
  } else if (k.covered < kMostlyUncovered) {
    k.verdict = Verdict::NotCapable;
    k.reason = Shortfall::Uncovered;
  } else if (k.ratio >= options.capable_ratio && !sparse) {
    k.verdict = Verdict::Capable;
  } else {
    k.verdict = k.ratio >= options.marginal_ratio ? Verdict::Marginal : Verdict::NotCapable;
    k.reason = sparse ? Shortfall::TooSparse : Shortfall::TooNoisy;
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

std::string_view toString(Shortfall reason) {
  switch (reason) {
    case Shortfall::None: return "none";
    case Shortfall::Uncovered: return "uncovered";
    case Shortfall::TooSparse: return "too_sparse";
    case Shortfall::TooNoisy: return "too_noisy";
  }
  return "?";
}

std::vector<Capability> capabilities(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                                     const std::vector<Characteristic>& characteristics) {
  if (characteristics.empty()) return {};
  const CapabilityOptions& options = spec.spec.planner.capability;
  std::vector<Patch> patches = patchesOf(part, characteristics);
  look(part, spec, plan, patches);
  const std::vector<RestOrientation> rests = restOrientations(part);
  std::vector<Capability> result;
  for (const Characteristic& c : characteristics) {
    std::vector<const Patch*> mine;
    for (const Patch& p : patches)
      if (std::binary_search(c.faces.begin(), c.faces.end(), p.point.face)) mine.push_back(&p);
    Capability k;
    k.characteristic = c.id;
    std::vector<const Patch*> measured;
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
    if (!measured.empty())
      k.uncertainty = uncertainty(c, measured, options, spec.spec.planner.seed);
    judge(c, k, options);
    if (k.covered < kCoveredEnough) k.rest = restFor(mine, rests, plan.part_to_world);
    result.push_back(k);
  }
  return result;
}

}  // namespace scanplan
