// The virtual inspection (docs/capability.md, "Virtual inspection"). Each run simulates
// every registered view's cloud at the inspection's spacing, its noise that of the mean of
// the scanner's points each simulated point stands for; puts on it the scanner's
// acceptance errors drawn for that view (a bow over the field within the flatness error, a
// scale within the sphere-spacing error over the volume's diagonal, an offset along the
// surface within half the probing error of size); moves it where a run of its
// registration puts it (simulated_registration.h); and applies the declared deviations.
// Each characteristic is evaluated from the points of one frame, the one holding most of
// its faces' and datums' points, as the evaluation defines it; the part's own value comes
// from the same evaluation on the deviated surface, sampled densely, without error.

#include "planning/evaluation.h"
#include "planning/simulated_icp.h"
#include "planning/simulated_registration.h"

#include <scanplan/core/errors.h>
#include <scanplan/planning/capability.h>
#include <scanplan/planning/inspection.h>
#include <scanplan/planning/planner.h>
#include <scanplan/planning/verify.h>
#include <scanplan/scanner/simulation.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <tuple>

namespace scanplan {
namespace {

using detail::FacePoints;

// Samples of the faces as designed, mm apart.
constexpr double kNominalSpacing = 1;

// Every face the characteristics and their datums name.
std::set<int> facesOf(const Part& part, const std::vector<Characteristic>& list) {
  std::set<int> faces;
  for (const Characteristic& c : list) {
    faces.insert(c.faces.begin(), c.faces.end());
    for (const std::string& reference : c.datums)
      for (int f : datumFaces(part.gdt, reference)) faces.insert(f);
  }
  return faces;
}

// The deviations, checked against the part's faces.
void checkDeviations(const Part& part, const std::vector<Deviation>& deviations) {
  for (std::size_t k = 0; k < deviations.size(); ++k) {
    const Deviation& d = deviations[k];
    const std::string where = "deviation " + std::to_string(k + 1);
    for (int f : d.faces) {
      if (f < 1 || f > static_cast<int>(part.faces.size()))
        throw InputError(part.file, where + ": the part has no face " + std::to_string(f));
      if (d.kind == Deviation::Kind::Diameter && part.faces[f - 1].type != SurfaceType::Cylinder)
        throw InputError(part.file, where + ": face " + std::to_string(f) + " is not a cylinder");
    }
  }
}

// A point of face `face` (part frame, outward normal `n`) where the deviations put it.
Vec3 deviated(const std::vector<Deviation>& deviations, const detail::Nominal& nominal, int face,
              const Vec3& p, const Vec3& n) {
  Vec3 q = p;
  for (const Deviation& d : deviations) {
    if (std::find(d.faces.begin(), d.faces.end(), face) == d.faces.end()) continue;
    const detail::NominalFace* f = nominal.face(face);
    switch (d.kind) {
      case Deviation::Kind::Offset: q += d.amount * n; break;
      case Deviation::Kind::Move: q += d.move; break;
      case Deviation::Kind::Bow: {
        if (!f || f->rim <= 0) break;
        const Vec3 across = (p - f->centroid) - (p - f->centroid).dot(f->normal) * f->normal;
        const double r = across.norm() / f->rim;
        q += d.amount * (1 - r * r) * n;
        break;
      }
      case Deviation::Kind::Diameter: {
        if (!f) break;
        const Vec3 from = p - f->cylinder.point;
        const Vec3 radial = from - from.dot(f->cylinder.axis) * f->cylinder.axis;
        q += d.amount / 2 * radial.normalized();
        break;
      }
    }
  }
  return q;
}

// The surface as designed (part frame), densely, on `faces`.
std::vector<SurfacePoint> designedPoints(const Part& part, const ResolvedSpec& spec,
                                         const std::set<int>& faces) {
  const Simulator simulator(part, spec.spec.scanner,
                            simulationOptionsFor(spec, part, Pose::Identity()));
  std::vector<SurfacePoint> points;
  for (const SurfacePoint& p : simulator.surfacePoints(kNominalSpacing, 1))
    if (faces.count(p.face)) points.push_back(p);
  return points;
}

// The part simulated: the designed surface of `faces` where the deviations put it.
FacePoints simulatedPart(const detail::Nominal& nominal, const std::set<int>& faces,
                         const std::vector<Deviation>& deviations) {
  FacePoints truth;
  for (const int id : faces)
    if (const detail::NominalFace* f = nominal.face(id))
      for (std::size_t k = 0; k < f->points.size(); ++k)
        truth[id].push_back(deviated(deviations, nominal, id, f->points[k], f->normals[k]));
  return truth;
}

// The scanner's acceptance errors drawn for one view: applied to a world point with its
// normal.
struct AcceptanceErrors {
  double bow = 0, scale = 0, offset = 0;
  Vec3 apply(const Scanner& s, const View& view, const Vec3& p, const Vec3& n) const {
    const Vec3 local = view.camera_to_world.inverse() * p;
    const double at = local.z() / s.standoff;  // the field grows with the depth
    const double u = 2 * local.x() / (s.fov_width * at), v = 2 * local.y() / (s.fov_height * at);
    const Vec3 ray = view.camera_to_world.linear().col(2);
    Vec3 q = p + bow * (u * u + v * v) / 2 * ray;
    q = view.target + (1 + scale) * (q - view.target);
    return q + offset * n;
  }
};
AcceptanceErrors drawAcceptance(const Scanner& s, std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(-1, 1);
  const double diagonal = std::hypot(s.fov_width, s.fov_height, s.depth_of_field);
  return {s.flatness_error * unit(random), s.sphere_spacing / diagonal * unit(random),
          s.probing_size / 2 * unit(random)};
}

// One run's points: per frame, by face (part frame).
using RunPoints = std::map<std::size_t, FacePoints>;

// A view's cloud as every run of the inspection simulates it before drawing its noise
// (viewRays).
struct ViewRays {
  CloudRays rays;                      // its noise's source; its cloud left empty
  std::vector<SurfacePoint> designed;  // the points kept, world
  std::vector<Vec3> hits;              // where their rays met the mesh, world
  std::vector<std::size_t> kept;       // each one's index in the cloud
};

// The clouds the views are simulated as: one simulator per orientation of the plan, each
// simulated point the mean of the scanner's points around it, `spacing` apart, its noise
// so much less.
struct Clouds {
  std::vector<Simulator> simulators;
  double spacing = 0;
};
Clouds averagedClouds(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                      double spacing) {
  Scanner averaged = plan.scanner;
  averaged.noise_sigma *= std::min(1.0, plan.scanner.point_spacing / spacing);
  Clouds clouds{{}, spacing};
  for (std::size_t k = 0; k < std::max<std::size_t>(1, plan.orientations.size()); ++k)
    clouds.simulators.emplace_back(part, averaged,
                                   simulationOptionsFor(spec, part, orientationPlacement(plan, k)));
  return clouds;
}

struct Setup {
  const Part& part;
  const ResolvedSpec& spec;
  const Plan& plan;
  const InspectionOptions& options;
  const detail::Nominal& nominal;
  const std::set<int>& faces;
  const std::vector<detail::ViewError>& errors;
  const Clouds& clouds;
  // The clouds an ICP link is registered again on, kDenser times denser (none without ICP
  // links registered).
  const Clouds& dense;
  std::vector<std::size_t> orientation;  // per view
  double tolerance;                      // registration.tolerance, mm
  // Per view, the view it registers to by ICP in each run (none: its link is drawn).
  std::vector<std::optional<std::size_t>> icp;
  const detail::SimulatedIcp* registering = nullptr;
  // Per view placed, its rays at the clouds' spacing, simulated once for every run
  // (allViewRays).
  std::vector<ViewRays> rays = {};
};

// One view's points in a run before its registration moves them (world): on the part as
// designed, with the scanner's noise and the view's acceptance errors; of every face when
// it takes part in an ICP link, else of the characteristics' faces.
using ViewPoints = std::vector<SurfacePoint>;

// Where view v's camera rays meet the part in every run, at `clouds`' spacing (world): the
// points kept (of every face, or of the characteristics'), each on the part as designed
// instead of the mesh; and what each run's noise is drawn from.
ViewRays viewRays(const Setup& s, const Clouds& clouds, std::size_t v, bool every_face) {
  const std::size_t k = s.orientation[v];
  const Pose to_world = orientationPlacement(s.plan, k), to_part = to_world.inverse();
  ViewRays made{clouds.simulators[k].rays(s.plan.views[v], clouds.spacing), {}, {}, {}};
  const PointCloud& cloud = made.rays.cloud;
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const int face = cloud.faces[i];
    if (!every_face && !s.faces.count(face)) continue;
    const SurfacePoint on =
        s.nominal.onDesigned(face, to_part * cloud.hits[i], to_part.linear() * cloud.normals[i]);
    made.designed.push_back({to_world * on.position, to_world.linear() * on.normal, face});
    made.hits.push_back(cloud.hits[i]);
    made.kept.push_back(i);
  }
  made.rays.cloud = {};  // what runs need is kept apart
  return made;
}

// View v's points in run `run`: its designed points with the noise along each ray, and
// the view's acceptance errors.
ViewPoints measuredPoints(const Setup& s, const ViewRays& rays, std::size_t v,
                          const AcceptanceErrors& acceptance, int run) {
  const View& view = s.plan.views[v];
  const std::uint64_t seed = s.options.seed * 7919 + static_cast<std::uint64_t>(run) * 104729 +
                             static_cast<std::uint64_t>(view.id);
  const std::vector<Vec3> noise = noiseOf(rays.rays, seed);
  ViewPoints mine;
  mine.reserve(rays.designed.size());
  for (std::size_t j = 0; j < rays.designed.size(); ++j) {
    // The noise as the cloud carries it: the noisy point less its ray's hit.
    const Vec3& hit = rays.hits[j];
    const SurfacePoint& on = rays.designed[j];
    const Vec3 at = on.position + ((hit + noise[rays.kept[j]]) - hit);
    mine.push_back({acceptance.apply(s.plan.scanner, view, at, on.normal), on.normal, on.face});
  }
  return mine;
}

// ICP from this many starts at most, as the cell's operator registers again a view that
// does not fit; the starts after the first on clouds kDenser times denser. At the
// inspection's spacing a narrow face that alone holds a link may get a point or two, which
// can take a neighbouring face as their nearest and hold ICP off where they balance
// (docs/capability.md, "A run").
constexpr std::uint64_t kStarts = 3;
constexpr double kDenser = 4;

// The RMS displacement `motion` gives `points`.
double rmsMove(const Pose& motion, const std::vector<SurfacePoint>& points) {
  double squares = 0;
  for (const SurfacePoint& p : points) squares += (motion * p.position - p.position).squaredNorm();
  return std::sqrt(squares / static_cast<double>(std::max<std::size_t>(1, points.size())));
}

// What ICP moves for the link of view v to view p: the points of v's cloud `mine`, one of
// `clouds`, that p measures too (part frame, `spacing` apart), and the surface p measured.
struct IcpOverlap {
  std::vector<SurfacePoint> points;
  double spacing = 0;
  detail::FixedSurface surface;
};
IcpOverlap icpOverlap(const Setup& s, std::size_t v, std::size_t p, const ViewPoints& mine,
                      const Clouds& clouds, const AcceptanceErrors& fixed_errors) {
  const View& fixed = s.plan.views[p];
  const Simulator& simulator = clouds.simulators[s.orientation[v]];
  const Pose to_world = orientationPlacement(s.plan, s.orientation[v]),
             to_part = to_world.inverse();
  IcpOverlap overlap;
  overlap.spacing = clouds.spacing;
  const std::vector<Loss> seen = simulator.measure(fixed, mine);
  for (std::size_t i = 0; i < mine.size(); ++i)
    if (seen[i] == Loss::Measured)
      overlap.points.push_back(
          {to_part * mine[i].position, to_part.linear() * mine[i].normal, mine[i].face});
  const Scanner& scanner = simulator.scanner();
  const View& moved = s.plan.views[v];
  overlap.surface = [&scanner, &fixed, &moved, &fixed_errors, to_world](const Vec3& at,
                                                                        const Vec3& normal) {
    const Vec3 a = to_world * at, m = to_world.linear() * normal;
    detail::SurfaceOffset offset = detail::fixedPoints(scanner, fixed, moved, a, m);
    offset.shift = m.dot(fixed_errors.apply(scanner, fixed, a, m) - a);
    return offset;
  };
  return overlap;
}

// The ICP links of one run (world motions; none for views whose link is drawn), each
// registered again from another start while it lands further than the registration's
// tolerance from where it belongs; the restarts and the links left so counted in
// `counts`.
std::vector<std::optional<Pose>> icpLinks(const Setup& s, const std::vector<ViewPoints>& measured,
                                          const std::vector<AcceptanceErrors>& acceptance, int run,
                                          Inspection& counts) {
  const std::size_t n = s.plan.views.size();
  std::vector<std::optional<Pose>> links(n);
  std::atomic<std::size_t> restarted = 0, failed = 0;
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    if (!s.icp[v]) return;
    const std::size_t p = *s.icp[v], k = s.orientation[v];
    const Pose to_world = orientationPlacement(s.plan, k), to_part = to_world.inverse();
    IcpOverlap overlap = icpOverlap(s, v, p, measured[v], s.clouds, acceptance[p]);
    for (std::uint64_t start = 0; start < kStarts; ++start) {
      if (start == 1)
        overlap = icpOverlap(
            s, v, p, measuredPoints(s, viewRays(s, s.dense, v, true), v, acceptance[v], run),
            s.dense, acceptance[p]);
      const std::uint64_t seed = s.options.seed * 6151 + static_cast<std::uint64_t>(run) * 65537 +
                                 static_cast<std::uint64_t>(s.plan.views[v].id) * 7 + start;
      const std::optional<Pose> link =
          s.registering->link(overlap.points, overlap.surface, overlap.spacing, seed);
      if (!link) break;  // too little overlap to run ICP on: its covariance is drawn
      links[v] = to_world * *link * to_part;
      if (rmsMove(*link, overlap.points) <= s.tolerance) break;
      ++(start + 1 < kStarts ? restarted : failed);
    }
  });
  counts.icp_restarted += restarted;
  counts.icp_failed += failed;
  return links;
}

