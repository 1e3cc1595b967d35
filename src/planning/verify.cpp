// Checking a plan again: coverage, registration and sequence.

#include "cad/face_triangles.h"

#include <scanplan/cad/elementary.h>
#include <scanplan/core/errors.h>
#include <scanplan/planning/bridging.h>
#include <scanplan/planning/verify.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace scanplan {

namespace {

// How the plan's cell turns its markers: each view at the table angle the plan takes it at;
// none without a table or without markers on the working plane.
std::shared_ptr<const TableTurn> planTable(const Plan& plan, const std::vector<Marker>& markers) {
  if (!plan.cell || !plan.cell->table) return nullptr;
  std::map<int, double> angles;
  for (std::size_t v = 0; v < plan.views.size() && v < plan.cell_poses.size(); ++v)
    if (plan.cell_poses[v]) angles[plan.views[v].id] = plan.cell_poses[v]->table_angle;
  return tableTurnFor(plan.cell->table->origin, plan.cell->table->axis, markers,
                      [angles](const View& view) {
                        const auto it = angles.find(view.id);
                        return it == angles.end() ? 0.0 : it->second;
                      });
}

// The registration options a plan is checked with: the spec's, without bridging, with the
// plan's method (and robot accuracy) when the spec names none, and the plan's `required`.
// A plan with the markers it proposed placed registers by them (registerByPlacedMarkers).
RegistrationOptions checkOptions(const Spec& spec, const Plan& plan) {
  const Registration& planned = *plan.registration;
  RegistrationOptions registration = registrationOptions(spec);
  if (!spec.placed_markers.empty()) registerByPlacedMarkers(registration);
  registration.bridging = false;
  registration.required = planned.required;
  registration.aligned_as_taken = planned.aligned_as_taken;
  if (registration.method == RegistrationMode::Default) {
    registration.method = planned.method;
    if (registration.method == RegistrationMode::Robot)
      registration.robot_accuracy = planned.robot_accuracy;
  }
  return registration;
}

// Whether the link the file claims for view `id` is one the check finds: a view registered
// by markers or ICP to view `claimed.to` must form a pair with it that shares markers
// registering both, or a stable overlap that ICP, if it was verified, did not fail; one
// registered by reference points must see them as the check simulates it.
bool linkHolds(const Registration& found, int id, const ViewRegistration& claimed,
               const ViewRegistration& again) {
  if (claimed.method == RegistrationMethod::ReferencePoints)
    return again.method == RegistrationMethod::ReferencePoints;
  if (claimed.method != RegistrationMethod::Markers && claimed.method != RegistrationMethod::Icp)
    return true;
  const PairCheck* pair = found.pair(id, claimed.to);
  return pair && pair->registrable();
}

// Per pair of the `count` views (indices; `index` by view id), whether the file's
// registration claims the pair links and the check, which verifies by ICP only the pairs
// its own tree needs, left it unverified with a registrable overlap: a link ICP can confirm.
std::vector<std::vector<char>> confirmableLinks(std::size_t count, const std::map<int, int>& index,
                                                const Registration& claimed,
                                                const Registration& found) {
  std::set<std::pair<int, int>> claims;
  for (const PairCheck& p : claimed.pairs)
    if (claimed.links(p)) claims.insert({p.a, p.b});
  std::vector<std::vector<char>> result(count, std::vector<char>(count, 0));
  for (const PairCheck& p : found.pairs) {
    const auto a = index.find(p.a), b = index.find(p.b);
    if (!p.registrable() || p.icp || !claims.count({p.a, p.b}) || a == index.end() ||
        b == index.end())
      continue;
    result[a->second][b->second] = result[b->second][a->second] = 1;
  }
  return result;
}

// The sequence as the file gives it, into `check`: every view once, each registered view
// after one it registers to, and its motion cost. A view follows one it registers to by a
// link of the check's registration, or by one the file's claims and the check confirms.
// The plan has a registration (verifyPlacement checks none without).
void checkSequence(const Simulator& simulator, const Plan& plan, const std::vector<View>& views,
                   const RegistrationOptions& options, PlanCheck& check) {
  Plan& again = check.plan;
  std::map<int, int> index, seen;
  for (std::size_t v = 0; v < views.size(); ++v) index[views[v].id] = static_cast<int>(v);
  std::vector<int> order;
  if (plan.sequence)
    for (int id : plan.sequence->views)
      if (index.count(id) && seen[id]++ == 0) order.push_back(index[id]);
  check.sequence_missing = views.size() - order.size() +
                           (plan.sequence ? plan.sequence->views.size() - order.size() : 0);
  const std::vector<std::vector<char>> links = registrationLinks(views, *again.registration);
  const std::vector<std::vector<char>> confirmable =
      confirmableLinks(views.size(), index, *plan.registration, *again.registration);
  std::map<int, IcpCloud> clouds;  // by view index, each made once
  auto cloud = [&](int v) -> const IcpCloud& {
    auto found = clouds.find(v);
    if (found == clouds.end())
      found = clouds.emplace(v, icpCloud(simulator, views[v], options)).first;
    return found->second;
  };
  // ICP on the pair, the earlier view's cloud fixed, as the registration runs it.
  auto icpPasses = [&](int a, int b) {
    return checkIcp(simulator, cloud(std::min(a, b)), cloud(std::max(a, b)), options).passed;
  };
  for (std::size_t k = 1; k < order.size(); ++k) {
    if (again.registration->views[order[k]].method == RegistrationMethod::None) continue;
    const int v = order[k];
    bool follows = false;
    for (std::size_t j = 0; j < k && !follows; ++j) follows = links[v][order[j]];
    for (std::size_t j = 0; j < k && !follows; ++j)
      follows = confirmable[v][order[j]] && icpPasses(v, order[j]);
    check.sequence_breaks += !follows;
  }
  const Eigen::MatrixXd cost = shortestPaths(directCosts(simulator, views));
  again.sequence.emplace();
  for (int k : order) again.sequence->views.push_back(views[k].id);
  again.sequence->length = pathLength(cost, order);
  again.sequence->nearest_neighbour_length =
      pathLength(cost, nearestNeighbourOrder(cost, links, order.empty() ? 0 : order.front()));
}

// verifyPlan of a plan with one placement.
PlanCheck verifyPlacement(const Plan& plan, const Part& part, const ResolvedSpec& resolved,
                          const PlanningOptions& options, const Progress& progress) {
  const Spec& spec = resolved.spec;
  PlanCheck check;
  Plan& again = check.plan;
  again = plan;
  again.fixture_faces = resolved.fixtureFaces();
  const std::vector<Marker> spec_markers = specMarkers(resolved, part, plan.part_to_world);
  const Simulator simulator(part, plan.scanner,
                            simulationOptionsFor(resolved, plan.part_to_world, spec_markers));

  report(progress, "simulating " + std::to_string(plan.views.size()) + " views", 0);
  const std::vector<SurfacePoint> points = plan.samplePoints();
  const auto losses = simulator.measure(plan.views, points);
  for (std::size_t i = 0; i < plan.samples.size(); ++i) {
    std::vector<int>& by = again.samples[i].measured_by;
    by.clear();
    for (std::size_t v = 0; v < plan.views.size(); ++v)
      if (losses[v][i] == Loss::Measured) by.push_back(plan.views[v].id);
    std::vector<int> claimed = plan.samples[i].measured_by;
    std::sort(claimed.begin(), claimed.end());
    if (by != claimed) ++check.coverage_differences;
  }

  if (!options.registration || !plan.registration) return check;
  std::vector<View> views = plan.views;
  RegistrationOptions registration = checkOptions(spec, plan);
  if (!spec.markers_file.empty() || spec.marker_grid > 0 || !spec.fixtures.empty())
    again.markers = spec_markers;
  registration.table = planTable(plan, again.markers);
  again.registration =
      registerWithBridging(simulator, views, again.markers, registration, CellCheck{}, progress);
  std::size_t bridges = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    // What the file says of the view (nothing: not registered).
    const ViewRegistration claimed = plan.registration && v < plan.registration->views.size()
                                         ? plan.registration->views[v]
                                         : ViewRegistration{};
    ViewRegistration& found = again.registration->views[v];
    found.bridge = claimed.bridge;
    bridges += claimed.bridge;
    const bool state_differs =
        (claimed.method == RegistrationMethod::None) != (found.method == RegistrationMethod::None);
    check.registration_differences +=
        state_differs || !linkHolds(*again.registration, views[v].id, claimed, found);
  }
  again.registration->bridging_views = bridges;
  check.unregistered = views.size() - again.registration->registered();
  check.registration_required = again.registration->required;

