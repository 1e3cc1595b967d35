// scanplan report and scanplan export: what a written plan shows, checked again on its
// part (coverage and registration as `verify` finds them), as the HTML report, a picture,
// or files for other tools.

#include "commands.h"
#include "files.h"
#include "terminal.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/inspection_files.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/io/views_csv.h>
#include <scanplan/planning.h>
#include <scanplan/report/report.h>
#include <scanplan/robot/motion.h>
#include <scanplan/robot/program.h>
#include <scanplan/spec/spec.h>

#include <fmt/format.h>

#include <filesystem>
#include <map>
#include <optional>

namespace scanplan::cli {
namespace {

struct Input {
  std::string plan;
  std::string part;  // "" : the plan's own part file
  std::string spec;
};

// \throw OutputError when `out` is one of the command's own input files, or a file its
// spec names.
void refuseOwnInput(const std::string& out, const Input& input, const Spec& spec) {
  refuseInputAsOutput(out, commandInputs({input.plan, input.part}, spec));
}

struct Checked {
  Plan plan;
  Part part;
  ResolvedSpec spec;  // with its fixture models read once
};

// The plan re-simulated and its registration re-checked on its part, as verify does.
Checked check(const Input& input, const Plan& plan, const Spec& spec, const Progress& progress) {
  Part part = importWithWarnings(partFileFor(input.part, plan, input.plan), {}, progress);
  PlanCheck checked = verifyPlan(plan, part, spec, {}, progress);
  ResolvedSpec resolved = resolveSpec(part, spec);
  printWarnings("", resolved.warnings);
  return {std::move(checked.plan), std::move(part), std::move(resolved)};
}

void addInput(CLI::App& command, Input& input) {
  command.add_option("plan", input.plan, "plan.json")->required();
  command.add_option("part", input.part,
                     "CAD or mesh file of the part (default: the file the plan names)");
  command
      .add_option("--spec", input.spec,
                  "Inspection spec (YAML) of the plan: specular faces, markers, fixtures, cell "
                  "(default: the one the plan was made with)")
      ->check(kNamedFile);
}

struct ReportCommand {
  Input input;
  std::string out;
  std::string png;
  std::string inspection;
};

// The inspection the report shows: the one named, else inspection.json beside the plan if
// there is one.
std::optional<Inspection> inspectionFor(const ReportCommand& options, const Plan& plan) {
  std::string file = options.inspection;
  if (file.empty()) {
    const std::filesystem::path beside =
        std::filesystem::path(options.input.plan).parent_path() / "inspection.json";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(beside, ec)) return std::nullopt;
    file = beside.string();
  }
  return readInspection(file, plan);
}

int runReport(const ReportCommand& options, const GlobalOptions& global) {
  const std::string out =
      options.out.empty()
          ? (std::filesystem::path(options.input.plan).parent_path() / "report.html").string()
          : options.out;
  const Plan plan = readPlan(options.input.plan);
  const Spec spec = specFor(options.input.spec, plan, options.input.plan);
  refuseOwnInput(out, options.input, spec);
  if (!options.png.empty()) refuseOwnInput(options.png, options.input, spec);
  if (!options.inspection.empty()) refuseInputAsOutput(out, {options.inspection});
  Progress progress = terminalProgress(global);
  const Checked c = check(options.input, plan, spec, progress);
  ReportEvidence evidence = reportEvidence(c.plan, c.part, c.spec, {}, progress);
  evidence.inspection = inspectionFor(options, c.plan);
  writeReport(c.plan, c.part, c.spec, evidence, out);
  if (!options.png.empty()) writePng(renderScene(planScene(c.plan, c.part, c.spec)), options.png);
  clearProgress();
  fmt::print("report     {}\n", out);
  if (!options.png.empty()) fmt::print("picture    {}\n", options.png);
  return kExitOk;
}

struct ExportCommand {
  Input input;
  std::string format;
  std::string out;
  double spacing = 1;
  std::string frame;  // cad (the default) or world; files of points and poses only
  bool allow_collisions = false;
  std::size_t setup = 0;  // robot programs of a plan over several rest orientations: 1 to N
};

// Whether `format` is a robot program.
bool programFormat(const std::string& format) {
  return format == "krl" || format == "rapid" || format == "fanuc" || format == "urscript" ||
         format == "robot-json";
}

// The robot program of the plan in its cell, or in another spec's (planProgram).
void writeProgram(const Checked& c, const ExportCommand& options) {
  // KRL wants the program named as its file.
  const ProgramRequest request{std::filesystem::path(options.out).stem().string(), options.setup,
                               options.input.plan, "--setup"};
  const RobotProgram program = planProgram(c.plan, c.part, c.spec, request);
  checkClearMoves(program, options.allow_collisions, options.out);
  const std::string language = options.format == "robot-json" ? "json" : options.format;
  writeRobotProgram(program, language, options.out);
  if (!program.unreached.empty())
    fmt::print("left out   {} views the cell cannot reach\n", program.unreached.size());
  for (const RobotMove& move : program.uncleared)
    fmt::print("warning    the move {} collides and could not be cleared\n", toString(move));
  fmt::print("motion     {:.1f} s of joint travel\n", programSeconds(program));
}

// The plan's views as CSV, in the order the cell visits them: in the CAD frame, or each in
// the world of its setup.
void writeViewsInOrder(const Plan& plan, Frame frame, const std::string& out) {
  const std::vector<std::size_t> orientation = viewOrientations(plan);
  std::map<int, std::size_t> index;
  for (std::size_t v = 0; v < plan.views.size(); ++v) index[plan.views[v].id] = v;
  ViewsCsv csv{{}, {}, std::string(toString(frame)), plan.scanner.standoff};
  for (int id : visitingOrder(plan)) {
    const std::size_t v = index.at(id);
    View view = plan.views[v];
    if (frame == Frame::Cad) {
      const Pose to_cad = orientationPlacement(plan, orientation[v]).inverse();
      view.camera_to_world = to_cad * view.camera_to_world;
      view.target = to_cad * view.target;
    }
    csv.views.push_back(view);
    csv.setups.push_back(orientation[v] + 1);
  }
  writeViewsCsv(csv, out);
}

// Whether `format` holds points and poses, which --frame places.
bool placedFormat(const std::string& format) {
  return format == "csv" || format == "glb" || format == "samples-ply" || format == "clouds-ply";
}

// The frame --frame names.
Frame exportFrame(const ExportCommand& options) {
  if (!options.frame.empty() && !placedFormat(options.format))
    throw UsageError("--frame",
                     "applies to csv, glb, samples-ply and clouds-ply; " + options.format +
                         " is written in the " +
                         (options.format == "png" ? "report's view" : "robot's own frames"));
  if (options.setup > 0 && !programFormat(options.format))
    throw UsageError("--setup",
                     "applies to robot programs; " + options.format + " holds every setup");
  return options.frame == "world" ? Frame::World : Frame::Cad;
}

int runExport(const ExportCommand& options, const GlobalOptions& global) {
  const Frame frame = exportFrame(options);
  const Plan plan = readPlan(options.input.plan);
  const Spec spec = specFor(options.input.spec, plan, options.input.plan);
  refuseOwnInput(options.out, options.input, spec);
  // The views' CSV needs the plan only; a part given is checked against it all the same.
  if (options.format == "csv" && options.input.part.empty()) {
    writeViewsInOrder(plan, frame, options.out);
  } else {
    Progress progress = terminalProgress(global);
    const Checked c = check(options.input, plan, spec, progress);
    if (options.format == "csv") {
      writeViewsInOrder(c.plan, frame, options.out);
    } else if (options.format == "glb") {
      PlanScene scene = planScene(c.plan, c.part, c.spec);
      moveScene(scene, sceneTo(c.plan, frame));
      writeGlb(scene, options.out);
    } else if (options.format == "samples-ply") {
      writePly(samplesPly(c.plan, frame), options.out);
    } else if (options.format == "clouds-ply") {
      writeCloudsPly(c.plan, c.part, c.spec.spec, options.spacing, frame, options.out, progress);
    } else if (options.format == "png") {
      writePng(renderScene(planScene(c.plan, c.part, c.spec)), options.out);
    } else {
      writeProgram(c, options);
    }
    clearProgress();
  }
  if (placedFormat(options.format))
    fmt::print("written    {} ({}, {} frame)\n", options.out, options.format, toString(frame));
  else
    fmt::print("written    {} ({})\n", options.out, options.format);
  return kExitOk;
}

}  // namespace