// Every placed view's rays at the clouds' spacing (viewRays): of every face for the views
// in an ICP link, whose overlap ICP registers, else of the characteristics' faces.
std::vector<ViewRays> allViewRays(const Setup& s) {
  std::vector<char> in_icp(s.plan.views.size(), 0);
  for (std::size_t v = 0; v < s.icp.size(); ++v)
    if (s.icp[v]) in_icp[v] = in_icp[*s.icp[v]] = 1;
  std::vector<ViewRays> rays(s.plan.views.size());
  tbb::parallel_for(std::size_t{0}, s.plan.views.size(), [&](std::size_t v) {
    if (s.errors[v].placed) rays[v] = viewRays(s, s.clouds, v, in_icp[v]);
  });
  return rays;
}

RunPoints simulateRun(const Setup& s, const detail::SimulatedRegistration& registration, int run,
                      Inspection& counts) {
  std::mt19937_64 random(s.options.seed * 1000003 + static_cast<std::uint64_t>(run));
  std::mt19937_64 registration_random = random;
  std::vector<Pose> moves = registration.draw(random);
  std::vector<AcceptanceErrors> acceptance;
  for (std::size_t v = 0; v < s.plan.views.size(); ++v)
    acceptance.push_back(drawAcceptance(s.plan.scanner, random));
  std::vector<ViewPoints> measured(s.plan.views.size());
  tbb::parallel_for(std::size_t{0}, s.plan.views.size(), [&](std::size_t v) {
    if (s.errors[v].placed) measured[v] = measuredPoints(s, s.rays[v], v, acceptance[v], run);
  });
  if (s.registering)
    moves = registration.draw(registration_random, icpLinks(s, measured, acceptance, run, counts));
  std::vector<FacePoints> by_view(s.plan.views.size());
  tbb::parallel_for(std::size_t{0}, s.plan.views.size(), [&](std::size_t v) {
    const Pose to_part = orientationPlacement(s.plan, s.orientation[v]).inverse();
    for (const SurfacePoint& m : measured[v]) {
      const int face = m.face;
      if (!s.faces.count(face)) continue;
      const Vec3 in_part = to_part * (moves[v] * m.position),
                 normal = to_part.linear() * moves[v].linear() * m.normal;
      by_view[v][face].push_back(deviated(s.options.deviations, s.nominal, face, in_part, normal));
    }
  });
  // Merged in the views' order, whatever order the threads ran them in.
  RunPoints points;
  for (std::size_t v = 0; v < by_view.size(); ++v) {
    if (!s.errors[v].placed) continue;
    FacePoints& frame = points[s.errors[v].frame];
    for (auto& [face, list] : by_view[v])
      frame[face].insert(frame[face].end(), list.begin(), list.end());
  }
  return points;
}

