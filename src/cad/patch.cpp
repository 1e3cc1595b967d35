// Surface grids over a face's parameters or an interpolated patch, and the patch itself.

#include "cad/brep_model.h"
#include "cad/patch_surface.h"

#include <scanplan/cad/patch.h>
#include <scanplan/cad/raycast.h>
#include <scanplan/core/errors.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IntCurvesFace_Intersector.hxx>
#include <Precision.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Lin.hxx>
#include <gp_Trsf.hxx>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <optional>

namespace scanplan {

namespace {

constexpr int kMaxGrid = 400;  // nodes per direction of a sweep grid
constexpr int kMaxFit = 120;   // fitted heights per direction of a patch

int nodesFor(double length, double spacing, int most) {
  return std::clamp(static_cast<int>(std::ceil(length / spacing)) + 1, 2, most);
}

}  // namespace

SurfaceGrid faceGrid(const Part& part, int id, double spacing) {
  part.face(id);
  if (!part.brep)
    throw InputError(part.file, "face " + std::to_string(id) +
                                    " has no parameters to sweep along: the part is a mesh");
  const TopoDS_Face face = part.brep->outwardFace(id);
  const BRepAdaptor_Surface surface(face);
  const BRepTopAdaptor_FClass2d classifier(face, 1e-7);
  double u0 = 0, u1 = 1, v0 = 0, v1 = 1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  auto point = [&](double u, double v) {
    const gp_Pnt p = surface.Value(u, v);
    return Vec3(p.X(), p.Y(), p.Z());
  };
  // The longest iso-line in each direction sets the node counts.
  constexpr int kProbe = 17;
  double length_u = 0, length_v = 0;
  for (int a = 0; a < kProbe; ++a) {
    double lu = 0, lv = 0;
    const double fa = static_cast<double>(a) / (kProbe - 1);
    for (int b = 0; b + 1 < kProbe; ++b) {
      const double f0 = static_cast<double>(b) / (kProbe - 1),
                   f1 = static_cast<double>(b + 1) / (kProbe - 1);
      lu += (point(u0 + f1 * (u1 - u0), v0 + fa * (v1 - v0)) -
             point(u0 + f0 * (u1 - u0), v0 + fa * (v1 - v0)))
                .norm();
      lv += (point(u0 + fa * (u1 - u0), v0 + f1 * (v1 - v0)) -
             point(u0 + fa * (u1 - u0), v0 + f0 * (v1 - v0)))
                .norm();
    }
    length_u = std::max(length_u, lu);
    length_v = std::max(length_v, lv);
  }
  SurfaceGrid grid;
  grid.nu = nodesFor(length_u, spacing, kMaxGrid);
  grid.nv = nodesFor(length_v, spacing, kMaxGrid);
  const std::size_t n = static_cast<std::size_t>(grid.nu) * grid.nv;
  grid.points.resize(n);
  grid.normals.resize(n, Vec3::UnitZ());
  grid.inside.resize(n, 0);
  for (int j = 0; j < grid.nv; ++j)
    for (int i = 0; i < grid.nu; ++i) {
      const double u = u0 + (u1 - u0) * i / (grid.nu - 1), v = v0 + (v1 - v0) * j / (grid.nv - 1);
      gp_Pnt p;
      gp_Vec du, dv;
      surface.D1(u, v, p, du, dv);
      gp_Vec normal = du.Crossed(dv);
      const std::size_t k = grid.index(i, j);
      grid.points[k] = Vec3(p.X(), p.Y(), p.Z());
      if (normal.Magnitude() < 1e-12) continue;  // a pole: no normal
      if (face.Orientation() == TopAbs_REVERSED) normal.Reverse();
      normal.Normalize();
      grid.normals[k] = Vec3(normal.X(), normal.Y(), normal.Z());
      grid.inside[k] = classifier.Perform(gp_Pnt2d(u, v)) != TopAbs_OUT;
    }
  return grid;
}

std::vector<std::vector<int>> segmentByNormal(const Part& part, const std::vector<int>& faces,
                                              double max_angle) {
  // Per face: its area-weighted normal sum and a few of its triangle normals.
  struct FaceNormals {
    int id = 0;
    double area = 0;
    Vec3 sum = Vec3::Zero();
    std::vector<Vec3> normals;
  };
  std::vector<FaceNormals> info;
  for (int id : faces) {
    const Face& face = part.face(id);
    FaceNormals f;
    f.id = id;
    f.area = face.area;
    const int stride = std::max(1, face.triangle_count / 64);
    for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
      const Vec3 normal = part.mesh.normal(t);
      f.sum += part.mesh.area(t) * normal;
      if ((t - face.first_triangle) % stride == 0 && !normal.isZero()) f.normals.push_back(normal);
    }
    info.push_back(std::move(f));
  }
  std::stable_sort(info.begin(), info.end(),
                   [](const FaceNormals& a, const FaceNormals& b) { return a.area > b.area; });
  const double min_cos = std::cos(radians(max_angle));
  std::vector<char> used(info.size(), 0);
  std::vector<std::vector<int>> sets;
  for (std::size_t seed = 0; seed < info.size(); ++seed) {
    if (used[seed]) continue;
    used[seed] = 1;
    std::vector<int> set = {info[seed].id};
    Vec3 sum = info[seed].sum;
    std::vector<Vec3> normals = info[seed].normals;
    for (std::size_t f = seed + 1; f < info.size(); ++f) {
      if (used[f]) continue;
      const Vec3 grown = sum + info[f].sum;
      if (grown.norm() < 1e-12) continue;
      const Vec3 direction = grown.normalized();
      auto within = [&](const Vec3& n) { return n.dot(direction) >= min_cos; };
      if (!std::all_of(normals.begin(), normals.end(), within) ||
          !std::all_of(info[f].normals.begin(), info[f].normals.end(), within))
        continue;
      used[f] = 1;
      set.push_back(info[f].id);
      sum = grown;
      normals.insert(normals.end(), info[f].normals.begin(), info[f].normals.end());
    }
    std::sort(set.begin(), set.end());
    sets.push_back(std::move(set));
  }
  return sets;
}

