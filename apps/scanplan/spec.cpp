// scanplan spec: the inspection-spec editor of a part, a page to open in a browser.

#include "commands.h"
#include "files.h"
#include "terminal.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/editor/editor.h>
#include <scanplan/io/spec_yaml.h>

#include <fmt/format.h>

namespace scanplan::cli {
namespace {

struct SpecCommand {
  std::string part;
  std::string spec;
  std::string out = "spec-editor.html";
};

int run(const SpecCommand& options, const GlobalOptions& global) {
  refuseInputAsOutput(
      options.out,
      commandInputs({options.part}, options.spec.empty() ? defaultSpec() : loadSpec(options.spec)));
  const Part part = importWithWarnings(options.part, {}, terminalProgress(global));
  writeSpecEditor(part, options.spec, options.out);
  clearProgress();
  fmt::print("editor     {}\n", options.out);
  return kExitOk;
}

}  // namespace

void addSpecCommand(CLI::App& app, const GlobalOptions& global, Action& selected) {
  auto options = std::make_shared<SpecCommand>();
  CLI::App* command = app.add_subcommand(
      "spec",
      "Write the inspection-spec editor of a part: pick faces, tasks and control points "
      "in a browser, download spec.yaml and points.csv");
  command->add_option("part", options->part, "CAD or mesh file of the part")->required();
  command->add_option("--spec", options->spec, "Inspection spec (YAML) to start from")
      ->check(kNamedFile);
  command->add_option("-o,--out", options->out, "HTML file (default: spec-editor.html)");
  command->callback([options, &global, &selected] {
    selected = [options, &global] { return run(*options, global); };
  });
}

}  // namespace scanplan::cli
