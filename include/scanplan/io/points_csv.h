#pragma once
// Control points and markers as CSV: `x,y,z[,nx,ny,nz]` in mm, one point per line, an
// optional header line, blank lines and lines starting with '#' ignored.

#include <scanplan/core/tasks.h>
#include <scanplan/registration/registration.h>

#include <string>
#include <vector>

namespace scanplan {

// \throw InputError naming the file and line of a malformed entry, a zero normal, or an
//        empty or missing file.
std::vector<ControlPoint> readPointsCsv(const std::string& path);

// Markers from a CSV of `x,y,z[,nx,ny,nz]` in the world frame; without
// a normal a marker faces up. \throw InputError naming the file and line.
std::vector<Marker> readMarkers(const std::string& path);

// Writes markers as readMarkers reads them (with a header and normals), whole or not at
// all. \throw OutputError naming the file.
void writeMarkers(const std::vector<Marker>& markers, const std::string& path);

}  // namespace scanplan