double normalSpread(const Part& part, const std::vector<int>& faces) {
  Vec3 sum = Vec3::Zero();
  for (int id : faces) {
    const Face& face = part.face(id);
    for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t)
      sum += part.mesh.area(t) * part.mesh.normal(t);
  }
  if (sum.norm() < 1e-9 * std::max(1.0, part.area())) return 180;
  const Vec3 mean = sum.normalized();
  double spread = 0;
  for (int id : faces) {
    const Face& face = part.face(id);
    for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
      const Vec3 n = part.mesh.normal(t);
      if (!n.isZero())
        spread = std::max(spread, degrees(std::acos(std::clamp(n.dot(mean), -1.0, 1.0))));
    }
  }
  return spread;
}

double InterpolatedPatch::height(double x, double y) const {
  return surface->surface->Value(x, y).Z();
}

namespace {

// The points (x, y) of an nx x ny grid over the patch's extent, nudged inwards at the
// border so that faces ending there are hit, and the closest hits of rays cast down onto
// the faces along z from height `top`.
struct DownHits {
  std::vector<Eigen::Vector2d> xy;
  std::vector<Ray> rays;
  std::vector<std::optional<RayHit>> hits;
};
DownHits castDown(const RayCaster& caster, const InterpolatedPatch& patch, int nx, int ny,
                  double top) {
  const Vec3 down = -patch.frame.linear().col(2);
  const double nudge_x = 1e-4 * (patch.x1 - patch.x0), nudge_y = 1e-4 * (patch.y1 - patch.y0);
  DownHits result;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = std::clamp(patch.x0 + (patch.x1 - patch.x0) * i / (nx - 1),
                                  patch.x0 + nudge_x, patch.x1 - nudge_x);
      const double y = std::clamp(patch.y0 + (patch.y1 - patch.y0) * j / (ny - 1),
                                  patch.y0 + nudge_y, patch.y1 - nudge_y);
      result.xy.emplace_back(x, y);
      result.rays.push_back(Ray{patch.frame * Vec3(x, y, top), down});
    }
  result.hits = caster.intersect(result.rays);
  return result;
}