  checkSequence(simulator, plan, views, registration, check);
  return check;
}

// How far a sample of the plan may lie from its face on the part planned (checkPlanPart):
// from an elementary surface, a little more than the edges of a STEP file lie off their
// faces (up to 0.0009 mm on the NIST models); from the mesh, which cuts inside curved
// faces by about its chordal tolerance, as many times that as leaves room past the most
// seen (1.8 on NIST FTC 06's spheres), and a floor: a mesh part's samples lie on its
// triangles, to rounding.
constexpr double kExactSlack = 0.01;  // mm
constexpr double kMeshSlack = 4;      // times the chordal tolerance
constexpr double kMeshFloor = 0.001;  // mm

// A face of the part as a sample is checked against: its triangles, and its surface where
// that is elementary.
struct FaceGeometry {
  FaceGeometry(const Part& part, int id)
      : exact(elementarySurface(part, id)), triangles(part, id) {}
  std::optional<ElementarySurface> exact;
  detail::FaceTriangles triangles;
};

}  // namespace

PartFit partFit(const Plan& plan, const Part& part) {
  PartFit fit;
  fit.samples = plan.samples.size();
  fit.exact_tolerance = kExactSlack;
  fit.mesh_tolerance = kMeshSlack * part.linear_deflection + kMeshFloor;
  const Pose to_part = plan.part_to_world.inverse();
  std::map<int, FaceGeometry> faces;
  for (const PlannedSample& s : plan.samples) {
    const int id = s.sample.face;
    if (id < 1 || id > static_cast<int>(part.faces.size())) {
      ++fit.off;
      continue;
    }
    const FaceGeometry& face = faces.try_emplace(id, part, id).first->second;
    const Vec3 p = to_part * s.sample.position;
    const auto on = face.triangles.nearest(p);
    if (!on) continue;  // a face its mesh left out: nothing to measure from
    const double mesh = (p - on->position).norm();
    const double exact = face.exact ? (p - nearestOn(*face.exact, p).first).norm() : 0;
    fit.off += mesh > fit.mesh_tolerance || exact > fit.exact_tolerance;
    fit.mesh_farthest = std::max(fit.mesh_farthest, mesh);
    fit.exact_farthest = std::max(fit.exact_farthest, exact);
  }
  return fit;
}

