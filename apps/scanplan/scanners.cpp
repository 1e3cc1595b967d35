// scanplan scanners: the scanner presets with their main figures.

#include "commands.h"

#include <scanplan/scanner/sensor.h>

#include <fmt/format.h>

namespace scanplan::cli {
namespace {

int run() {
  fmt::print("{:<26} {:>8} {:>8} {:>15} {:>8} {:>8} {:>6}\n", "preset", "standoff", "depth",
             "field", "spacing", "noise", "angle");
  fmt::print("{:<26} {:>8} {:>8} {:>15} {:>8} {:>8} {:>6}\n", "", "mm", "mm", "mm", "mm", "mm",
             "deg");
  for (const std::string& name : scannerPresetNames()) {
    const Scanner s = scannerPreset(name);
    fmt::print("{:<26} {:>8.0f} {:>8.0f} {:>15} {:>8.3f} {:>8.3f} {:>6.0f}\n", name, s.standoff,
               s.depth_of_field, fmt::format("{:.0f} x {:.0f}", s.fov_width, s.fov_height),
               s.point_spacing, s.noise_sigma, s.triangulation_angle);
  }
  return 0;
}

}  // namespace

void addScannersCommand(CLI::App& app, Action& selected) {
  CLI::App* command = app.add_subcommand(
      "scanners",
      "List the scanner presets (plan --scanner, the spec's scanner) with their figures");
  command->callback([&selected] { selected = run; });
}

}  // namespace scanplan::cli