// The exact heights of the hit faces under the rays of `cast` (B-Rep), and where they are:
// on which face and at which (u, v).
void exactHeights(const Part& part, const DownHits& cast, const Vec3& down, double top,
                  std::vector<double>& heights, std::vector<int>& face, std::vector<gp_Pnt2d>& uv) {
  const std::vector<Ray>& rays = cast.rays;
  const std::vector<std::optional<RayHit>>& hits = cast.hits;
  std::map<int, std::unique_ptr<IntCurvesFace_Intersector>> intersectors;
  for (std::size_t k = 0; k < rays.size(); ++k) {
    if (!hits[k]) continue;
    auto& intersector = intersectors[hits[k]->face];
    if (!intersector)
      intersector = std::make_unique<IntCurvesFace_Intersector>(
          part.brep->outwardFace(hits[k]->face), Precision::Confusion());
    const Vec3& o = rays[k].origin;
    intersector->Perform(gp_Lin(gp_Pnt(o.x(), o.y(), o.z()), gp_Dir(down.x(), down.y(), down.z())),
                         0, 2 * hits[k]->t + 1);
    if (!intersector->IsDone()) continue;
    int best = 0;
    for (int p = 1; p <= intersector->NbPnt(); ++p)
      if (best == 0 || std::abs(intersector->WParameter(p) - hits[k]->t) <
                           std::abs(intersector->WParameter(best) - hits[k]->t))
        best = p;
    if (best == 0) continue;
    heights[k] = top - intersector->WParameter(best);
    face[k] = hits[k]->face;
    uv[k] = gp_Pnt2d(intersector->UParameter(best), intersector->VParameter(best));
  }
}

// Heights of `faces` (cast onto by `caster`) seen from above along z of the patch frame,
// on the patch's nx x ny fitting grid: the exact intersection with the hit face (B-Rep),
// else the mesh hit. NaN where no face lies under the node. On a B-Rep, nodes within two
// nodes of a hit continue the neighbouring face's surface past its trims.
std::vector<double> faceHeights(const Part& part, const RayCaster& caster,
                                const InterpolatedPatch& patch, double top) {
  const Vec3 down = -patch.frame.linear().col(2);
  const int nx = patch.nx, ny = patch.ny;
  const DownHits cast = castDown(caster, patch, nx, ny, top);
  const std::vector<Eigen::Vector2d>& xy = cast.xy;
  const std::vector<Ray>& rays = cast.rays;
  const std::vector<std::optional<RayHit>>& hits = cast.hits;
  std::vector<double> heights(rays.size(), std::nan(""));
  for (std::size_t k = 0; k < rays.size(); ++k)
    if (hits[k]) heights[k] = top - hits[k]->t;
  if (!part.brep) return heights;

  // Exact heights, and where they are, on which face and at which (u, v).
  std::vector<int> face(rays.size(), 0);
  std::vector<gp_Pnt2d> uv(rays.size());
  exactHeights(part, cast, down, top, heights, face, uv);

  // Continuation past the trims: Newton on (x, y) of the neighbour face's surface.
  const Pose to_patch = patch.frame.inverse();
  std::map<int, Handle(Geom_Surface)> surfaces;
  auto extend = [&](std::size_t k, std::size_t from) {
    Handle(Geom_Surface)& surface = surfaces[face[from]];
    if (surface.IsNull()) surface = BRep_Tool::Surface(part.brep->outwardFace(face[from]));
    double u = uv[from].X(), v = uv[from].Y();
    for (int iteration = 0; iteration < 20; ++iteration) {
      gp_Pnt p;
      gp_Vec du, dv;
      surface->D1(u, v, p, du, dv);
      const Vec3 q = to_patch * Vec3(p.X(), p.Y(), p.Z());
      const Vec3 qu = to_patch.linear() * Vec3(du.X(), du.Y(), du.Z());
      const Vec3 qv = to_patch.linear() * Vec3(dv.X(), dv.Y(), dv.Z());
      const Eigen::Vector2d residual = q.head<2>() - xy[k];
      if (residual.norm() < 1e-7) {
        heights[k] = q.z();
        face[k] = face[from];
        uv[k] = gp_Pnt2d(u, v);
        return;
      }
      Eigen::Matrix2d jacobian;
      jacobian << qu.x(), qv.x(), qu.y(), qv.y();
      if (std::abs(jacobian.determinant()) < 1e-12) return;
      const Eigen::Vector2d step = jacobian.inverse() * residual;
      u -= step.x();
      v -= step.y();
    }
  };
  for (int ring = 0; ring < 2; ++ring) {
    const std::vector<int> known = face;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::size_t k = static_cast<std::size_t>(i + nx * j);
        if (!std::isnan(heights[k])) continue;
        for (const auto& [a, b] : {std::pair{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}})
          if (a >= 0 && b >= 0 && a < nx && b < ny && known[a + nx * b]) {
            extend(k, static_cast<std::size_t>(a + nx * b));
            break;
          }
      }
  }
  return heights;
}

