// scanplan scanners: the scanner presets with their main figures.

#include "commands.h"

#include <scanplan/scanner/sensor.h>

#include <fmt/format.h>

namespace scanplan::cli {
namespace {

int run() {
  const char* row = "{:<26} {:>8} {:>8} {:>15} {:>8} {:>8} {:>6} {:>7} {:>12}\n";
  fmt::print(fmt::runtime(row), "preset", "standoff", "depth", "field", "spacing", "noise", "angle",
             "cameras", "acquisition");
  fmt::print(fmt::runtime(row), "", "mm", "mm", "mm", "mm", "mm", "deg", "", "s");
  for (const std::string& name : scannerPresetNames()) {
    const Scanner s = scannerPreset(name);
    fmt::print(fmt::runtime(row), name, fmt::format("{:.0f}", s.standoff),
               fmt::format("{:.0f}", s.depth_of_field),
               fmt::format("{:.0f} x {:.0f}", s.fov_width, s.fov_height),
               fmt::format("{:.3f}", s.point_spacing), fmt::format("{:.3f}", s.noise_sigma),
               fmt::format("{:.0f}", s.triangulation_angle), fmt::format("{:.0f}", s.cameras),
               fmt::format("{:.2f}{}", s.acquisitionSeconds(), s.sweep_speed > 0 ? " sweep" : ""));
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
