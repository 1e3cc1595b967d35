// A plan's views as the robot's steps, in visiting order.

#include <scanplan/core/errors.h>
#include <scanplan/planning/cell_poses.h>
#include <scanplan/planning/planner.h>
#include <scanplan/planning/robot_steps.h>
#include <scanplan/planning/verify.h>
#include <scanplan/robot/kinematics.h>
#include <scanplan/robot/motion.h>

#include <algorithm>
#include <iterator>
#include <map>

namespace scanplan {
namespace {

// Each view's place in plan.views, by its id.
std::map<int, std::size_t> viewIndex(const Plan& plan) {
  std::map<int, std::size_t> index;
  for (std::size_t i = 0; i < plan.views.size(); ++i) index[plan.views[i].id] = i;
  return index;
}

// The plan a program is written for: the plan, or the setup `setup` (1 to N) of a plan over
// several rest orientations.
Plan programPlan(const Plan& plan, std::size_t setup, const std::string& key) {
  const std::size_t setups = std::max<std::size_t>(1, plan.orientations.size());
  if (setup == 0 && setups > 1)
    throw UsageError(key, "the plan turns the part into " + std::to_string(setups) +
                              " rest orientations, each a program of its own: name one, 1 to " +
                              std::to_string(setups));
  if (setup > setups)
    throw UsageError(key, "the plan has " + std::to_string(setups) + " setup" +
                              (setups == 1 ? "" : "s") + ", not " + std::to_string(setup));
  return setups == 1 ? plan : setupPlan(plan, setup - 1);
}

}  // namespace

RobotProgram robotProgram(const Plan& plan, const Cell& cell,
                          const std::vector<std::optional<CellPose>>& poses,
                          const std::string& name, const std::string& source) {
  const std::map<int, std::size_t> index = viewIndex(plan);
  std::vector<ProgramStep> steps;
  std::vector<int> unreached;
  for (int id : visitingOrder(plan)) {
    const std::size_t i = index.at(id);
    if (i >= poses.size() || !poses[i]) {
      unreached.push_back(id);
      continue;
    }
    steps.push_back({id,
                     plan.views[i].task,
                     *poses[i],
                     forwardKinematics(cell.robot, poses[i]->joints),
                     {},
                     {}});
  }
  RobotProgram program = robotProgram(cell, cell.base.inverse() * plan.part_to_world,
                                      std::move(steps), std::move(unreached), name, source);
  program.load_inertia = loadInertia(cell, plan.scanner.body());
  return program;
}

RobotProgram robotProgram(const Plan& plan, const Cell& cell, const std::string& name,
                          const std::string& source, const CellCollisions* collisions) {
  return robotProgram(plan, cell, cellPoses(cell, plan.views, visitingOrder(plan), collisions),
                      name, source);
}

void takeProgramPoses(const RobotProgram& program, Plan& plan) {
  const std::map<int, std::size_t> index = viewIndex(plan);
  plan.cell_poses.resize(plan.views.size());
  for (const ProgramStep& step : program.steps) plan.cell_poses[index.at(step.view)] = step.pose;
}

RobotProgram safeProgram(const Plan& plan, const Cell& cell, const CellCollisions& collisions,
                         const std::vector<std::optional<CellPose>>& poses, const std::string& name,
                         const std::string& source) {
  RobotProgram program = robotProgram(plan, cell, poses, name, source);
  planMotion(program, collisions, viaLift(cell, plan.scanner));
  return program;
}

RobotProgram planProgram(const Plan& written, const Part& part, const ResolvedSpec& spec,
                         const ProgramRequest& request) {
  checkPlanPart(written, part);
  const Plan plan = programPlan(written, request.setup, request.setup_key);
  // The cell planned takes the views with the joints planned: with no spec's cell, or with
  // the spec the plan was made with. Another cell, with those cellPoses chooses there.
  const bool planned =
      plan.cell && (!spec.spec.cell || (written.spec && written.spec->text == spec.spec.text));
  const std::optional<Cell>& cell = planned ? plan.cell : spec.spec.cell;
  if (!cell)
    throw InputError(spec.spec.source.empty() ? request.plan_file : spec.spec.source,
                     "robot programs need the cell: the plan carries none (made without one, "
                     "or with link meshes); give a spec with cell.robot");
  const SimulationOptions placed = simulationOptionsFor(spec, part, plan.part_to_world);
  const CellCollisions collisions(*cell, plan.scanner.body(), part.mesh, plan.part_to_world,
                                  placed.fixtures, placed.working_plane, cell->clearance);
  const std::vector<std::optional<CellPose>> poses =
      planned ? plan.cell_poses : cellPoses(*cell, plan.views, visitingOrder(plan), &collisions);
  const std::size_t setups = written.orientations.size();
  const std::string source =
      request.plan_file +
      (setups > 1 ? ", setup " + std::to_string(request.setup) + " of " + std::to_string(setups)
                  : "");
  return safeProgram(plan, *cell, collisions, poses, request.name, source);
}

std::vector<int> viewsBehind(const std::vector<RobotMove>& uncleared) {
  std::vector<RobotMove> between;  // the moves between two views
  std::copy_if(uncleared.begin(), uncleared.end(), std::back_inserter(between),
               [](const RobotMove& m) { return m.from > 0 && m.to > 0; });
  std::map<int, int> moves;  // view id: the moves it is in
  for (const RobotMove& m : between)
    for (const int id : {m.from, m.to}) ++moves[id];
  std::vector<int> behind;
  for (const auto& [id, n] : moves)
    if (n > 1) behind.push_back(id);
  return behind;
}

}  // namespace scanplan
