// The joint path search of robot/path_search.h, on OMPL.

#include "robot/path_search.h"

#include <scanplan/robot/motion.h>

#include <ompl/base/MotionValidator.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateSampler.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/datastructures/NearestNeighborsLinear.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>

#include <algorithm>
#include <memory>
#include <mutex>

namespace scanplan::detail {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

// OMPL's own sampler of the joint box, its generator seeded alike for every search: OMPL
// otherwise seeds each generator from seeds its process hands out one after another.
class SeededSampler : public ob::RealVectorStateSampler {
 public:
  explicit SeededSampler(const ob::StateSpace* space) : ob::RealVectorStateSampler(space) {
    rng_.setLocalSeed(1);
  }
};

CellPose poseOf(const ob::State* state, double table_angle) {
  const double* q = state->as<ob::RealVectorStateSpace::StateType>()->values;
  CellPose pose{table_angle, {}};
  std::copy(q, q + 6, pose.joints.begin());
  return pose;
}

// A move between two configurations is clear as moveIsClear samples it.
class SampledMotion : public ob::MotionValidator {
 public:
  SampledMotion(const ob::SpaceInformationPtr& si, const CellCollisions& collisions,
                double table_angle)
      : ob::MotionValidator(si), collisions_(collisions), table_angle_(table_angle) {}

  bool checkMotion(const ob::State* a, const ob::State* b) const override {
    return moveIsClear(collisions_, poseOf(a, table_angle_), poseOf(b, table_angle_));
  }
  bool checkMotion(const ob::State* a, const ob::State* b,
                   std::pair<ob::State*, double>& last_valid) const override {
    const std::vector<CellPose> samples =
        sampledMove(collisions_, poseOf(a, table_angle_), poseOf(b, table_angle_));
    for (std::size_t k = 1; k < samples.size(); ++k) {
      if (!collisions_.collides(samples[k])) continue;
      last_valid.second = static_cast<double>(k - 1) / static_cast<double>(samples.size() - 1);
      if (last_valid.first)
        si_->getStateSpace()->interpolate(a, b, last_valid.second, last_valid.first);
      return false;
    }
    return true;
  }

 private:
  const CellCollisions& collisions_;
  double table_angle_;
};

void setJoints(ob::ScopedState<ob::RealVectorStateSpace>& state, const Joints& q) {
  for (int j = 0; j < 6; ++j) state[j] = q[j];
}

// The path's corners kept where a straight joint move past them collides: from each, on to
// the farthest later corner the move to which is clear.
std::vector<CellPose> shortened(const CellCollisions& collisions,
                                const std::vector<CellPose>& path) {
  std::vector<CellPose> kept = {path.front()};
  for (std::size_t at = 0; at + 1 < path.size();) {
    std::size_t next = path.size() - 1;
    while (next > at + 1 && !moveIsClear(collisions, path[at], path[next])) --next;
    kept.push_back(path[next]);
    at = next;
  }
  return kept;
}

}  // namespace

std::optional<std::vector<CellPose>> searchedPath(const Cell& cell,
                                                  const CellCollisions& collisions,
                                                  const CellPose& from, const CellPose& to) {
  if (collisions.collides(from) || collisions.collides({from.table_angle, to.joints}))
    return std::nullopt;
  static std::once_flag quiet;
  std::call_once(quiet, [] { ompl::msg::setLogLevel(ompl::msg::LOG_NONE); });

  const RobotModel range = workingRange(cell);
  auto space = std::make_shared<ob::RealVectorStateSpace>(6);
  ob::RealVectorBounds bounds(6);  // the working range, and both ends (OMPL's upper above lower)
  for (int j = 0; j < 6; ++j) {
    const double low = std::min({range.lower[j], from.joints[j], to.joints[j]});
    bounds.setLow(j, low);
    bounds.setHigh(j, std::max({range.upper[j], from.joints[j], to.joints[j], low + 1e-9}));
  }
  space->setBounds(bounds);
  space->setStateSamplerAllocator(
      [](const ob::StateSpace* s) { return std::make_shared<SeededSampler>(s); });
  auto si = std::make_shared<ob::SpaceInformation>(space);
  const double angle = from.table_angle;
  si->setStateValidityChecker(
      [&](const ob::State* s) { return !collisions.collides(poseOf(s, angle)); });
  si->setMotionValidator(std::make_shared<SampledMotion>(si, collisions, angle));
  si->setup();

  ob::ScopedState<ob::RealVectorStateSpace> start(space), goal(space);
  setJoints(start, from.joints);
  setJoints(goal, to.joints);
  auto problem = std::make_shared<ob::ProblemDefinition>(si);
  problem->setStartAndGoalStates(start, goal);
  og::RRTConnect planner(si);
  planner.setNearestNeighbors<ompl::NearestNeighborsLinear>();  // no random pivots
  planner.setRange(kSearchStepLength);
  planner.setProblemDefinition(problem);
  planner.setup();
  unsigned steps = 0;
  const ob::PlannerStatus status =
      planner.solve(ob::PlannerTerminationCondition([&] { return ++steps > kMostSearchSteps; }));
  if (status != ob::PlannerStatus::EXACT_SOLUTION) return std::nullopt;

  std::vector<CellPose> path;
  for (const ob::State* s : problem->getSolutionPath()->as<og::PathGeometric>()->getStates())
    path.push_back(poseOf(s, angle));
  path = shortened(collisions, path);
  return std::vector<CellPose>(path.begin() + 1, path.end() - 1);
}

}  // namespace scanplan::detail
