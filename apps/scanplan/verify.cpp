// scanplan verify: checks a plan again on its part: coverage, registration, sequence.

#include "commands.h"
#include "files.h"
#include "summary.h"
#include "terminal.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning.h>
#include <scanplan/spec/spec.h>

#include <fmt/format.h>

#include <algorithm>

namespace scanplan::cli {
namespace {

struct Options {
  std::string plan;
  std::string part;
  std::string spec;
};

int run(const Options& options, const GlobalOptions& global) {
  Progress progress = terminalProgress(global);
  const Plan plan = readPlan(options.plan);
  const Spec spec = specFor(options.spec, plan, options.plan);
  const Part part = importWithWarnings(partFileFor(options.part, plan, options.plan), {}, progress);
  const PlanCheck check = verifyPlan(plan, part, spec, {}, progress);
  clearProgress();

  fmt::print("{:<22} {}\n", "plan", options.plan);
  fmt::print("{:<22} {}\n", "part", part.file);
  fmt::print("{:<22} {}\n", "spec", specSource(options.spec, plan));
  printPlanSummary(check.plan, part);
  auto verdict = [](std::size_t differences, const std::string& what) {
    return differences == 0 ? std::string("as planned") : fmt::format("{} {}", differences, what);
  };
  fmt::print(
      "{:<22} every sample on its face: within {:.4f} mm of its surface ({:g} allowed) and "
      "{:.4f} mm of its triangles ({:.4f} allowed)\n",
      "part check", check.part.exact_farthest, check.part.exact_tolerance, check.part.mesh_farthest,
      check.part.mesh_tolerance);
  fmt::print("{:<22} {}\n", "coverage check",
             verdict(check.coverage_differences, "samples measured otherwise than planned"));
  if (!plan.registration) {
    fmt::print("{:<22} {}\n", "registration check", "none: planned without registration");
  } else {
    fmt::print("{:<22} {}\n", "registration check",
               verdict(check.registration_differences, "views registered otherwise than planned"));
    if (check.unregistered > 0)
      fmt::print("{:<22} {} views register to nothing{}\n", "unregistered", check.unregistered,
                 check.registration_required ? "" : " (the plan does not require registration)");
  }
  if (!plan.sequence)
    fmt::print("{:<22} {}\n", "sequence check", "none: planned without a sequence");
  else
    fmt::print("{:<22} {}\n", "sequence check",
               check.sequence_missing + check.sequence_breaks == 0
                   ? std::string("every view once, each after one it registers to") +
                         (plan.registration && !plan.registration->aligned_as_taken
                              ? " (those registered by ICP in any order: aligned once all are "
                                "taken)"
                              : "")
                   : fmt::format("{} views missing or repeated, {} not after one they register to",
                                 check.sequence_missing, check.sequence_breaks));
  const bool measures = std::any_of(check.plan.samples.begin(), check.plan.samples.end(),
                                    [](const PlannedSample& s) { return !s.measured_by.empty(); });
  if (!measures) fmt::print("{:<22} {}\n", "measured", "nothing: no view measures a sample");
  return check.holds() && measures ? kExitOk : kExitPlanning;
}

}  // namespace

void addVerifyCommand(CLI::App& app, const GlobalOptions& global, Action& selected) {
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand(
      "verify",
      "Check a plan again on its part: coverage, registration and sequence (exit 3 when the "
      "plan does not hold)");
  command->add_option("plan", options->plan, "plan.json")->required();
  command->add_option("part", options->part,
                      "CAD or mesh file of the part (default: the file the plan names)");
  command
      ->add_option("--spec", options->spec,
                   "Inspection spec (YAML): specular faces, markers, registration thresholds "
                   "(default: the one the plan was made with)")
      ->check(kNamedFile);
  command->callback([options, &global, &selected] {
    selected = [options, &global] { return run(*options, global); };
  });
}

}  // namespace scanplan::cli
