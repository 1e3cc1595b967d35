#pragma once
// Views as CSV, for spreadsheets and cell software: one line per view,
// `id,m00,m01,m02,m03,m10,...,m33,target_x,target_y,target_z,task` under a header line;
// m is camera_to_world (scanner frame S to world, docs/design.md §3), row-major, mm.

#include <scanplan/view.h>

#include <string>
#include <vector>

namespace scanplan {

// \throw OutputError when the file cannot be written.
void writeViewsCsv(const std::vector<View>& views, const std::string& path);

// Reads what writeViewsCsv writes. \throw InputError naming the file and line of a
// malformed row or a matrix that is not rigid.
std::vector<View> readViewsCsv(const std::string& path);

}  // namespace scanplan