// The frame holding most of the characteristic's faces' and datums' points.
const FacePoints& frameFor(const Characteristic& c, const Part& part, const RunPoints& run) {
  static const FacePoints none;
  const std::set<int> faces = facesOf(part, {c});
  const FacePoints* best = &none;
  std::size_t most = 0;
  for (const auto& [frame, by_face] : run) {
    std::size_t count = 0;
    for (int f : faces)
      if (const auto found = by_face.find(f); found != by_face.end()) count += found->second.size();
    if (count > most) best = &by_face, most = count;
  }
  return *best;
}

// Whether some face of the characteristic or its datums has points in other frames of the
// run but none in `frame`.
bool inOtherFramesOnly(const Characteristic& c, const Part& part, const RunPoints& run,
                       const FacePoints& frame) {
  for (int f : facesOf(part, {c})) {
    if (frame.count(f)) continue;
    for (const auto& [other, by_face] : run)
      if (&by_face != &frame && by_face.count(f)) return true;
  }
  return false;
}

// Per view, the view it registers to by ICP, where the inspection registers that link by
// ICP in each run: both placed, in one setup.
std::vector<std::optional<std::size_t>> icpParents(const Plan& plan,
                                                   const std::vector<detail::ViewError>& errors,
                                                   const InspectionOptions& options) {
  std::vector<std::optional<std::size_t>> parents(plan.views.size());
  if (options.icp != InspectionOptions::IcpLinks::Registered || !plan.registration ||
      plan.registration->views.size() != plan.views.size())
    return parents;
  const std::vector<std::size_t> orientation = viewOrientations(plan);
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    const std::optional<std::size_t>& to = errors[v].parent;
    if (plan.registration->views[v].method == RegistrationMethod::Icp && errors[v].placed && to &&
        errors[*to].placed && orientation[*to] == orientation[v])
      parents[v] = to;
  }
  return parents;
}

