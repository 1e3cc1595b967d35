// scanplan plan: the main job, from a part and a spec to plan.json and report.html.

#include "commands.h"
#include "files.h"
#include "summary.h"
#include "terminal.h"

#include <scanplan/cad/import.h>
#include <scanplan/cad/localization.h>
#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/points_csv.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning.h>
#include <scanplan/report/report.h>
#include <scanplan/spec/spec.h>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <map>
#include <optional>

namespace scanplan::cli {
namespace {

struct Options {
  std::string part;
  std::string spec;
  std::string scanner;
  std::string outdir = "scanplan-out";
  bool no_registration = false;
  bool no_report = false;
  bool png = false;
  bool place_markers = false;
  std::optional<double> coverage;  // --coverage: planner.coverage for every task
  std::string aim;                 // --aim: planner.aim
  std::string rest;                // --rest: part.rest
};

constexpr const char* kProposedMarkers = "proposed-markers.csv";

// The part, then per task and role the samples and those measured.
void printTaskRows(const Plan& plan, const Part& part) {
  std::map<std::pair<std::string, std::string>, std::array<std::size_t, 2>> rows;
  for (const PlannedSample& s : plan.samples) {
    auto& row = rows[{std::string(toString(s.sample.task)), std::string(toString(s.sample.role))}];
    ++row[0];
    row[1] += !s.measured_by.empty();
  }
  fmt::print("part       {} ({} faces)\n", part.file, part.faces.size());
  fmt::print("{:<10} {:<9} {:>8} {:>9} {:>8}\n", "task", "role", "samples", "measured", "share");
  for (const auto& [key, row] : rows)
    fmt::print("{:<10} {:<9} {:>8} {:>9} {:>7.1f}%\n", key.first, key.second, row[0], row[1],
               100.0 * static_cast<double>(row[1]) / static_cast<double>(row[0]));
}

// Into `outputs`: the surface task's interpolated patches, plan.json, and as asked
// report.html and plan.png; the files of the set this run does not write are dropped.
// Returns the report's seconds.
double writeOutputs(Plan& plan, const Part& part, const Spec& spec, const Options& options,
                    FileSet& outputs, const Progress& progress) {
  const std::filesystem::path outdir(options.outdir);
  writePlanFiles(plan, (outdir / "plan.json").string(), &outputs);
  const auto report_start = std::chrono::steady_clock::now();
  // Resolved once for the report and the picture: it reads the fixture models.
  const ResolvedSpec resolved = resolveSpec(part, spec);
  printWarnings("", resolved.warnings);
  if (!options.no_report)
    writeReport(plan, part, resolved, outputs.stage((outdir / "report.html").string()), {},
                progress);
  else
    outputs.drop((outdir / "report.html").string());
  const double report_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - report_start).count();
  if (options.png)
    writePng(renderScene(planScene(plan, part, resolved)),
             outputs.stage((outdir / "plan.png").string()));
  else
    outputs.drop((outdir / "plan.png").string());
  return report_seconds;
}

// Writes to `csv` the markers `plan` proposed; with `planning` (--place-markers), plans
// again with them (planWithProposedMarkers) into `plan`, and writes every marker added.
void stageProposedMarkers(const Part& part, const Spec& spec, const PlanningOptions* planning,
                          const Progress& progress, const std::string& csv, Plan& plan) {
  std::vector<Marker> markers = plan.proposed_markers->markers;
  if (planning) {
    PlacedMarkers placed =
        planWithProposedMarkers(part, spec, std::move(plan), *planning, progress);
    plan = std::move(placed.plan);
    markers = std::move(placed.placed);
  }
  writeMarkers(markers, csv);
}

// The samples not coverable, by reason; the selection against its bound.
void printCoverageAndBound(const Plan& plan) {
  fmt::print("{:<22} {}\n", "not coverable", plan.notCoverableCount());
  std::map<std::string, std::size_t> reasons;
  for (const PlannedSample& s : plan.samples)
    if (s.uncoverable != Uncoverable::None) ++reasons[std::string(toString(s.uncoverable))];
  for (const auto& [reason, count] : reasons) fmt::print("  {:<28} {}\n", reason, count);
  if (!plan.bound) return;
  const PlanBound& b = *plan.bound;
  fmt::print("{:<22} {} views, at least {} needed from {} candidate poses{} (greedy {})\n",
             "selection", b.views, b.lower_bound, b.pool, b.proven_optimal ? ", the fewest" : "",
             b.greedy_views);
  if (b.time_capped)
    printWarnings("", {"the selection stopped at planner.selection_seconds before its "
                       "planner.selection_nodes: this plan depends on the machine's speed"});
}

// The spec with the command line's settings over its own: --scanner, --coverage, --aim
// (--rest is applied before, when the inputs are listed).
void applyOptions(Spec& spec, const Options& options) {
  if (!options.scanner.empty()) spec.scanner = scannerNamed(options.scanner);
  if (options.coverage) {
    if (!(*options.coverage > 0 && *options.coverage <= 1))
      throw UsageError("--coverage", "must be a share within (0, 1], such as 0.95");
    spec.planner.coverage.others = *options.coverage;
    spec.planner.coverage.tasks.clear();
  }
  if (!options.aim.empty())
    spec.planner.aim = options.aim == "samples" ? Aim::Samples : Aim::Characteristics;
  if (options.place_markers && spec.rest_all)  // refused before the part is read and planned
    throw UsageError("--place-markers",
                     "plans one rest orientation only, not every one (--rest all, or the "
                     "spec's part.rest: all)");
}

int run(const Options& options, const GlobalOptions& global) {
  Spec spec = options.spec.empty() ? defaultSpec() : loadSpec(options.spec);
  if (!options.rest.empty()) setRest(spec, options.rest, "--rest");
  const std::vector<std::string> inputs = commandInputs({options.part}, spec);
  for (const char* name : {"plan.json", "report.html", "plan.png", kProposedMarkers})
    refuseInputAsOutput((std::filesystem::path(options.outdir) / name).string(), inputs);
  Progress progress = terminalProgress(global);
  applyOptions(spec, options);
  const Part part = importWithWarnings(options.part, {}, progress);
  // --rest FACE is checked here, so that a face the part cannot stand on is named as given.
  if (!options.rest.empty() && spec.rest_face) restOnFace(part, spec.rest_face, "", "--rest");
  PlanningOptions planning;
  planning.registration = !options.no_registration;
  Plan plan = planViews(part, spec, planning, progress);
  for (const Sweep& sweep : plan.sweeps)
    if (!sweep.patch_file.empty())
      refuseInputAsOutput((std::filesystem::path(options.outdir) / sweep.patch_file).string(),
                          inputs);
  // The folder only once the inputs are read and planned: a failed run leaves none.
  std::error_code ec;
  std::filesystem::create_directories(options.outdir, ec);
  if (ec) throw OutputError(options.outdir, "cannot create the folder: " + ec.message());
  const std::filesystem::path outdir(options.outdir);
  const std::string markers_csv = (outdir / kProposedMarkers).string();
  const std::string path = (outdir / "plan.json").string();
  FileSet outputs;
  const bool proposed = plan.proposed_markers && !plan.proposed_markers->markers.empty();
  if (proposed)
    stageProposedMarkers(part, spec, options.place_markers ? &planning : nullptr, progress,
                         outputs.stage(markers_csv), plan);
  else
    outputs.drop(markers_csv);
  const double report_seconds = writeOutputs(plan, part, spec, options, outputs, progress);
  outputs.commit();
  clearProgress();

  printTaskRows(plan, part);
  printPlanSummary(plan, part);
  printCoverageAndBound(plan);
  printResultsRow(plan);
  fmt::print("\n");
  for (const StageTime& t : plan.times) fmt::print("  {:<16} {:.2f} s\n", t.stage, t.seconds);
  if (!options.no_report) fmt::print("  {:<16} {:.2f} s\n", "report", report_seconds);
  fmt::print("total      {:.2f} s\nplan       {}\n", plan.seconds, path);
  if (!options.no_report) fmt::print("report     {}\n", (outdir / "report.html").string());
  if (options.png) fmt::print("picture    {}\n", (outdir / "plan.png").string());
  if (proposed)
    fmt::print("markers    {}{}\n", markers_csv,
               options.place_markers ? " (placed: the plan above uses them)" : "");
  if (plan.views.empty()) {  // a valid plan, but nothing to scan: say why, and fail
    fmt::print(stderr,
               "error: {}: no sample of the spec's tasks can be measured (see 'not "
               "coverable' above)\n",
               part.file);
    return kExitPlanning;
  }
  return kExitOk;
}

}  // namespace

