// scanplan inspect: a virtual inspection of a plan on its part, each characteristic
// measured over Monte Carlo runs of the plan's scans (docs/capability.md).

#include "commands.h"
#include "files.h"
#include "terminal.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/inspection_files.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning/inspection.h>
#include <scanplan/spec/spec.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <map>

namespace scanplan::cli {
namespace {

struct Options {
  std::string plan;
  std::string part;
  std::string spec;
  std::string deviations;
  std::string out;
  int runs = 20;
  bool runs_given = false;
  double precision = 0;
  double spacing = 0;
  InspectionOptions::IcpLinks icp = InspectionOptions::IcpLinks::Drawn;
};

// The planned capability of characteristic `id`, if the plan has it.
const Capability* planned(const Plan& plan, int id) {
  for (const Capability& k : plan.capabilities)
    if (k.characteristic == id) return &k;
  return nullptr;
}

// What the runs were asked for, and for which characteristics they ran out first.
std::string runsAskedFor(const Inspection& inspection) {
  if (!(inspection.precision_asked > 0)) return "";
  return fmt::format(
      " (until each U + |bias| is known within {:.3g} %{})", 100 * inspection.precision_asked,
      inspection.imprecise.empty()
          ? ""
          : fmt::format("; the runs ran out first for {}", fmt::join(inspection.imprecise, ", ")));
}

void printInspection(const Inspection& inspection, const Plan& plan) {
  fmt::print(
      "{:<22} {} runs{}, points {:.2f} mm apart{}\n", "inspection", inspection.runs,
      runsAskedFor(inspection), inspection.spacing,
      inspection.views_left_out > 0
          ? fmt::format(", {} views left out (registered to nothing)", inspection.views_left_out)
          : "");
  if (inspection.icp_registered > 0)
    fmt::print(
        "{:<22} {} views registered by ICP in every run; {} registered again from another "
        "start, {} still off after three\n",
        "", inspection.icp_registered, inspection.icp_restarted, inspection.icp_failed);
  fmt::print("  {:>3} {:<22} {:>8} {:>10} {:>10} {:>9} {:>8} {:>9} {:>9} {:>7}  {:<14} {}\n", "id",
             "kind", "width", "true", "measured", "bias", "U", "±", "error 95", "ratio", "verdict",
             "planned U, verdict");
  for (std::size_t i = 0; i < inspection.characteristics.size(); ++i) {
    const InspectedCharacteristic& k = inspection.characteristics[i];
    const Characteristic& c = plan.characteristics[i];
    const Capability* p = planned(plan, c.id);
    const std::string plan_side =
        p ? fmt::format("{:.4f}, {}", p->uncertainty, toString(p->verdict)) : "-";
    if (!k.evaluated) {
      fmt::print("  {:>3} {:<22} {:>8.3f}  not evaluated: {}\n", c.id, c.kind, c.width(),
                 k.not_evaluated);
      continue;
    }
    fmt::print(
        "  {:>3} {:<22} {:>8.3f} {:>10.4f} {:>10.4f} {:>9.4f} {:>8.4f} {:>9.4f} {:>9.4f} {:>7.2f}  "
        "{:<14} {}\n",
        c.id, c.kind, c.width(), k.true_value, k.mean, k.bias, k.uncertainty, k.precision,
        k.error_95, k.ratio, toString(k.verdict), plan_side);
  }
  fmt::print(
      "{:<22} ±: how far U + |bias| may lie, at 95 %, from what endless runs give; error 95: "
      "what 95 % of the runs' errors stay under, as the planned U\n",
      "");
}

int run(const Options& options, const GlobalOptions& global) {
  Progress progress = terminalProgress(global);
  const Plan plan = readPlan(options.plan);
  const Spec spec = specFor(options.spec, plan, options.plan);
  InspectionOptions inspection;
  inspection.runs = options.precision > 0 && !options.runs_given ? kMostPreciseRuns : options.runs;
  inspection.precision = options.precision;
  inspection.spacing = options.spacing;
  inspection.icp = options.icp;
  if (!options.deviations.empty()) inspection.deviations = loadDeviations(options.deviations);
  const std::string out =
      options.out.empty()
          ? (std::filesystem::path(options.plan).parent_path() / "inspection.json").string()
          : options.out;
  const std::string part_file = partFileFor(options.part, plan, options.plan);
  refuseInputAsOutput(out, commandInputs({options.plan, part_file, options.deviations}, spec));
  const Part part = importWithWarnings(part_file, {}, progress);
  const ResolvedSpec resolved = resolveSpec(part, spec);
  const Inspection result = inspectPlan(part, resolved, plan, inspection, progress);
  writeInspection(result, plan, out);
  clearProgress();
  fmt::print("{:<22} {}\n", "plan", options.plan);
  fmt::print("{:<22} {}\n", "part", part.file);
  fmt::print("{:<22} {}\n", "spec", specSource(options.spec, plan));
  printInspection(result, plan);
  fmt::print("{:<22} {}\n", "written", out);
  return kExitOk;
}

}  // namespace

void addInspectCommand(CLI::App& app, const GlobalOptions& global, Action& selected) {
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand(
      "inspect",
      "Inspect a plan virtually: each characteristic measured over Monte Carlo runs of its "
      "scans, with the scanner's errors and the registration's");
  command->add_option("plan", options->plan, "plan.json")->required();
  command->add_option("part", options->part,
                      "CAD or mesh file of the part (default: the file the plan names)");
  command
      ->add_option("--spec", options->spec,
                   "Inspection spec (YAML) (default: the one the plan was made with)")
      ->check(kNamedFile);
  command
      ->add_option("--deviations", options->deviations,
                   "Deviations of the simulated part (YAML: faces offset, bowed, moved, a "
                   "diameter changed)")
      ->check(kNamedFile);
  CLI::Option* runs =
      command
          ->add_option("--runs", options->runs,
                       fmt::format("Monte Carlo runs (default 20; with --precision, the most, "
                                   "default {})",
                                   kMostPreciseRuns))
          ->check(CLI::Range(2, 10000));
  command
      ->add_option("--precision", options->precision,
                   fmt::format("Run until each characteristic's U + |bias| is known within this "
                               "share of itself at 95 % (bootstrap of the runs; checked every {} "
                               "runs from {} on)",
                               kPrecisionBatch, kLeastRuns))
      ->check(CLI::Range(0.001, 0.999));
  command
      ->add_option(
          "--spacing", options->spacing,
          "Simulated points' spacing at the standoff, mm (default planner.evaluation_spacing, "
          "or fov_height / 100)")
      ->check(CLI::Range(0.01, 100.0));
  command
      ->add_option("--icp", options->icp,
                   "Views registered by ICP: drawn from the capability model's covariance "
                   "(default), or registered by ICP on each run's simulated clouds (slower)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, InspectionOptions::IcpLinks>{
              {"registered", InspectionOptions::IcpLinks::Registered},
              {"drawn", InspectionOptions::IcpLinks::Drawn}},
          CLI::ignore_case));
  command->add_option("-o,--output", options->out,
                      "Results (JSON; default inspection.json beside the plan)");
  command->callback([options, runs, &global, &selected] {
    options->runs_given = runs->count() > 0;
    selected = [options, &global] { return run(*options, global); };
  });
}

}  // namespace scanplan::cli
