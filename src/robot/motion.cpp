// Safe motion between the views of a robot program: approach poses along the view axes,
// joint-interpolated moves sampled and checked with the cell's collision model (FCL), and
// via points above the scene where a direct move collides.

#include <scanplan/robot/cycle.h>
#include <scanplan/robot/motion.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace scanplan {
namespace {

double largestStep(const CellPose& a, const CellPose& b) {
  double largest = std::abs(b.table_angle - a.table_angle);
  for (int j = 0; j < 6; ++j) largest = std::max(largest, std::abs(b.joints[j] - a.joints[j]));
  return largest;
}

// The solution for `flange` nearest to `near` (largest joint difference) that is clear.
std::optional<Joints> nearestClear(const CellCollisions& collisions, const RobotModel& robot,
                                   const Pose& flange, const Joints& near, double table_angle) {
  std::optional<Joints> best;
  double best_step = 0;
  for (const Joints& q : inverseKinematics(robot, flange, near)) {
    if (collisions.collides({table_angle, q})) continue;
    const double step = largestStep({0, q}, {0, near});
    if (!best || step < best_step) {
      best = q;
      best_step = step;
    }
  }
  return best;
}

// `pose` with its flange raised (world z) to `height`, same orientation, same table angle;
// none when the robot cannot take it clear.
std::optional<CellPose> lifted(const Cell& cell, const CellCollisions& collisions,
                               const CellPose& pose, double height) {
  Pose world = cell.base * forwardKinematics(cell.robot, pose.joints);
  world.translation().z() = std::max(world.translation().z(), height);
  const std::optional<Joints> q = nearestClear(
      collisions, workingRange(cell), cell.base.inverse() * world, pose.joints, pose.table_angle);
  if (!q) return std::nullopt;
  return CellPose{pose.table_angle, *q};
}

// The approach joints of `step`: the camera moved back along its axis by cell.approach,
// clear, and the move from there to the view clear too.
std::optional<Joints> approachOf(const Cell& cell, const CellCollisions& collisions,
                                 const ProgramStep& step) {
  if (cell.approach <= 0) return std::nullopt;
  const Pose back =
      step.flange * cell.mount * Eigen::Translation3d(0, 0, -cell.approach) * cell.mount.inverse();
  const std::optional<Joints> q =
      nearestClear(collisions, workingRange(cell), back, step.pose.joints, step.pose.table_angle);
  if (!q || !moveIsClear(collisions, {step.pose.table_angle, *q}, step.pose, cell.motion_step))
    return std::nullopt;
  return q;
}

// The via points of the move from `from` to `to`: none when it is clear, else up over the
// scene and across; nullopt when that collides too.
std::optional<std::vector<CellPose>> viaPoints(const Cell& cell, const CellCollisions& collisions,
                                               const CellPose& from, const CellPose& to,
                                               double height) {
  if (moveIsClear(collisions, from, to, cell.motion_step)) return std::vector<CellPose>{};
  const std::optional<CellPose> up = lifted(cell, collisions, from, height);
  const std::optional<CellPose> over = lifted(cell, collisions, to, height);
  if (!up || !over || !moveIsClear(collisions, from, *up, cell.motion_step) ||
      !moveIsClear(collisions, *up, *over, cell.motion_step) ||
      !moveIsClear(collisions, *over, to, cell.motion_step))
    return std::nullopt;
  return std::vector<CellPose>{*up, *over};
}

}  // namespace

std::vector<CellPose> sampledMove(const CellPose& from, const CellPose& to, double step) {
  const int n = std::max(1, static_cast<int>(std::ceil(largestStep(from, to) / step)));
  std::vector<CellPose> samples;
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    CellPose p;
    p.table_angle = from.table_angle + t * (to.table_angle - from.table_angle);
    for (int j = 0; j < 6; ++j) p.joints[j] = from.joints[j] + t * (to.joints[j] - from.joints[j]);
    samples.push_back(p);
  }
  return samples;
}

bool moveIsClear(const CellCollisions& collisions, const CellPose& from, const CellPose& to,
                 double step) {
  for (const CellPose& p : sampledMove(from, to, step))
    if (collisions.collides(p)) return false;
  return true;
}

void planMotion(RobotProgram& program, const CellCollisions& collisions, double lift) {
  if (program.steps.empty()) return;
  const Cell& cell = program.cell;
  const double height = collisions.top() + lift;
  for (ProgramStep& step : program.steps) step.approach = approachOf(cell, collisions, step);
  auto start = [](const ProgramStep& s) {
    return CellPose{s.pose.table_angle, s.approach.value_or(s.pose.joints)};
  };
  if (cell.home)
    program.home = CellPose{0, *cell.home};
  else
    program.home = lifted(cell, collisions, start(program.steps.front()), height);
  if (!program.home) program.home = start(program.steps.front());
  auto join = [&](const CellPose& from, const CellPose& to, RobotMove move,
                  std::vector<CellPose>& via) {
    const std::optional<std::vector<CellPose>> points =
        viaPoints(cell, collisions, from, to, height);
    if (points)
      via = *points;
    else
      program.uncleared.push_back(move);
  };
  CellPose at = *program.home;
  int at_view = 0;  // home
  for (ProgramStep& step : program.steps) {
    join(at, start(step), {at_view, step.view}, step.via);
    at = start(step);
    at_view = step.view;
  }
  join(at, *program.home, {at_view, 0}, program.via_home);
}

double viaLift(const Cell& cell, const Scanner& scanner) {
  return cell.mount.translation().norm() + scanner.body_depth + scanner.body_margin +
         cell.clearance;
}

double programSeconds(const RobotProgram& program) {
  const std::vector<Waypoint> path = waypoints(program);
  double seconds = 0;
  for (std::size_t k = 1; k < path.size(); ++k)
    seconds += moveTime(program.cell, path[k - 1].pose, path[k].pose);
  return seconds;
}

double moveTime(const Cell& cell, const CellPose& a, const CellPose& b) {
  return moveSeconds(cell, a, b).total();
}

JointMotion jointMotion(const Cell& cell, const std::vector<std::optional<CellPose>>& poses,
                        const std::vector<View>& views, const std::vector<int>& order) {
  std::map<int, std::size_t> index;
  for (std::size_t i = 0; i < views.size(); ++i) index[views[i].id] = i;
  JointMotion motion;
  const CellPose* previous = nullptr;
  for (int id : order) {
    auto it = index.find(id);
    if (it == index.end() || it->second >= poses.size()) continue;
    const std::optional<CellPose>& pose = poses[it->second];
    if (!pose) {
      ++motion.unreached;
      continue;
    }
    if (previous) {
      for (int j = 0; j < 6; ++j) {
        const double step = std::abs(pose->joints[j] - previous->joints[j]);
        if (step > motion.max_step) {
          motion.max_step = step;
          motion.max_step_joint = j + 1;
        }
      }
      motion.seconds += moveTime(cell, *previous, *pose);
      motion.table_moves += std::abs(pose->table_angle - previous->table_angle) > 1e-9;
    }
    previous = &*pose;
  }
  return motion;
}

}  // namespace scanplan