void addPlanCommand(CLI::App& app, const GlobalOptions& global, Action& selected) {
  auto options = std::make_shared<Options>();
  CLI::App* command =
      app.add_subcommand("plan", "Plan the scanner views for a part and write plan.json");
  command->add_option("part", options->part, "CAD or mesh file of the part")->required();
  command->add_option("--spec", options->spec, "Inspection spec (YAML); default: one global task")
      ->check(kNamedFile);
  command->add_option("-o,--out", options->outdir, "Output folder (default: scanplan-out)");
  command->add_option("--scanner", options->scanner,
                      "Scanner preset (scanplan scanners) or scanner file (YAML), overriding the "
                      "spec's");
  command->add_option("--coverage", options->coverage,
                      "Share of the coverable samples of every task to measure, such as 0.95 "
                      "(the priority faces' samples keep the spec's share, all of them by "
                      "default); overrides planner.coverage");
  command
      ->add_option("--aim", options->aim,
                   "What the views must measure: samples (every coverable sample) or "
                   "characteristics (what each characteristic's capability needs); overrides "
                   "planner.aim")
      ->check(CLI::IsMember({"samples", "characteristics"}));
  command->add_option("--rest", options->rest,
                      "How the part stands, overriding the spec's part.rest: auto (its steadiest "
                      "rest), all (every rest orientation), drawn (as the CAD model is drawn) or a "
                      "face id to stand on");
  command->add_flag("--no-registration", options->no_registration,
                    "Skip the registration check, bridging and sequencing");
  command->add_flag("--no-report", options->no_report,
                    "Do not write report.html (the 3D HTML report) beside plan.json");
  command->add_flag("--place-markers", options->place_markers,
                    "Where views register to nothing, plan again with the markers proposed for "
                    "them (written to proposed-markers.csv)");
  command->add_flag("--png", options->png,
                    "Also write plan.png, a picture of the part coloured by coverage with the "
                    "views and the path");
  command->callback([options, &global, &selected] {
    selected = [options, &global] { return run(*options, global); };
  });
}

}  // namespace scanplan::cli
