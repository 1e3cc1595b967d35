#include "summary.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <map>
#include <set>

namespace scanplan::cli {

namespace {

double percent(std::size_t some, std::size_t whole) {
  return whole ? 100.0 * static_cast<double>(some) / static_cast<double>(whole) : 0.0;
}

// Views registered, by which method, and those registered to nothing; the markers proposed.
void printRegistration(const Plan& plan, const Registration& r) {
  fmt::print("{:<22} {} ({:.1f}%), by {}\n", "views registered", r.registered(),
             percent(r.registered(), plan.views.size()), toString(r.method));
  std::string by;
  for (RegistrationMethod m : kRegistrationMethods)
    if (const auto n =
            std::count_if(r.views.begin(), r.views.end(), [&](auto& v) { return v.method == m; }))
      by += fmt::format("{}{} {}", by.empty() ? "" : ", ", toString(m), n);
  if (!by.empty()) fmt::print("{:<22} {}\n", "", by);
  if (const std::vector<SetupRegistration> setups = setupRegistration(plan); setups.size() > 1) {
    std::string within;
    std::set<std::size_t> frames;
    for (const SetupRegistration& setup : setups) {
      within +=
          fmt::format("{}{} of {}", within.empty() ? "" : ", ", setup.registered, setup.views);
      frames.insert(setup.frame);
    }
    const std::string joined = frames.size() == 1 ? "joined by markers on the part"
                               : frames.size() == setups.size()
                                   ? "not joined"
                                   : fmt::format("in {} frames", frames.size());
    fmt::print("{:<22} {} {}, registered within each: {}; {} of {} views in one frame\n", "setups",
               setups.size(), joined, within, registeredInOneFrame(setups), plan.views.size());
  }
  fmt::print("{:<22} {} ({:.1f}%)\n", "measured, registered", plan.registeredMeasuredCount(),
             percent(plan.registeredMeasuredCount(), plan.samples.size()));
  fmt::print("{:<22} {}\n", "bridging views added", r.bridging_views);
  if (r.registered() < plan.views.size()) {
    // The first kListed of them (plan.json lists them all), numbered as the report and
    // the robot programs number them: their place in the sequence, their id beside.
    constexpr std::size_t kListed = 40;
    std::map<int, std::size_t> place;
    if (plan.sequence)
      for (std::size_t k = 0; k < plan.sequence->views.size(); ++k)
        place[plan.sequence->views[k]] = k + 1;
    std::string ids;
    std::size_t unconstrained = 0, unregistrable = 0;
    for (std::size_t v = 0; v < plan.views.size() && v < r.views.size(); ++v)
      if (r.views[v].method == RegistrationMethod::None) {
        const int id = plan.views[v].id;
        if (unregistrable++ < kListed)
          ids += fmt::format("{}{}", ids.empty() ? "" : ", ",
                             place.count(id) ? fmt::format("{} (id {})", place[id], id)
                                             : fmt::format("id {}", id));
        unconstrained += !r.views[v].constrained;
      }
    if (unregistrable > kListed) ids += fmt::format(" and {} more", unregistrable - kListed);
    fmt::print("{:<22} {}\n", "unregistrable views", ids);
    if (unconstrained)
      fmt::print(
          "{:<22} {} of them see too little to register to (mostly a plane or a "
          "cylinder: condition number above the limit, and too few markers): add markers\n",
          "", unconstrained);
  }
  if (!plan.proposed_markers) return;
  const MarkerProposal& proposal = *plan.proposed_markers;
  if (!proposal.markers.empty())
    fmt::print("{:<22} {}, for {} of the views registered to nothing (at least {} needed)\n",
               "proposed markers", proposal.markers.size(), proposal.views, proposal.lower_bound);
  if (!proposal.unserved.empty())
    fmt::print(
        "{:<22} {} view(s), ids {}: no marker position tried serves them (each sees too few "
        "of the candidate positions on the part, the plate and the fixtures)\n",
        "no marker serves", proposal.unserved.size(), fmt::join(proposal.unserved, ", "));
}

// What a characteristic asks for, as the report gives it: a tolerance's zone, or a
// dimension's nominal value with its limits.
std::string specified(const Characteristic& c) {
  return c.dimension ? fmt::format("{:.3f} ({:.3f} to {:.3f})", c.value, c.lower, c.upper)
                     : fmt::format("zone {:.3f}", c.value);
}

// Per verdict how many characteristics, then each that is not capable with its reason
// and the rest orientation that would reach it.
void printCharacteristics(const Plan& plan) {
  if (plan.capabilities.empty()) return;
  std::map<std::string, std::size_t> verdicts;
  for (const Capability& k : plan.capabilities) ++verdicts[std::string(toString(k.verdict))];
  std::string counts;
  for (const auto& [verdict, n] : verdicts)
    counts += fmt::format("{}{} {}", counts.empty() ? "" : ", ", n, verdict);
  fmt::print("{:<22} {}: {}\n", "characteristics", plan.capabilities.size(), counts);
  for (std::size_t i = 0; i < plan.capabilities.size(); ++i) {
    const Capability& k = plan.capabilities[i];
    if (k.verdict == Verdict::Capable || k.verdict == Verdict::Untoleranced) continue;
    const Characteristic& c = plan.characteristics[i];
    fmt::print(
        "  {:>3} {:<22} {:<26} {:>5.1f}% covered, U {:.4f} (noise {:.4f}, registration "
        "{:.4f}, scanner {:.4f}), ratio {:.2f}: {} ({}){}{}{}\n",
        c.id, c.kind, specified(c), 100 * k.covered, k.uncertainty, k.budget.noise,
        k.budget.registration, k.budget.scanner, k.ratio, toString(k.verdict), toString(k.reason),
        k.limit == Limit::None ? "" : fmt::format("; beyond the views: {}", toString(k.limit)),
        k.inspected_uncertainty
            ? fmt::format("; inspected U {:.4f}, bias {:.4f} (U + |bias| ± {:.4f})",
                          *k.inspected_uncertainty, k.inspected_bias.value_or(0),
                          k.inspected_precision.value_or(0))
            : "",
        k.rest ? fmt::format("; rest orientation {} reaches it (part: {{rest: all}})", *k.rest + 1)
               : "");
  }
}

}  // namespace

void printPlanSummary(const Plan& plan, const Part& part) {
  fmt::print("{:<22} {}\n", "model faces", plan.part_faces);
  fmt::print("{:<22} {}\n", "fixture faces", plan.fixture_faces);
  fmt::print("{:<22} {}\n", "target samples", plan.samples.size());
  fmt::print("{:<22} {} ({:.1f}%)\n", "measured samples", plan.measuredCount(),
             percent(plan.measuredCount(), plan.samples.size()));
  if (!plan.face_areas.empty()) {
    double area = 0, measured = 0;
    for (const FaceArea& f : plan.face_areas) {
      area += f.area;
      measured += f.measured;
    }
    fmt::print("{:<22} {:.0f} of {:.0f} mm² of the part's surface ({:.1f}%)\n", "measured area",
               measured, area, area > 0 ? 100 * measured / area : 0.0);
  }
  for (const Plan::FaceShortfall& f : plan.priorityShortfall()) {
    const std::string& name = f.face >= 1 && f.face <= static_cast<int>(part.faces.size())
                                  ? part.faces[f.face - 1].name
                                  : std::string();
    fmt::print("{:<22} face {}{}: {} of {} priority samples measured\n", "priority face short",
               f.face, name.empty() ? "" : " (" + name + ")", f.measured, f.samples);
  }
  fmt::print("{:<22} {}\n", "views", plan.views.size());
  for (std::size_t k = 0; k < plan.orientations.size(); ++k) {
    const PlannedOrientation& o = plan.orientations[k];
    fmt::print("{:<22} {}: down ({:+.3f}, {:+.3f}, {:+.3f}), margin {:.3f}, {} views\n",
               k == 0 ? "rest orientations" : "", k + 1, o.rest.down.x(), o.rest.down.y(),
               o.rest.down.z(), o.rest.margin, o.views.size());
  }
  for (const Sweep& sweep : plan.sweeps) {
    std::string faces;
    for (int id : sweep.faces) faces += fmt::format("{}{}", faces.empty() ? "" : " ", id);
    fmt::print(
        "{:<22} {} views over {} tiles, {} face(s): {}{}\n", "sweep", sweep.views.size(),
        sweep.tiles, sweep.faces.size(), faces.size() > 40 ? faces.substr(0, 40) + "..." : faces,
        sweep.patch ? fmt::format(" (patch within {:.3f} mm)", sweep.patch->max_deviation) : "");
  }
  if (plan.registration) printRegistration(plan, *plan.registration);
  if (plan.sequence)
    fmt::print("{:<22} {:.0f} mm (nearest neighbour {:.0f} mm)\n", "path length",
               plan.sequence->length, plan.sequence->nearest_neighbour_length);
  printCharacteristics(plan);
  if (plan.cell_motion) {
    fmt::print("{:<22} {:.1f} s of joint travel (home, approaches, via points)\n", "robot motion",
               plan.cell_motion->seconds);
    for (const RobotMove& move : plan.cell_motion->uncleared)
      fmt::print("{:<22} {} collides and could not be cleared\n", "robot move", toString(move));
  }
  if (plan.cycle) {
    const CycleTime& c = *plan.cycle;
    fmt::print(
        "{:<22} {:.1f} s: acquisition {:.1f}, motion {:.1f}, table {:.1f}, settling and "
        "handshakes {:.1f} ({})\n",
        "cycle time", c.total(), c.acquisition, c.motion, c.table, c.other,
        c.model == "cell" ? "the robot program" : "generic positioning, no cell");
    if (c.turns > 0)
      fmt::print("{:<22} {:.1f} s: the part turned over by hand {} time{} (cycle.turn_over)\n", "",
                 c.turning, c.turns, c.turns == 1 ? "" : "s");
  }
}

void printResultsRow(const Plan& plan) {
  const Plan::ResultsRow row = plan.resultsRow();
  fmt::print("\n{:>11} {:>13} {:>15} {:>15} {:>8} {:>15}\n", "model faces", "fixture faces",
             row.control_points ? "control points" : "targets", "acquired", "views",
             "alignable views");
  fmt::print(
      "{:>11} {:>13} {:>15} {:>15} {:>8} {:>15}\n", row.model_faces, row.fixture_faces, row.points,
      fmt::format("{} ({:.1f}%)", row.acquired, percent(row.acquired, row.points)), row.views,
      row.alignable
          ? fmt::format("{} ({:.1f}%)", *row.alignable, percent(*row.alignable, row.views))
          : "-");
}

}  // namespace scanplan::cli
