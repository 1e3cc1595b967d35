#pragma once
// The subcommands of the scanplan tool. Each registers its subcommand and options on the
// CLI11 app; when that subcommand is parsed, it sets `selected` to the action to run.

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace scanplan::cli {

struct GlobalOptions {
  bool quiet = false;
  bool verbose = false;  // each stage's time on stderr
};

using Action = std::function<int()>;

// Refuses an empty file name given to an option (`--spec ""`), which would else read as no
// file given.
inline const CLI::Validator kNamedFile(
    [](std::string& name) { return name.empty() ? std::string("the file name is empty") : ""; },
    "FILE");

// scanplan info FILE [--json]
void addInfoCommand(CLI::App& app, const GlobalOptions& global, Action& selected);

// scanplan plan PART [--spec spec.yaml] [--scanner PRESET|file.yaml] [-o outdir]
void addPlanCommand(CLI::App& app, const GlobalOptions& global, Action& selected);

// scanplan sample PART [--spec spec.yaml] [-o samples.ply|.json]
void addSampleCommand(CLI::App& app, const GlobalOptions& global, Action& selected);

// scanplan verify plan.json PART [--spec spec.yaml]
void addVerifyCommand(CLI::App& app, const GlobalOptions& global, Action& selected);

// scanplan inspect plan.json PART [--spec spec.yaml] [--deviations FILE] [--runs N] [-o FILE]
void addInspectCommand(CLI::App& app, const GlobalOptions& global, Action& selected);

// scanplan report plan.json [PART] [-o report.html] [--png picture.png]
void addReportCommand(CLI::App& app, const GlobalOptions& global, Action& selected);

// scanplan export plan.json [PART] --format glb|samples-ply|clouds-ply|csv|png|krl|rapid|
//                                          urscript|robot-json -o FILE
void addExportCommand(CLI::App& app, const GlobalOptions& global, Action& selected);

// scanplan spec PART [--spec spec.yaml] [-o spec-editor.html]
void addSpecCommand(CLI::App& app, const GlobalOptions& global, Action& selected);

// scanplan scanners
void addScannersCommand(CLI::App& app, Action& selected);

// scanplan study study.yaml [-o DIR] [--jobs N] [--dask tcp://HOST:PORT]
void addStudyCommand(CLI::App& app, const GlobalOptions& global, Action& selected);

// scanplan simulate PART --views views.json [--spec spec.yaml] [-o,--cloud DIR] [--json]
void addSimulateCommand(CLI::App& app, const GlobalOptions& global, Action& selected);

}  // namespace scanplan::cli
