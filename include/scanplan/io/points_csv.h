#pragma once
// Control points and markers as CSV: `x,y,z[,nx,ny,nz]` in mm, one point per line, an
// optional header line, blank lines and lines starting with '#' ignored.

#include <scanplan/geometry.h>

#include <optional>
#include <string>
#include <vector>

namespace scanplan {

struct ControlPoint {
  Vec3 position = Vec3::Zero();  // mm, part frame
  std::optional<Vec3> normal;    // unit when given
  int line = 0;                  // line in the file, for messages
};

// \throw InputError naming the file and line of a malformed entry, a zero normal, or an
//        empty or missing file.
std::vector<ControlPoint> readPointsCsv(const std::string& path);

}  // namespace scanplan