// Fills the NaN heights from their neighbours, nearest first (a breadth-first wave): each
// new node takes the mean of the linear extrapolations (2 z1 - z2) along the directions
// where two known nodes line up, or of its known neighbours' heights where none do.
void fillHoles(std::vector<double>& z, int nx, int ny) {
  auto known = [&](int i, int j) {
    return i >= 0 && j >= 0 && i < nx && j < ny && !std::isnan(z[i + nx * j]);
  };
  std::vector<std::size_t> front;
  for (std::size_t k = 0; k < z.size(); ++k)
    if (!std::isnan(z[k])) front.push_back(k);
  const int di[] = {1, -1, 0, 0}, dj[] = {0, 0, 1, -1};
  while (!front.empty()) {
    std::vector<std::size_t> next;
    std::vector<char> queued(z.size(), 0);
    for (std::size_t k : front) {
      const int i = static_cast<int>(k % nx), j = static_cast<int>(k / nx);
      for (int d = 0; d < 4; ++d) {
        const int a = i + di[d], b = j + dj[d];
        if (a < 0 || b < 0 || a >= nx || b >= ny || known(a, b) || queued[a + nx * b]) continue;
        queued[a + nx * b] = 1;
        next.push_back(static_cast<std::size_t>(a + nx * b));
      }
    }
    std::vector<double> values;
    for (std::size_t m : next) {
      const int i = static_cast<int>(m % nx), j = static_cast<int>(m / nx);
      double linear = 0, nearest = 0;
      int linear_count = 0, nearest_count = 0;
      for (int d = 0; d < 4; ++d) {
        const int a = i + di[d], b = j + dj[d];
        if (!known(a, b)) continue;
        nearest += z[a + nx * b];
        ++nearest_count;
        if (known(a + di[d], b + dj[d])) {
          linear += 2 * z[a + nx * b] - z[a + di[d] + nx * (b + dj[d])];
          ++linear_count;
        }
      }
      values.push_back(linear_count ? linear / linear_count : nearest / nearest_count);
    }
    for (std::size_t n = 0; n < next.size(); ++n) z[next[n]] = values[n];
    front = std::move(next);
  }
}

// The patch's frame (z the faces' area-weighted mean normal, x along the world's x where it
// can) and its extent in x and y; the height above the mesh's highest point, returned.
double placePatch(const Part& part, const TriangleMesh& mesh, InterpolatedPatch& patch) {
  Vec3 sum = Vec3::Zero();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) sum += mesh.area(t) * mesh.normal(t);
  if (sum.norm() < 1e-9 * std::max(1.0, part.area()))
    throw InputError(part.file, "faces of the patch face no common direction");
  const Vec3 z = sum.normalized();
  Vec3 x = Vec3::UnitX() - Vec3::UnitX().dot(z) * z;
  if (x.norm() < 0.1) x = Vec3::UnitY() - Vec3::UnitY().dot(z) * z;
  x.normalize();
  patch.frame.linear().col(0) = x;
  patch.frame.linear().col(1) = z.cross(x);
  patch.frame.linear().col(2) = z;
  const Pose to_patch = patch.frame.inverse();
  Box box;
  for (const Vec3& v : mesh.vertices) box.add(to_patch * v);
  patch.x0 = box.min.x();
  patch.y0 = box.min.y();
  patch.x1 = box.max.x();
  patch.y1 = box.max.y();
  return box.max.z() + 1;
}