// The mean of `values` and U, twice their standard deviation (k = 2).
std::pair<double, double> meanAndU(std::span<const double> values) {
  const double n = static_cast<double>(values.size());
  if (n < 1) return {0, 0};
  double mean = 0, squares = 0;
  for (double x : values) mean += x / n;
  for (double x : values) squares += (x - mean) * (x - mean);
  return {mean, n > 1 ? 2 * std::sqrt(squares / (n - 1)) : 0};
}

// The error that 95 % of `values` stay under, from `true_value`: the smallest that at least
// 95 % of them do.
double error95(const std::vector<double>& values, double true_value) {
  if (values.empty()) return 0;
  std::vector<double> errors;
  for (double x : values) errors.push_back(std::abs(x - true_value));
  const auto at = errors.begin() + static_cast<std::ptrdiff_t>(
                                       std::ceil(0.95 * static_cast<double>(errors.size())) - 1);
  std::nth_element(errors.begin(), at, errors.end());
  return *at;
}

// Mean, bias, U, their precision and verdict from the runs' values; `seed` the
// resamples' (spreadPrecision).
void judge(const Characteristic& c, const CapabilityOptions& capability, std::uint64_t seed,
           InspectedCharacteristic& k) {
  std::tie(k.mean, k.uncertainty) = meanAndU(k.values);
  k.bias = k.mean - k.true_value;
  const double spread = k.uncertainty + std::abs(k.bias);
  k.precision = spreadPrecision(k.values, k.true_value, seed);
  k.error_95 = error95(k.values, k.true_value);
  k.ratio = c.width() > 0 && spread > 0 ? c.width() / (2 * spread) : 0;
  k.verdict = !(c.width() > 0)                       ? Verdict::Untoleranced
              : k.ratio >= capability.capable_ratio  ? Verdict::Capable
              : k.ratio >= capability.marginal_ratio ? Verdict::Marginal
                                                     : Verdict::NotCapable;
}

