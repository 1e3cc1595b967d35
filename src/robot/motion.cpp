// Safe motion between the views of a robot program: approach poses along the view axes,
// joint-interpolated moves sampled and checked with the cell's collision model (FCL), via
// points above the scene where a direct move collides, and a path searched for in joint
// space where those do not clear it (robot/path_search.h).

#include "robot/path_search.h"

#include <scanplan/robot/cycle.h>
#include <scanplan/robot/motion.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

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

// `pose` with its flange moved by `offset` (world frame, mm), same orientation, same table
// angle, the clear solution nearest to it; none when the robot cannot take it clear.
std::optional<CellPose> shifted(const Cell& cell, const CellCollisions& collisions,
                                const CellPose& pose, const Vec3& offset) {
  Pose world = cell.base * forwardKinematics(cell.robot, pose.joints);
  world.translation() += offset;
  const std::optional<Joints> q = nearestClear(
      collisions, workingRange(cell), cell.base.inverse() * world, pose.joints, pose.table_angle);
  if (!q) return std::nullopt;
  return CellPose{pose.table_angle, *q};
}

// The poses that move the flange of `pose` along `offset` in a straight line, same
// orientation: the fewest equal steps (1, 2, 4 or 8) whose joint moves are all clear; none
// when no such steps are found.
std::optional<std::vector<CellPose>> straightMove(const Cell& cell,
                                                  const CellCollisions& collisions,
                                                  const CellPose& pose, const Vec3& offset) {
  for (int steps = 1; steps <= 8; steps *= 2) {
    std::vector<CellPose> path;
    CellPose at = pose;
    for (int k = 0; k < steps; ++k) {
      const std::optional<CellPose> next = shifted(cell, collisions, at, offset / steps);
      if (!next || !moveIsClear(collisions, at, *next)) break;
      path.push_back(*next);
      at = *next;
    }
    if (static_cast<int>(path.size()) == steps) return path;
  }
  return std::nullopt;
}

// The poses that take the flange of `pose` up towards `height` (world z), same orientation:
// straight up, or where that collides, first back away from what the scanner looks at (along
// its axis or level, 200 or 400 mm) and then up. Where the orientation cannot be kept that
// high, as far up as it can: three quarters, half or a quarter of the way. None when no path
// rises; empty when the flange is there already.
std::optional<std::vector<CellPose>> liftOf(const Cell& cell, const CellCollisions& collisions,
                                            const CellPose& pose, double height) {
  const Pose flange = cell.base * forwardKinematics(cell.robot, pose.joints);
  const double rise = height - flange.translation().z();
  if (rise <= 0) return std::vector<CellPose>{};
  const Vec3 axis = -(flange * cell.mount).linear().col(2);  // away from the scanner's view
  const Vec3 level(axis.x(), axis.y(), 0);
  std::vector<Vec3> backs = {Vec3::Zero(), 200 * axis, 400 * axis};
  if (level.norm() > 0.1)
    backs.insert(backs.begin() + 1, {200 * level.normalized(), 400 * level.normalized()});
  for (const double share : {1.0, 0.75, 0.5, 0.25})
    for (const Vec3& back : backs) {
      std::optional<std::vector<CellPose>> path = std::vector<CellPose>{};
      if (back.norm() > 0) path = straightMove(cell, collisions, pose, back);
      if (!path) continue;
      const std::optional<std::vector<CellPose>> up = straightMove(
          cell, collisions, path->empty() ? pose : path->back(), Vec3(0, 0, share * rise));
      if (!up) continue;
      path->insert(path->end(), up->begin(), up->end());
      return path;
    }
  return std::nullopt;
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
  if (!q || !moveIsClear(collisions, {step.pose.table_angle, *q}, step.pose)) return std::nullopt;
  return q;
}

// The via points of the move from `from` to `to` (at one table angle): none when it is
// clear, else up over the scene from each end where it can rise, and across; where the
// move across collides, through `home`'s joints. nullopt when that collides too.
std::optional<std::vector<CellPose>> viaPoints(const Cell& cell, const CellCollisions& collisions,
                                               const CellPose& from, const CellPose& to,
                                               double height, const CellPose* home) {
  if (moveIsClear(collisions, from, to)) return std::vector<CellPose>{};
  std::vector<CellPose> up =
      liftOf(cell, collisions, from, height).value_or(std::vector<CellPose>{});
  const std::vector<CellPose> down =
      liftOf(cell, collisions, to, height).value_or(std::vector<CellPose>{});
  const CellPose& top_from = up.empty() ? from : up.back();
  const CellPose& top_to = down.empty() ? to : down.back();
  if (!moveIsClear(collisions, top_from, top_to)) {
    if (!home) return std::nullopt;
    const CellPose over{to.table_angle, home->joints};
    if (!moveIsClear(collisions, top_from, over) || !moveIsClear(collisions, over, top_to))
      return std::nullopt;
    up.push_back(over);
  }
  up.insert(up.end(), down.rbegin(), down.rend());
  return up;
}

