#pragma once
// Views as CSV, for spreadsheets and cell software: one line per view, in the order the
// cell takes them, `sequence,id,m00,m01,m02,m03,m10,...,m33,target_x,target_y,target_z,task`
// under a header line; sequence counts from 1; m is camera_to_world (scanner frame S to
// world, docs/design.md §3), row-major, mm.

#include <scanplan/core/view.h>

#include <string>
#include <vector>

namespace scanplan {

// `views` in the order the cell takes them (visitingOrder). \throw OutputError when the
// file cannot be written.
void writeViewsCsv(const std::vector<View>& views, const std::string& path);

// Reads what writeViewsCsv writes, in its order (also files without the sequence column). \throw
// InputError naming the file and line of a malformed row or a matrix that is not rigid.
std::vector<View> readViewsCsv(const std::string& path);

}  // namespace scanplan