// OCCT's approximation z(x, y) within `tolerance` of the heights on the patch's nx x ny
// grid, its holes filled first.
std::shared_ptr<detail::PatchSurface> fittedSurface(const Part& part,
                                                    const InterpolatedPatch& patch,
                                                    std::vector<double> heights, double tolerance) {
  const int nx = patch.nx, ny = patch.ny;
  fillHoles(heights, nx, ny);
  TColStd_Array2OfReal values(1, nx, 1, ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) values(i + 1, j + 1) = heights[i + nx * j];
  auto surface = std::make_shared<detail::PatchSurface>();
  try {
    GeomAPI_PointsToBSplineSurface fit;
    fit.Init(values, patch.x0, (patch.x1 - patch.x0) / (nx - 1), patch.y0,
             (patch.y1 - patch.y0) / (ny - 1), 3, 8, GeomAbs_C2, tolerance);
    if (!fit.IsDone()) throw LibraryError(part.file, "OCCT could not fit the interpolated patch");
    surface->surface = fit.Surface();
  } catch (const Standard_Failure& failure) {
    throw LibraryError(part.file, std::string("OCCT failed fitting the interpolated patch: ") +
                                      failure.GetMessageString());
  }
  return surface;
}

// The sweep grid: the patch's surface evaluated `grid_spacing` apart, inside where a face
// lies under the node.
SurfaceGrid sweepGrid(const InterpolatedPatch& patch, const Handle(Geom_Surface) & surface,
                      const RayCaster& caster, double grid_spacing, double top) {
  SurfaceGrid grid;
  grid.nu = nodesFor(patch.x1 - patch.x0, grid_spacing, kMaxGrid);
  grid.nv = nodesFor(patch.y1 - patch.y0, grid_spacing, kMaxGrid);
  for (int j = 0; j < grid.nv; ++j)
    for (int i = 0; i < grid.nu; ++i) {
      gp_Pnt p;
      gp_Vec du, dv;
      surface->D1(patch.x0 + (patch.x1 - patch.x0) * i / (grid.nu - 1),
                  patch.y0 + (patch.y1 - patch.y0) * j / (grid.nv - 1), p, du, dv);
      const gp_Vec n = du.Crossed(dv);
      grid.points.push_back(patch.frame * Vec3(p.X(), p.Y(), p.Z()));
      grid.normals.push_back(patch.frame.linear() * Vec3(n.X(), n.Y(), n.Z()).normalized());
    }
  const auto hits = castDown(caster, patch, grid.nu, grid.nv, top).hits;
  for (const auto& hit : hits) grid.inside.push_back(hit.has_value());
  return grid;
}

}  // namespace

InterpolatedPatch interpolatedPatch(const Part& part, const std::vector<int>& faces, double spacing,
                                    double grid_spacing, double tolerance) {
  if (faces.empty()) throw InputError(part.file, "an interpolated patch needs faces");
  if (!(spacing > 0) || !(grid_spacing > 0) || !(tolerance > 0))
    throw InputError(part.file, "patch spacing and tolerance must be positive");
  InterpolatedPatch patch;
  patch.faces = faces;
  patch.tolerance = tolerance;
  const TriangleMesh mesh = part.meshOf(faces);
  const double top = placePatch(part, mesh, patch);

  // Fitted heights: exact face heights on a regular grid, holes filled, then OCCT's
  // approximation z(x, y) within the tolerance.
  patch.nx = nodesFor(patch.x1 - patch.x0, spacing, kMaxFit);
  patch.ny = nodesFor(patch.y1 - patch.y0, spacing, kMaxFit);
  const int nx = patch.nx, ny = patch.ny;
  const double dx = (patch.x1 - patch.x0) / (nx - 1), dy = (patch.y1 - patch.y0) / (ny - 1);
  const RayCaster caster(mesh);
  const std::vector<double> exact = faceHeights(part, caster, patch, top);
  const std::shared_ptr<detail::PatchSurface> surface =
      fittedSurface(part, patch, exact, tolerance);
  patch.surface = surface;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      if (!std::isnan(exact[i + nx * j]))
        patch.max_deviation = std::max(
            patch.max_deviation,
            std::abs(patch.height(patch.x0 + i * dx, patch.y0 + j * dy) - exact[i + nx * j]));
  patch.grid = sweepGrid(patch, surface->surface, caster, grid_spacing, top);
  return patch;
}

