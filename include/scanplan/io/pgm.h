#pragma once
// A visibility map as a PGM image.

#include <scanplan/scanner/visibility.h>

#include <string>

namespace scanplan {

// Writes the map as a binary PGM image (azimuth across, elevation up), grey levels
// scaled to the largest count. \throw OutputError when it cannot be written.
void writePgm(const VisibilityMap& map, const std::string& path);

}  // namespace scanplan
