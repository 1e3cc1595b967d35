#include "terminal.h"

#include <unistd.h>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace scanplan::cli {
namespace {

using Clock = std::chrono::steady_clock;

std::mutex g_mutex;
bool g_line_open = false;
// With --verbose: the stage under way and when it began.
std::string g_stage;
Clock::time_point g_stage_start;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Ends the status line, if one is shown (g_mutex held).
void endLine() {
  if (g_line_open) std::fprintf(stderr, "\r\033[K");
  g_line_open = false;
}

// With --verbose, the time of the stage under way once it ends (g_mutex held).
void endStage() {
  if (g_stage.empty()) return;
  endLine();
  std::fprintf(stderr, "  %-48s %8.2f s\n", g_stage.c_str(), secondsSince(g_stage_start));
  g_stage.clear();
}

}  // namespace

Progress terminalProgress(const GlobalOptions& global) {
  const bool line = !global.quiet && isatty(fileno(stderr));
  if (!line && !global.verbose) return {};
  const auto start = Clock::now();
  return [start, line, verbose = global.verbose](std::string_view stage, double fraction) {
    std::lock_guard lock(g_mutex);
    if (verbose && stage != g_stage) {
      endStage();
      g_stage = stage;
      g_stage_start = Clock::now();
    }
    if (!line) return;
    std::fprintf(stderr, "\r\033[K[%6.1fs] %.*s", secondsSince(start),
                 static_cast<int>(stage.size()), stage.data());
    if (fraction > 0 && fraction < 1) std::fprintf(stderr, " %3.0f%%", 100 * fraction);
    std::fflush(stderr);
    g_line_open = true;
  };
}

void clearProgress() {
  std::lock_guard lock(g_mutex);
  endStage();
  endLine();
}

void printWarnings(const std::string& file, const std::vector<std::string>& warnings) {
  if (warnings.empty()) return;
  std::lock_guard<std::mutex> lock(g_mutex);
  endLine();
  for (const std::string& warning : warnings)
    std::fprintf(stderr, "warning: %s%s\n", file.empty() ? "" : (file + ": ").c_str(),
                 warning.c_str());
}

Part importWithWarnings(const std::string& path, const ImportOptions& options,
                        const Progress& progress) {
  Part part = importPart(path, options, progress);
  printWarnings(part.file, part.warnings);
  return part;
}

}  // namespace scanplan::cli