// The resamples' seed of characteristic `id` (judge).
std::uint64_t resampleSeed(const InspectionOptions& options, int id) {
  return options.seed * 2654435761u + static_cast<std::uint64_t>(id);
}

// Whether a `precision` on U + |bias| = `spread` is within `share` of it.
bool knownWithin(double precision, double spread, double share) {
  return precision <= share * spread;
}

// Whether every characteristic still evaluated has its U + |bias| within `share` of
// itself at 95 % after the runs so far.
bool precise(const std::vector<InspectedCharacteristic>& inspected,
             const InspectionOptions& options) {
  return std::all_of(inspected.begin(), inspected.end(), [&](const InspectedCharacteristic& k) {
    return !k.evaluated || knownWithin(spreadPrecision(k.values, k.true_value,
                                                       resampleSeed(options, k.characteristic)),
                                       spreadOf(k.values, k.true_value), options.precision);
  });
}

// Per characteristic, its value on the simulated part, or why it has none.
std::vector<InspectedCharacteristic> trueValues(const Setup& s, const FacePoints& truth) {
  std::vector<InspectedCharacteristic> list;
  for (const Characteristic& c : s.plan.characteristics) {
    InspectedCharacteristic k;
    k.characteristic = c.id;
    const detail::Evaluation value = detail::evaluate(c, s.part.gdt, s.nominal, truth);
    k.evaluated = value.value.has_value();
    if (value.value) k.true_value = *value.value;
    k.not_evaluated = value.why_not;
    list.push_back(k);
  }
  return list;
}

