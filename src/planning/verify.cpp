// Checking a plan again: coverage, registration and sequence.

#include <scanplan/errors.h>
#include <scanplan/planning.h>

#include <algorithm>
#include <map>

namespace scanplan {

PlanCheck verifyPlan(const Plan& plan, const Part& part, const Spec& spec,
                     const PlanningOptions& options, const Progress& progress) {
  if (plan.part_faces != part.faces.size())
    throw InputError(part.file, "has " + std::to_string(part.faces.size()) +
                                    " faces where the plan's part has " +
                                    std::to_string(plan.part_faces));
  PlanCheck check;
  Plan& again = check.plan;
  again = plan;
  again.fixture_faces = resolveFaces(part, spec.fixture, spec.source).size();
  const Simulator simulator(part, plan.scanner,
                            simulationOptionsFor(part, spec, plan.part_to_world));

  report(progress, "simulating " + std::to_string(plan.views.size()) + " views", 0);
  std::vector<SurfacePoint> points;
  for (const PlannedSample& s : plan.samples)
    points.push_back({s.sample.position, s.sample.normal, s.sample.face});
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

  if (!options.registration) return check;
  std::vector<View> views = plan.views;
  RegistrationOptions registration = spec.registration;
  registration.bridging = false;
  registration.seed = options.seed;
  if (!spec.markers_file.empty() || spec.marker_grid > 0)
    again.markers = specMarkers(spec, part, plan.part_to_world);
  again.registration =
      registerViews(simulator, views, again.markers, registration, options, progress);
  std::size_t bridges = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    // What the file says of the view (nothing: not registered).
    const ViewRegistration claimed = plan.registration && v < plan.registration->views.size()
                                         ? plan.registration->views[v]
                                         : ViewRegistration{};
    ViewRegistration& found = again.registration->views[v];
    found.bridge = claimed.bridge;
    bridges += claimed.bridge;
    check.registration_differences +=
        (claimed.method == RegistrationMethod::None) != (found.method == RegistrationMethod::None);
  }
  again.registration->bridging_views = bridges;

  // The sequence as the file gives it: every view once, each registered view after one it
  // registers to, and its motion cost.
  std::map<int, int> index, seen;
  for (std::size_t v = 0; v < views.size(); ++v) index[views[v].id] = static_cast<int>(v);
  std::vector<int> order;
  if (plan.sequence)
    for (int id : plan.sequence->views)
      if (index.count(id) && seen[id]++ == 0) order.push_back(index[id]);
  check.sequence_missing = views.size() - order.size() +
                           (plan.sequence ? plan.sequence->views.size() - order.size() : 0);
  const std::vector<std::vector<char>> links = registrationLinks(views, *again.registration);
  for (std::size_t k = 1; k < order.size(); ++k) {
    if (again.registration->views[order[k]].method == RegistrationMethod::None) continue;
    bool follows = false;
    for (std::size_t j = 0; j < k && !follows; ++j) follows = links[order[k]][order[j]];
    check.sequence_breaks += !follows;
  }
  const Eigen::MatrixXd cost = shortestPaths(directCosts(simulator, views));
  again.sequence.emplace();
  for (int k : order) again.sequence->views.push_back(views[k].id);
  again.sequence->length = pathLength(cost, order);
  again.sequence->nearest_neighbour_length =
      pathLength(cost, nearestNeighbourOrder(cost, links, order.empty() ? 0 : order.front()));
  return check;
}

}  // namespace scanplan
