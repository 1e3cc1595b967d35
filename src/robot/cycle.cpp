// The cycle time of a plan (docs/cycle.md).
#include <scanplan/core/errors.h>
#include <scanplan/robot/cycle.h>

#include <algorithm>
#include <cmath>

namespace scanplan {

void validate(const CycleSettings& c, const std::string& source) {
  auto within = [&](double value, double lo, double hi, const std::string& what) {
    if (!(value >= lo && value <= hi)) throw InputError(source, "cycle." + what);
  };
  within(c.settle, 0, 60, "settle must lie within [0, 60] s");
  within(c.handshake, 0, 60, "handshake must lie within [0, 60] s");
  within(c.speed, 1, 10000, "speed must lie within [1, 10000] mm/s");
  within(c.acceleration, 1, 100000, "acceleration must lie within [1, 100000] mm/s²");
  within(c.turn_over, 0, 3600, "turn_over must lie within [0, 3600] s");
}

CycleTime& CycleTime::operator+=(const CycleTime& more) {
  if (!by_views.empty() && !more.by_views.empty()) {
    const double before = total();
    for (double s : more.by_views) by_views.push_back(before + s);
  } else {
    by_views.clear();
  }
  views += more.views;
  acquisition += more.acquisition;
  motion += more.motion;
  table += more.table;
  other += more.other;
  turns += more.turns;
  turning += more.turning;
  return *this;
}

MoveSeconds moveSeconds(const Cell& cell, const CellPose& a, const CellPose& b) {
  MoveSeconds seconds{travelTime(cell.robot, a.joints, b.joints), 0};
  if (cell.table)
    seconds.table = trapezoidSeconds(std::abs(a.table_angle - b.table_angle), cell.table->speed,
                                     cell.table->acceleration);
  return seconds;
}

namespace {

// The time at the views: their acquisition, settling and handshakes.
void addViews(CycleTime& cycle, std::size_t views, const Scanner& scanner,
              const CycleSettings& settings) {
  cycle.views = views;
  cycle.acquisition = static_cast<double>(views) * scanner.acquisitionSeconds();
  cycle.other = static_cast<double>(views) * (settings.settle + settings.handshake);
}

}  // namespace

double viewSeconds(const Scanner& scanner, const CycleSettings& settings) {
  return scanner.acquisitionSeconds() + settings.settle + settings.handshake;
}

std::vector<double> cycleByViews(std::span<const double> path, const Scanner& scanner,
                                 const CycleSettings& settings) {
  std::vector<double> result;
  for (std::size_t k = 0; k < path.size(); ++k)
    result.push_back(static_cast<double>(k + 1) * viewSeconds(scanner, settings) + path[k]);
  return result;
}

CycleTime programCycle(const RobotProgram& program, const Scanner& scanner,
                       const CycleSettings& settings) {
  CycleTime cycle;
  cycle.model = "cell";
  const std::vector<Waypoint> path = waypoints(program);
  std::size_t views = 0;
  for (std::size_t k = 0; k < path.size(); ++k) {
    views += path[k].what == "view";
    if (k == 0) continue;
    const MoveSeconds move = moveSeconds(program.cell, path[k - 1].pose, path[k].pose);
    (move.table > move.arm ? cycle.table : cycle.motion) += move.total();
  }
  addViews(cycle, views, scanner, settings);
  return cycle;
}

CycleTime genericCycle(std::span<const double> distances, std::size_t views, const Scanner& scanner,
                       const CycleSettings& settings) {
  CycleTime cycle;
  cycle.model = "generic";
  for (double d : distances)
    cycle.motion += trapezoidSeconds(d, settings.speed, settings.acceleration);
  addViews(cycle, views, scanner, settings);
  return cycle;
}

}  // namespace scanplan
