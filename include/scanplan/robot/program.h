#pragma once
// What the cell runs: a list of steps, the plan's views in sequence order, as a robot
// program that moves to each view and triggers a scan there (docs/cell.md). KUKA KRL (.src), ABB
// RAPID (.mod), Universal Robots URScript (.script), and a neutral JSON of joints and flange poses.

#include <scanplan/robot/cell.h>

#include <string>
#include <string_view>
#include <vector>

namespace scanplan {

// A move of the robot program between two views, by id (0: home).
struct RobotMove {
  int from = 0, to = 0;
};
std::string toString(const RobotMove& move);  // "view 3 -> home"

struct ProgramStep {
  int view = 0;      // view id in the plan
  std::string task;  // the task that asked for it
  CellPose pose;     // joints (radians) and table angle
  Pose flange;       // the flange in the robot's base frame, mm
  // Safe motion (robot/motion.h): the configurations passed on the way from the previous
  // step (or home), and the approach and retract pose back along the view's axis (none:
  // straight to the view).
  std::vector<CellPose> via;
  std::optional<Joints> approach;
};

struct RobotProgram {
  std::string name;    // a valid identifier in every language: letters, digits, _
  std::string source;  // what it was made from, for the header comment
  Cell cell;
  // The work object: the part's frame in the robot's base frame with the table at 0. The
  // programs give each view's scanner pose in it (scannerInPart).
  Pose work_object = Pose::Identity();
  // The payload's principal moments of inertia about its centre of gravity, flange axes,
  // kg·m² (loadInertia).
  Vec3 load_inertia = Vec3::Zero();
  std::vector<ProgramStep> steps;    // in sequence order
  std::vector<int> unreached;        // views of the plan the cell cannot take (left out)
  std::optional<CellPose> home;      // where the program starts and ends (planMotion)
  std::vector<CellPose> via_home;    // on the way back home from the last step
  std::vector<RobotMove> uncleared;  // moves that collide and could not be lifted clear
};

// The part's frame in the table's frame (tableFrame), mm: where the part rides on a cell with
// a table, as the programs' coordinated work objects give it.
Pose partOnTable(const RobotProgram& program);

// The scanner frame (the tool) at `step` in the part's frame as the table stands then, mm:
// the same for every table angle, since the part turns with the table.
Pose scannerInPart(const RobotProgram& program, const ProgramStep& step);

// The program of `steps` (in the order they are taken; `unreached`: views left out) with the
// part's frame at `work_object`. `name` is made a valid identifier.
RobotProgram robotProgram(const Cell& cell, const Pose& work_object, std::vector<ProgramStep> steps,
                          std::vector<int> unreached, const std::string& name,
                          const std::string& source);

// One move of a program, in order: home, the via points, each view's approach, the view
// (where the scan is taken), its retract (the approach again), the way home.
struct Waypoint {
  CellPose pose;
  std::string what;                   // "home", "via", "approach", "view", "retract"
  const ProgramStep* step = nullptr;  // the step it belongs to (none: home and its way)
};
std::vector<Waypoint> waypoints(const RobotProgram& program);

// Refuses a format the cell's robot does not run (each maker's language for its own arms:
// KRL for KUKA, RAPID for ABB, FANUC's for FANUC, URScript for Universal Robots; an arm
// given by its parameters runs any but URScript), signals the language cannot number, or a
// rotary table the format cannot drive (URScript without the table's signals).
// \throw UsageError naming the format.
void checkProgramFormat(const Cell& cell, std::string_view format);

// Refuses a program with a move that collides and could not be lifted clear, naming the
// first such move and how many there are, unless `allow`. \throw UsageError naming `path`,
// the program's file.
void checkClearMoves(const RobotProgram& program, bool allow, const std::string& path);

// ABB's cfx for an ortho-parallel arm at `joints` (RAPID reference manual, confdata, serial
// link robots): 4 when the wrist centre lies behind axis 1, + 2 when it lies behind the
// lower arm (axis 2 to axis 3), + 1 when axis 5 is negative; 0 to 7.
int rapidCfx(const RobotModel& robot, const Joints& joints);

std::string krlProgram(const RobotProgram& program);
// The .dat beside krlProgram's .src: its points, named (XHOME, XVIA<k>, XAPPROACH<view>,
// XVIEW<view>), so that they can be touched up on the pendant.
std::string krlData(const RobotProgram& program);
std::string rapidProgram(const RobotProgram& program);
std::string urScript(const RobotProgram& program);
// FANUC's teach-pendant program as LS text: joint positions (J3 as FANUC counts it, the
// table as E1), the handshake on GO, DO and DI with timeouts (docs/cell.md).
std::string fanucProgram(const RobotProgram& program);
std::string programJson(const RobotProgram& program);

// Refuses a format that is none of writeRobotProgram's. \throw UsageError naming "format".
void checkProgramLanguage(std::string_view format);

// "krl", "rapid", "fanuc", "urscript" or "json". \throw UsageError for another
// (checkProgramLanguage), one the cell's robot does not run (checkProgramFormat), or a file
// name the language cannot run; OutputError when it cannot be written.
void writeRobotProgram(const RobotProgram& program, std::string_view format,
                       const std::string& path);

}  // namespace scanplan