PartFit checkPlanPart(const Plan& plan, const Part& part) {
  if (plan.part_faces != part.faces.size())
    throw InputError(part.file, "has " + std::to_string(part.faces.size()) +
                                    " faces where the plan's part has " +
                                    std::to_string(plan.part_faces));
  const PartFit fit = partFit(plan, part);
  if (fit.off == 0) return fit;
  throw InputError(part.file,
                   fmt::format("{} of the plan's {} samples lie off their faces on it (farther "
                               "than {:g} mm from their surfaces or {:.3f} mm from their "
                               "triangles): not the part the plan was made for; plan it again, "
                               "or simulate the plan's views on it",
                               fit.off, fit.samples, fit.exact_tolerance, fit.mesh_tolerance));
}

PlanCheck verifyPlan(const Plan& plan, const Part& part, const Spec& spec,
                     const PlanningOptions& options, const Progress& progress) {
  const PartFit fit = checkPlanPart(plan, part);
  // The spec's markers, and those the plan placed where it proposed them (--place-markers),
  // which hide the surface under them as they did in the plan.
  Spec with_placed = spec;
  std::copy_if(plan.markers.begin(), plan.markers.end(),
               std::back_inserter(with_placed.placed_markers),
               [](const Marker& m) { return m.placed; });
  const ResolvedSpec resolved = resolveSpec(part, with_placed);
  if (plan.orientations.empty()) {
    PlanCheck check = verifyPlacement(plan, part, resolved, options, progress);
    check.part = fit;
    return check;
  }

  // Each orientation on its own, then the results merged.
  PlanCheck check;
  check.part = fit;
  check.plan = plan;
  Plan& again = check.plan;
  for (PlannedSample& s : again.samples) s.measured_by.clear();
  const bool registration = options.registration && plan.registration;
  if (registration) {
    again.registration = Registration{};
    again.sequence = Sequence{};
  }
  for (std::size_t k = 0; k < again.orientations.size(); ++k) {
    PlannedOrientation& o = again.orientations[k];
    // Each setup with the view ids it was planned with: they seed its clouds and ICP.
    const int offset = setupIdOffset(plan, k);
    PlanCheck part_check =
        verifyPlacement(setupPlan(plan, k, offset), part, resolved, options, progress);
    check.coverage_differences += part_check.coverage_differences;
    check.registration_differences += part_check.registration_differences;
    check.sequence_missing += part_check.sequence_missing;
    check.sequence_breaks += part_check.sequence_breaks;
    check.unregistered += part_check.unregistered;
    check.registration_required |= part_check.registration_required;
    if (registration) {
      o.markers = part_check.plan.markers;
      o.reference = part_check.plan.registration->reference;
      if (o.reference > 0) o.reference += offset;
    } else {  // the plan's own, not checked again
      part_check.plan.registration.reset();
      part_check.plan.sequence.reset();
    }
    appendOrientation(again, part_check.plan, offset);
  }
  for (PlannedSample& s : again.samples) std::sort(s.measured_by.begin(), s.measured_by.end());
  return check;
}

}  // namespace scanplan
