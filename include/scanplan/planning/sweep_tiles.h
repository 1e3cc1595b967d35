#pragma once
// Sweep positioning (docs/sweep.md): a surface much larger than the field of view is cut
// along its parameters into tiles that fit the field of view with a set overlap, one view
// per tile, in boustrophedon order.

#include <scanplan/cad/patch.h>
#include <scanplan/scanner/sensor.h>

#include <vector>

namespace scanplan {

struct SweepTile {
  int row = 0, column = 0;         // position in the tiling; rows follow the sweep direction
  Vec3 centre = Vec3::Zero();      // middle of the tile's nodes in the tile frame, part frame
  Vec3 normal = Vec3::UnitZ();     // mean normal of its nodes
  Vec3 across = Vec3::UnitX();     // unit, perpendicular to the normal: the field of view's width
  double width = 0, height = 0;    // extent of its nodes across and along the normal's cross
  std::vector<std::size_t> nodes;  // grid nodes (inside ones) it holds
};

// Tiles of `grid` for `scanner`: the parameter ranges are cut into tiles whose inside
// nodes span at most (1 - overlap) of the field of view, the field of view's width laid
// along the parameter direction that needs fewer tiles, tiles with no inside node
// dropped; returned in boustrophedon order (row by row, alternating, rows along the
// direction with more tiles).
std::vector<SweepTile> sweepTiles(const SurfaceGrid& grid, const Scanner& scanner,
                                  double overlap = 0.3);

// True when points spread over at least twice the field of view's width along their
// principal direction (the samples extend over twice the field of view).
bool needsSweep(const std::vector<Vec3>& points, const Scanner& scanner);

}  // namespace scanplan