// The via points of the move from `from` to `to` when the table turns: it turns with the
// arm standing still, at `from` where the whole turn is clear, else at `from` raised
// towards `height` (liftOf), else at `home`'s joints; then viaPoints. nullopt when no turn is
// clear.
std::optional<std::vector<CellPose>> turnThenMove(const Cell& cell,
                                                  const CellCollisions& collisions,
                                                  const CellPose& from, const CellPose& to,
                                                  double height, const CellPose* home) {
  if (std::abs(to.table_angle - from.table_angle) < 1e-12)
    return viaPoints(cell, collisions, from, to, height, home);
  const auto turnIsClear = [&](const CellPose& at) {
    return moveIsClear(collisions, at, {to.table_angle, at.joints});
  };
  std::vector<CellPose> via;
  if (!turnIsClear(from)) {
    const std::optional<std::vector<CellPose>> up = liftOf(cell, collisions, from, height);
    const CellPose over = home ? CellPose{from.table_angle, home->joints} : from;
    if (up && !up->empty() && turnIsClear(up->back()))
      via = *up;
    else if (home && moveIsClear(collisions, from, over) && turnIsClear(over))
      via = {over};
    else
      return std::nullopt;
  }
  const CellPose turned{to.table_angle, via.empty() ? from.joints : via.back().joints};
  via.push_back(turned);
  const std::optional<std::vector<CellPose>> rest =
      viaPoints(cell, collisions, turned, to, height, home);
  if (!rest) return std::nullopt;
  via.insert(via.end(), rest->begin(), rest->end());
  return via;
}

// A home clear of everything: the scanner looking straight down from `height` (flange,
// world z) above the middle of the views' flanges, or where the robot cannot take that
// clear, above points a quarter, a half and three quarters of the way to the robot's base;
// the scanner's x axis turned about the vertical in 45° steps, the joints nearest `near`.
std::optional<CellPose> computedHome(const Cell& cell, const CellCollisions& collisions,
                                     const std::vector<ProgramStep>& steps, const Joints& near,
                                     double height) {
  Vec3 middle = Vec3::Zero();
  for (const ProgramStep& step : steps) middle += (cell.base * step.flange).translation();
  middle /= static_cast<double>(steps.size());
  const Vec3 base = cell.base.translation();
  const RobotModel robot = workingRange(cell);
  for (const double towards_base : {0.0, 0.25, 0.5, 0.75}) {
    Vec3 above = middle + towards_base * (base - middle);
    above.z() = height;
    for (int turn = 0; turn < 8; ++turn) {
      Pose scanner = Pose::Identity();
      scanner.linear() = (Eigen::AngleAxisd(turn * M_PI / 4, Vec3::UnitZ()) *
                          Eigen::AngleAxisd(M_PI, Vec3::UnitX()))
                             .toRotationMatrix();
      Pose flange = scanner * cell.mount.inverse();
      flange.translation() = above;
      if (const std::optional<Joints> q =
              nearestClear(collisions, robot, cell.base.inverse() * flange, near, 0))
        return CellPose{0, *q};
    }
  }
  return std::nullopt;
}

// The program's home: cell.home when it is clear, else computedHome, else `first` (the
// first view's approach) raised towards `height` (liftOf); none when none is clear.
std::optional<CellPose> homeOf(const Cell& cell, const CellCollisions& collisions,
                               const std::vector<ProgramStep>& steps, const CellPose& first,
                               double height) {
  if (cell.home) {
    const CellPose home{0, *cell.home};
    if (collisions.collides(home)) return std::nullopt;
    return home;
  }
  if (std::optional<CellPose> home = computedHome(cell, collisions, steps, first.joints, height))
    return home;
  const std::optional<std::vector<CellPose>> up = liftOf(cell, collisions, first, height);
  if (up && !up->empty()) return up->back();
  return std::nullopt;
}

}  // namespace