// Each characteristic still evaluated, from run `run`'s points.
void evaluateRun(const Setup& s, const RunPoints& points, int run,
                 std::vector<InspectedCharacteristic>& inspected) {
  const std::vector<Characteristic>& list = s.plan.characteristics;
  for (std::size_t i = 0; i < list.size(); ++i) {
    InspectedCharacteristic& k = inspected[i];
    if (!k.evaluated) continue;
    const FacePoints& frame = frameFor(list[i], s.part, points);
    for (int f : list[i].faces)
      if (const auto found = frame.find(f); found != frame.end())
        k.points += static_cast<double>(found->second.size());  // per run at the end
    const detail::Evaluation value = detail::evaluate(list[i], s.part.gdt, s.nominal, frame);
    if (!value.value) {
      k.evaluated = false;
      k.not_evaluated = "in run " + std::to_string(run + 1) + ", " + value.why_not +
                        (inOtherFramesOnly(list[i], s.part, points, frame)
                             ? " (faces of it are measured only in setups not joined to this one)"
                             : "");
      continue;
    }
    k.values.push_back(*value.value);
  }
}

// The runs of the inspection, all of `options.runs` or, with a precision, until it is
// reached; then each characteristic judged.
void runAll(const Setup& s, const detail::SimulatedRegistration& registration,
            const Progress& progress, Inspection& result) {
  const InspectionOptions& options = s.options;
  result.precision_asked = options.precision;
  const std::string most = (options.precision > 0 ? " of at most " : " of ");
  for (int run = 0; run < options.runs; ++run) {
    report(progress,
           "inspecting: run " + std::to_string(run + 1) + most + std::to_string(options.runs),
           static_cast<double>(run) / options.runs);
    evaluateRun(s, simulateRun(s, registration, run, result), run, result.characteristics);
    result.runs = run + 1;
    if (options.precision > 0 && result.runs >= kLeastRuns && result.runs % kPrecisionBatch == 0 &&
        precise(result.characteristics, options))
      break;
  }
  report(progress, "inspecting", 1);
  for (std::size_t i = 0; i < s.plan.characteristics.size(); ++i) {
    InspectedCharacteristic& k = result.characteristics[i];
    k.points /= result.runs;
    if (!k.evaluated) continue;
    judge(s.plan.characteristics[i], s.spec.spec.planner.capability,
          resampleSeed(options, k.characteristic), k);
    if (options.precision > 0 &&
        !knownWithin(k.precision, k.uncertainty + std::abs(k.bias), options.precision))
      result.imprecise.push_back(k.characteristic);
  }
}

}  // namespace

