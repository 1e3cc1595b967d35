#pragma once
// A generated car-door case for benchmarks and tests: a door-like panel (a crowned outer
// skin with a character line and a window opening, cut into a grid of B-spline faces,
// sewn into one shell), a marker frame around it as a fixture model, control points on
// the skin and the spec that plans them.

#include <string>

namespace scanplan::bench {

struct DoorOptions {
  double width = 1200, height = 800;      // mm, the skin's extent in x and y
  int columns = 96, rows = 80;            // the grid of faces, before the window is cut out
  int points = 107;                       // control points on the skin
  double frame_gap = 10, frame_bar = 60;  // mm between skin and frame; width of its bars
  double marker_step = 15;                // mm between the frame's markers
  std::string scanner;                    // the spec's scanner mapping, "" for the default
};

struct DoorCase {
  std::string part, frame, points, spec;  // the files written
  int faces = 0;                          // of the skin
};

// Writes door.step, frame.step, points.csv and spec.yaml into `folder` (which exists).
DoorCase writeDoorCase(const std::string& folder, const DoorOptions& options = {});

}  // namespace scanplan::bench
