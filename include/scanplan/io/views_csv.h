#pragma once
// Views as CSV, for spreadsheets and cell software: one line per view, in the order the
// cell takes them,
// `sequence,id,m00,m01,m02,m03,m10,...,m33,target_x,target_y,target_z,task,setup` under a
// header line; sequence counts from 1; m is camera_to_world (scanner frame S to world,
// docs/design.md §3), row-major, mm; setup is the rest orientation the view is taken in,
// from 1 (Plan::orientations; 1 for a plan with one placement).

#include <scanplan/core/view.h>

#include <string>
#include <vector>

namespace scanplan {

// `views` in the order the cell takes them (visitingOrder), each in the setup of the same
// place in `setups` (1 for all when it is empty). \throw OutputError when the file cannot
// be written.
void writeViewsCsv(const std::vector<View>& views, const std::string& path,
                   const std::vector<std::size_t>& setups = {});

// Reads what writeViewsCsv writes, in its order (also files without the sequence or the
// setup column). \throw
// InputError naming the file and line of a malformed row or a matrix that is not rigid.
std::vector<View> readViewsCsv(const std::string& path);

}  // namespace scanplan
