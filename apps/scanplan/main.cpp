// scanplan: plans the views of a robot-mounted 3D scanner for inspecting a part.
// This file wires the subcommands; the work is in the library.

#include "commands.h"
#include "terminal.h"

#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/core/version.h>

#include <tbb/global_control.h>

#include <csignal>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>

namespace {

// Ended by a signal: the files being written are removed, then the signal ends the run as
// usual.
extern "C" void onInterrupt(int signal) {
  scanplan::removeTemporaries();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace scanplan;
  for (const int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGXCPU, SIGXFSZ})
    std::signal(signal, onInterrupt);

  CLI::App app{"scanplan: view planning for robotic 3D scanning inspection"};
  app.require_subcommand(1);
  cli::GlobalOptions global;
  app.fallthrough();
  app.set_version_flag("--version", "scanplan " + std::string(version()));
  app.add_flag("-q,--quiet", global.quiet, "Show no progress");
  app.add_flag("-v,--verbose", global.verbose, "Write the time of each stage (import included)");
  int threads = 0;
  app.add_option("-j,--threads", threads,
                 "Threads to use (default: all cores); plans do not depend on it")
      ->check(CLI::Range(1, 1024));
  cli::Action action;
  cli::addInfoCommand(app, global, action);
  cli::addPlanCommand(app, global, action);
  cli::addSampleCommand(app, global, action);
  cli::addSimulateCommand(app, global, action);
  cli::addVerifyCommand(app, global, action);
  cli::addInspectCommand(app, global, action);
  cli::addReportCommand(app, global, action);
  cli::addExportCommand(app, global, action);
  cli::addSpecCommand(app, global, action);
  cli::addScannersCommand(app, action);
  cli::addStudyCommand(app, global, action);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }
  std::unique_ptr<tbb::global_control> thread_limit;
  if (threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(
        tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  try {
    int code = action();
    cli::clearProgress();
    return code;
  } catch (const Error& e) {
    cli::clearProgress();
    std::fprintf(stderr, "error: %s\n", printable(e.what()).c_str());
    return e.exitCode();
  } catch (const std::exception& e) {
    cli::clearProgress();
    std::fprintf(stderr, "error: internal: %s\n", printable(e.what()).c_str());
    return kExitPlanning;
  }
}