void addReportCommand(CLI::App& app, const GlobalOptions& global, Action& selected) {
  auto options = std::make_shared<ReportCommand>();
  CLI::App* command =
      app.add_subcommand("report", "Write the 3D HTML report of a plan, checked again on its part");
  addInput(*command, options->input);
  command->add_option("-o,--out", options->out, "HTML file (default: report.html beside the plan)");
  command->add_option("--png", options->png, "Also write a picture of the scene to this PNG file");
  command
      ->add_option("--inspection", options->inspection,
                   "Results of scanplan inspect to show (default: inspection.json beside the "
                   "plan, if there is one)")
      ->check(kNamedFile);
  command->callback([options, &global, &selected] {
    selected = [options, &global] { return runReport(*options, global); };
  });
}

void addExportCommand(CLI::App& app, const GlobalOptions& global, Action& selected) {
  auto options = std::make_shared<ExportCommand>();
  CLI::App* command = app.add_subcommand(
      "export",
      "Write a plan for other tools: glTF scene, PLY of samples or clouds, CSV of views, robot "
      "programs");
  addInput(*command, options->input);
  command
      ->add_option(
          "--format", options->format,
          "glb (glTF 2.0 binary scene), samples-ply (samples with coverage), "
          "clouds-ply (every view's simulated cloud), csv (views), png (picture), "
          "krl, rapid, fanuc, urscript, robot-json (robot programs; the plan's cell, or the "
          "spec's)")
      ->required()
      ->check(CLI::IsMember({"glb", "samples-ply", "clouds-ply", "csv", "png", "krl", "rapid",
                             "fanuc", "urscript", "robot-json"}));
  command->add_option("-o,--out", options->out, "Output file")->required();
  command
      ->add_option("--frame", options->frame,
                   "csv, glb, samples-ply, clouds-ply: the frame of points and poses, cad (the "
                   "part's CAD model, the default) or world (the cell's: each view's setup for "
                   "csv, the first setup for the others)")
      ->check(CLI::IsMember({"cad", "world"}));
  command->add_flag("--allow-collisions", options->allow_collisions,
                    "Robot programs: write one even with moves that collide and could not be "
                    "cleared, marked in its header (refused otherwise)");
  command
      ->add_option("--setup", options->setup,
                   "Robot programs of a plan over several rest orientations: the setup to write "
                   "(1 to N), each a program of its own, the part turned by hand between them")
      ->check(CLI::Range(1, 10000));
  command
      ->add_option("--spacing", options->spacing,
                   "clouds-ply: mm between the camera rays of each view (default 1; 0: the "
                   "scanner's point spacing, which makes files of gigabytes for large plans)")
      ->check(CLI::Range(0.0, 100.0));
  command->callback([options, &global, &selected] {
    selected = [options, &global] { return runExport(*options, global); };
  });
}

}  // namespace scanplan::cli
