#pragma once
// Sweep positioning (docs/sweep.md): a surface much larger than the field of view is cut
// along its parameters into tiles that fit the field of view with a set overlap, one view
// per tile, in boustrophedon order. The surface is a face's own (u, v), or, for the
// `surface` task, an interpolated patch over a set of faces.

#include <scanplan/cad/part.h>
#include <scanplan/sensor.h>
#include <scanplan/view.h>

#include <memory>
#include <string>
#include <vector>

namespace scanplan {

// A surface evaluated on a regular grid of its two parameters, part frame. Node (i, j),
// i along the first parameter, is at index i + nu * j.
struct SurfaceGrid {
  int nu = 0, nv = 0;
  std::vector<Vec3> points;
  std::vector<Vec3> normals;  // unit, outward
  std::vector<char> inside;   // the node lies on the face (within its trims), or over a face

  std::size_t index(int i, int j) const { return static_cast<std::size_t>(i + nu * j); }
};

// Face `face` of a B-Rep part on a grid of its (u, v) bounds, about `spacing` mm apart
// along the surface (at most 400 nodes per direction). \throw InputError for a mesh part
// or an unknown face.
SurfaceGrid faceGrid(const Part& part, int face, double spacing);

// Faces split into sets whose triangle normals all lie within `max_angle` degrees of the
// set's area-weighted mean direction, grown by direction alone from the largest face not
// yet taken; a face that turns further than that on its own forms a set alone.
std::vector<std::vector<int>> segmentByNormal(const Part& part, const std::vector<int>& faces,
                                              double max_angle = 80);

// Largest angle, degrees, between a triangle normal of `faces` and their area-weighted
// mean normal; 180 when the normals cancel out (a closed cylinder).
double normalSpread(const Part& part, const std::vector<int>& faces);

namespace detail {
struct PatchSurface;  // the OCCT B-spline surface, defined in src/sweep.cpp
}

// A B-spline patch z(x, y) fitted over a set of faces seen along their mean direction
// (GeomAPI_PointsToBSplineSurface through the faces' exact heights on a grid spanning
// their extent; nodes over no face, in holes or beyond a curved outline, are extrapolated
// linearly from their neighbours), trimmed to where it lies over a face.
struct InterpolatedPatch {
  std::vector<int> faces;
  Pose frame = Pose::Identity();          // patch frame in the part frame: z is the mean direction
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // extent of the faces in the patch frame, mm
  int nx = 0, ny = 0;                     // fitted heights per direction, evenly over the extent
  double tolerance = 0;                   // approximation tolerance asked of the fit, mm
  double max_deviation = 0;               // largest |patch - face| height over the fitted nodes, mm
  SurfaceGrid grid;  // the patch on the sweep grid; inside = over one of the faces
  std::shared_ptr<const detail::PatchSurface> surface;

  // Height of the patch above (x, y) of its frame, mm.
  double height(double x, double y) const;
};

// Fits the patch of `faces` with heights `spacing` mm apart (at most 120 per direction)
// and evaluates it on a sweep grid `grid_spacing` mm apart. \throw InputError for a
// mesh part, no faces, or faces that cannot be seen along a common direction;
// LibraryError when OCCT's fit fails.
InterpolatedPatch interpolatedPatch(const Part& part, const std::vector<int>& faces, double spacing,
                                    double grid_spacing, double tolerance = 0.05);

// Writes the patch trimmed to the fitted cells with a corner over a face, as STEP (.step, .stp) or
// BREP
// (.brep), in the part frame. \throw OutputError when the file cannot be written or its
// extension is neither.
void writePatch(const InterpolatedPatch& patch, const std::string& path);

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