std::vector<CellPose> sampledMove(const CellCollisions& collisions, const CellPose& from,
                                  const CellPose& to, int finer) {
  const int n = std::max(1, static_cast<int>(std::ceil(collisions.travelBound(from, to) /
                                                       collisions.sampleSpacing()))) *
                std::max(finer, 1);
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

bool moveIsClear(const CellCollisions& collisions, const CellPose& from, const CellPose& to) {
  for (const CellPose& p : sampledMove(collisions, from, to))
    if (collisions.collides(p)) return false;
  return true;
}

namespace {

// The via points of a move no lift over the scene clears, searched for in joint space
// (robot/path_search.h): at one table angle, or with the table turning where the arm
// stands at the move's start, else at its end. nullopt when the search finds none.
std::optional<std::vector<CellPose>> searchedMove(const Cell& cell,
                                                  const CellCollisions& collisions,
                                                  const CellPose& from, const CellPose& to) {
  if (from.table_angle == to.table_angle) return detail::searchedPath(cell, collisions, from, to);
  const CellPose turned_from{to.table_angle, from.joints}, turned_to{from.table_angle, to.joints};
  if (moveIsClear(collisions, from, turned_from))
    if (auto path = detail::searchedPath(cell, collisions, turned_from, to)) {
      path->insert(path->begin(), turned_from);
      return path;
    }
  if (moveIsClear(collisions, turned_to, to))
    if (auto path = detail::searchedPath(cell, collisions, from, turned_to)) {
      path->push_back(turned_to);
      return path;
    }
  return std::nullopt;
}

// Where the arm stands when it starts on step `s` and leaves it: its approach, or the view
// itself when it has none.
CellPose stepStart(const ProgramStep& s) {
  return CellPose{s.pose.table_angle, s.approach.value_or(s.pose.joints)};
}

// The safe motion of a program: the via points of each move into a step and of the way
// home, found or not.
struct Moves {
  const Cell& cell;
  const CellCollisions& collisions;
  RobotProgram& program;
  double height;
  // Per move k: into step k, and for k = steps.size() the way home.
  std::vector<std::optional<std::vector<CellPose>>> via;

  CellPose from(std::size_t k) const {
    return k == 0 ? *program.home : stepStart(program.steps[k - 1]);
  }
  CellPose to(std::size_t k) const {
    return k == program.steps.size() ? *program.home : stepStart(program.steps[k]);
  }
  void plan(std::size_t k) {
    via[k] = turnThenMove(cell, collisions, from(k), to(k), height, &*program.home);
  }

  // Step `i` taken by another of its inverse-kinematics solutions (its table angle, clear)
  // where the moves into and out of it were not both clear and are then; true when found.
  bool resolve(std::size_t i) {
    ProgramStep& step = program.steps[i];
    const ProgramStep original = step;
    const auto saved = std::pair{via[i], via[i + 1]};
    for (const Joints& q : inverseKinematics(workingRange(cell), step.flange, step.pose.joints)) {
      if (q == original.pose.joints || collisions.collides({step.pose.table_angle, q})) continue;
      step.pose.joints = q;
      step.approach = approachOf(cell, collisions, step);
      plan(i);
      plan(i + 1);
      if (via[i] && via[i + 1]) return true;
    }
    step = original;
    std::tie(via[i], via[i + 1]) = saved;
    return false;
  }
};

}  // namespace

void planMotion(RobotProgram& program, const CellCollisions& collisions, double lift) {
  if (program.steps.empty()) return;
  const Cell& cell = program.cell;
  const double height = collisions.top() + lift;
  for (ProgramStep& step : program.steps) step.approach = approachOf(cell, collisions, step);
  const CellPose first = stepStart(program.steps.front());
  const std::optional<CellPose> home = homeOf(cell, collisions, program.steps, first, height);
  // Without a clear home the program starts at its first view's approach, the move from home
  // marked as not cleared.
  program.home = home.value_or(first);
  if (!home) program.uncleared.push_back({0, program.steps.front().view});
  const std::size_t n = program.steps.size();
  Moves moves{cell, collisions, program, height,
              std::vector<std::optional<std::vector<CellPose>>>(n + 1)};
  for (std::size_t k = 0; k <= n; ++k) moves.plan(k);
  // A move not cleared: the step it reaches, or the one it leaves, by another solution;
  // else a path searched for.
  for (std::size_t k = 0; k <= n; ++k) {
    if (moves.via[k] || (k < n && moves.resolve(k))) continue;
    if (k > 0) moves.resolve(k - 1);
  }
  for (std::size_t k = 0; k <= n; ++k)
    if (!moves.via[k]) moves.via[k] = searchedMove(cell, collisions, moves.from(k), moves.to(k));
  for (std::size_t k = 0; k <= n; ++k) {
    const int from = k == 0 ? 0 : program.steps[k - 1].view;
    const int to = k == n ? 0 : program.steps[k].view;
    if (!moves.via[k]) {
      program.uncleared.push_back({from, to});
      continue;
    }
    (k == n ? program.via_home : program.steps[k].via) = *moves.via[k];
  }
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
