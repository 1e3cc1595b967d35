#include "terminal.h"

#include <unistd.h>
#include <chrono>
#include <cstdio>
#include <mutex>

namespace scanplan::cli {
namespace {
std::mutex g_mutex;
bool g_line_open = false;
}  // namespace

Progress terminalProgress(bool quiet) {
  if (quiet || !isatty(fileno(stderr))) return {};
  auto start = std::chrono::steady_clock::now();
  return [start](std::string_view stage, double fraction) {
    std::lock_guard lock(g_mutex);
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "\r\033[K[%6.1fs] %.*s", seconds, static_cast<int>(stage.size()),
                 stage.data());
    if (fraction > 0 && fraction < 1) std::fprintf(stderr, " %3.0f%%", 100 * fraction);
    std::fflush(stderr);
    g_line_open = true;
  };
}

void clearProgress() {
  std::lock_guard lock(g_mutex);
  if (g_line_open) std::fprintf(stderr, "\r\033[K");
  g_line_open = false;
}

}  // namespace scanplan::cli
