#pragma once
// Views as CSV, for spreadsheets and cell software (docs/report.md, "Views as CSV"): one
// line per view, in the order the cell takes them, under a header line:
//   sequence,id,m00,m01,...,m33,target_x,target_y,target_z,task,setup,frame,
//   tcp_x,tcp_y,tcp_z,tcp_a,tcp_b,tcp_c,tcp_qw,tcp_qx,tcp_qy,tcp_qz
// - sequence counts from 1; m is camera_to_world (scanner frame S to the frame, docs/
//   design.md §3), row-major, mm;
// - setup is the rest orientation the view is taken in, from 1 (Plan::orientations; 1 for
//   a plan with one placement); frame names the frame of every pose (`cad` or `world`);
// - the TCP is the centre of the measuring volume, the standoff along the camera's axis,
//   turned as the camera: its position, its A, B, C (degrees, r = Rz(A) Ry(B) Rx(C), as
//   KUKA's) and its unit quaternion (w, x, y, z, w >= 0, as ABB's).

#include <scanplan/core/view.h>

#include <string>
#include <vector>

namespace scanplan {

struct ViewsCsv {
  std::vector<View> views;          // in the order the cell takes them (visitingOrder)
  std::vector<std::size_t> setups;  // per view; 1 for all when empty
  std::string frame = "world";      // the frame the poses are given in
  double standoff = 0;              // the scanner's: camera to measuring-volume centre, mm
};

// \throw OutputError when the file cannot be written.
void writeViewsCsv(const ViewsCsv& csv, const std::string& path);

// The views of what writeViewsCsv writes, in its order, by the header's column names: the
// id, the matrix, the target and the task, with the sequence and the setup checked where
// there are such columns; the others are not read.
// \throw InputError naming the file and line of a malformed row or a matrix that is not
//        rigid, or a header without those columns.
std::vector<View> readViewsCsv(const std::string& path);

}  // namespace scanplan
