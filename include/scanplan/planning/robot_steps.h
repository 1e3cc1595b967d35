#pragma once
// A plan turned into the robot's steps (docs/cell.md): its views in visiting order, each with
// the joints the cell takes it with, and the program made of them.

#include <scanplan/cad/part.h>
#include <scanplan/plan/plan.h>
#include <scanplan/robot/cell.h>
#include <scanplan/robot/program.h>
#include <scanplan/spec/spec.h>

#include <optional>
#include <string>
#include <vector>

namespace scanplan {

// The program of `plan` in `cell`: its views in sequence order (then any outside the
// sequence), each with its cell pose from `poses` (per view, in the order of the plan's
// views; none: left out as unreached).
RobotProgram robotProgram(const Plan& plan, const Cell& cell,
                          const std::vector<std::optional<CellPose>>& poses,
                          const std::string& name, const std::string& source);
// The same with the joints cellPoses chooses (clear of the part with `collisions`).
RobotProgram robotProgram(const Plan& plan, const Cell& cell, const std::string& name,
                          const std::string& source, const CellCollisions* collisions = nullptr);

// Each view's joints in `plan` as `program` takes them: planMotion takes a view by another of
// its solutions where that clears a move.
void takeProgramPoses(const RobotProgram& program, Plan& plan);

// The program of `plan` in `cell` (robotProgram, the cell poses `poses`) with its safe
// motion (planMotion, lifted by viaLift).
RobotProgram safeProgram(const Plan& plan, const Cell& cell, const CellCollisions& collisions,
                         const std::vector<std::optional<CellPose>>& poses, const std::string& name,
                         const std::string& source);

// The program a written plan runs as: its name, the setup of a plan over several rest
// orientations (1 to N: each is a program of its own, the part turned by hand between
// them; 0 for a plan of one), and the plan's file, which its header names.
struct ProgramRequest {
  std::string name;
  std::size_t setup = 0;
  std::string plan_file;
  std::string setup_key = "setup";  // how errors name the setup: the caller's option
};

// The robot program of `plan` (of its setup, `request`) in the cell it was planned in, with
// the joints planned, unless a spec other than the plan's own gives a cell: then in that
// cell, with the joints cellPoses chooses there. Every move planned clear of the part and
// the fixtures (safeProgram).
// \throw UsageError naming the setup key for a setup the plan does not have, or none named
// for a plan of several; InputError naming the spec's file (else the plan's) when neither
// gives a cell.
RobotProgram planProgram(const Plan& plan, const Part& part, const ResolvedSpec& spec,
                         const ProgramRequest& request);

// The views no route reaches or leaves: those in two of the moves between views that the
// robot could not clear (`uncleared`; view 0 is home), in ascending order. A move to or
// from home blames no view (home itself may be what collides), nor does a move alone (the
// order may be what fails).
std::vector<int> viewsBehind(const std::vector<RobotMove>& uncleared);

}  // namespace scanplan