Inspection inspectPlan(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                       const InspectionOptions& options, const Progress& progress) {
  if (options.runs < 2 || options.runs > 10000)
    throw InputError(plan.part_file, "inspection runs must be within [2, 10000]");
  if (!(options.precision >= 0 && options.precision < 1))
    throw InputError(plan.part_file, "inspection precision must be within [0, 1)");
  if (!(options.spacing >= 0) || options.spacing > plan.scanner.fov_height)
    throw InputError(plan.part_file, "inspection spacing must be within [0, fov_height]");
  checkPlanPart(plan, part);
  checkDeviations(part, options.deviations);
  Inspection result;
  result.runs = options.runs;
  result.spacing = options.spacing > 0
                       ? options.spacing
                       : evaluationSpacing(plan.scanner, spec.spec.planner.capability);
  result.deviations = options.deviations;
  const std::set<int> faces = facesOf(part, plan.characteristics);
  const std::vector<detail::ViewError> errors = detail::registrationErrors(part, spec, plan);
  for (const detail::ViewError& e : errors) result.views_left_out += !e.placed;
  const std::vector<std::optional<std::size_t>> icp = icpParents(plan, errors, options);
  result.icp_registered = static_cast<std::size_t>(
      std::count_if(icp.begin(), icp.end(), [](const auto& p) { return p.has_value(); }));
  // ICP meets every face, as designed.
  std::set<int> designed_faces = faces;
  if (result.icp_registered > 0)
    for (int f = 1; f <= static_cast<int>(part.faces.size()); ++f) designed_faces.insert(f);
  const detail::Nominal nominal(part, designedPoints(part, spec, designed_faces));
  const RegistrationOptions registration_options = registrationOptions(spec.spec);
  const detail::SimulatedRegistration registration(plan, errors,
                                                   markerSigma(registration_options, plan.scanner));
  const Clouds clouds = averagedClouds(part, spec, plan, result.spacing);
  const Clouds dense =
      result.icp_registered > 0
          ? averagedClouds(part, spec, plan,
                           std::max(plan.scanner.point_spacing, result.spacing / kDenser))
          : Clouds{};
  const detail::SimulatedIcp registering(nominal, registration_options, part.linear_deflection);
  Setup setup{part,
              spec,
              plan,
              options,
              nominal,
              faces,
              errors,
              clouds,
              dense,
              viewOrientations(plan),
              registration_options.tolerance,
              icp,
              result.icp_registered > 0 ? &registering : nullptr};

  setup.rays = allViewRays(setup);
  result.characteristics = trueValues(setup, simulatedPart(nominal, faces, options.deviations));
  runAll(setup, registration, progress, result);
  return result;
}

double spreadOf(std::span<const double> values, double true_value) {
  const auto [mean, u] = meanAndU(values);
  return u + std::abs(mean - true_value);
}

double spreadPrecision(std::span<const double> values, double true_value, std::uint64_t seed) {
  if (values.size() < 2) return 0;
  std::mt19937_64 random(seed);
  std::uniform_int_distribution<std::size_t> pick(0, values.size() - 1);
  std::vector<double> resample(values.size());
  double sum = 0, squares = 0;
  for (int b = 0; b < kResamples; ++b) {
    for (double& x : resample) x = values[pick(random)];
    const double spread = spreadOf(resample, true_value);
    sum += spread;
    squares += spread * spread;
  }
  const double mean = sum / kResamples;
  return 2 * std::sqrt(std::max(0.0, squares / kResamples - mean * mean));
}

}  // namespace scanplan
