#pragma once
// Surfaces a sweep is laid over (docs/sweep.md): a face's own (u, v) on a grid, or, for the
// `surface` task, an interpolated patch over a set of faces.

#include <scanplan/cad/part.h>
#include <scanplan/core/view.h>

#include <array>
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
struct PatchSurface;  // the OCCT B-spline surface
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
  std::shared_ptr<const detail::PatchSurface> surface;  // defined in src/cad/patch_surface.h

  // Height of the patch above (x, y) of its frame, mm.
  double height(double x, double y) const;
};

// Fits the patch of `faces` with heights `spacing` mm apart (at most 120 per direction)
// and evaluates it on a sweep grid `grid_spacing` mm apart. \throw InputError for a
// mesh part, no faces, or faces that cannot be seen along a common direction;
// LibraryError when OCCT's fit fails.
InterpolatedPatch interpolatedPatch(const Part& part, const std::vector<int>& faces, double spacing,
                                    double grid_spacing, double tolerance = 0.05);

// A B-spline surface as the numbers OCCT's Geom_BSplineSurface is made of, part frame, mm.
struct BSplineSurface {
  int u_degree = 0, v_degree = 0;
  std::vector<double> u_knots, v_knots;
  std::vector<int> u_multiplicities, v_multiplicities;
  int u_poles = 0, v_poles = 0;
  std::vector<Vec3> poles;      // pole (i, j) at index i + u_poles * j
  std::vector<double> weights;  // per pole, as the poles; empty when not rational
};

// An interpolated patch as plain data, to be written as a file: its surface in the part
// frame, and the parameter rectangles {x0, x1, y0, y1} of its faces: the fitted cells with a
// corner over a face, one face per run of such cells along x.
struct PatchShape {
  BSplineSurface surface;
  std::vector<std::array<double, 4>> faces;
};
PatchShape patchShape(const InterpolatedPatch& patch);

}  // namespace scanplan
