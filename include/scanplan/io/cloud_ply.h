#pragma once
// Simulated point clouds as PLY files.

#include <scanplan/cad/ply.h>
#include <scanplan/scanner/simulation.h>

#include <string>

namespace scanplan {

// A cloud as PLY: x y z nx ny nz (float), face (int), incidence (float, degrees).
PlyData cloudPly(const PointCloud& cloud);
// Writes cloudPly(cloud) as binary little-endian PLY through a temporary file renamed
// into place. \throw OutputError when the file cannot be written.
void writePly(const PointCloud& cloud, const std::string& path);
// Reads a cloud written by writePly. \throw InputError naming the file and what is wrong.
PointCloud readCloudPly(const std::string& path);

}  // namespace scanplan