namespace {

// Which fitted nodes of `patch` lie over a face: those whose nearest sweep-grid node does.
std::vector<char> nodesOverFaces(const InterpolatedPatch& patch) {
  const int nx = patch.nx, ny = patch.ny;
  std::vector<char> over(static_cast<std::size_t>(nx) * ny, 0);
  const SurfaceGrid& g = patch.grid;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int gi = static_cast<int>(std::lround(static_cast<double>(i) * (g.nu - 1) / (nx - 1)));
      const int gj = static_cast<int>(std::lround(static_cast<double>(j) * (g.nv - 1) / (ny - 1)));
      over[i + nx * j] = g.inside[g.index(gi, gj)];
    }
  return over;
}

BSplineSurface bsplineData(const Geom_BSplineSurface& s) {
  BSplineSurface data;
  data.u_degree = s.UDegree();
  data.v_degree = s.VDegree();
  for (int i = 1; i <= s.NbUKnots(); ++i) {
    data.u_knots.push_back(s.UKnot(i));
    data.u_multiplicities.push_back(s.UMultiplicity(i));
  }
  for (int j = 1; j <= s.NbVKnots(); ++j) {
    data.v_knots.push_back(s.VKnot(j));
    data.v_multiplicities.push_back(s.VMultiplicity(j));
  }
  data.u_poles = s.NbUPoles();
  data.v_poles = s.NbVPoles();
  const bool rational = s.IsURational() || s.IsVRational();
  for (int j = 1; j <= data.v_poles; ++j)
    for (int i = 1; i <= data.u_poles; ++i) {
      const gp_Pnt p = s.Pole(i, j);
      data.poles.emplace_back(p.X(), p.Y(), p.Z());
      if (rational) data.weights.push_back(s.Weight(i, j));
    }
  return data;
}

}  // namespace

PatchShape patchShape(const InterpolatedPatch& patch) {
  gp_Trsf to_part;
  const Eigen::Matrix3d& r = patch.frame.linear();
  to_part.SetValues(r(0, 0), r(0, 1), r(0, 2), 0, r(1, 0), r(1, 1), r(1, 2), 0, r(2, 0), r(2, 1),
                    r(2, 2), 0);
  const Handle(Geom_BSplineSurface) surface =
      Handle(Geom_BSplineSurface)::DownCast(patch.surface->surface->Transformed(to_part));
  PatchShape shape;
  shape.surface = bsplineData(*surface);
  const int nx = patch.nx, ny = patch.ny;
  const double dx = (patch.x1 - patch.x0) / (nx - 1), dy = (patch.y1 - patch.y0) / (ny - 1);
  const std::vector<char> over = nodesOverFaces(patch);
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx;) {
      auto cell = [&](int a) {
        return over[a + nx * j] || over[a + 1 + nx * j] || over[a + nx * (j + 1)] ||
               over[a + 1 + nx * (j + 1)];
      };
      if (!cell(i)) {
        ++i;
        continue;
      }
      int end = i;
      while (end + 1 < nx && cell(end)) ++end;
      shape.faces.push_back(
          {patch.x0 + i * dx, patch.x0 + end * dx, patch.y0 + j * dy, patch.y0 + (j + 1) * dy});
      i = end;
    }
  return shape;
}

}  // namespace scanplan
