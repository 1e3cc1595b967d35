// Sweep positioning: surface grids (face parameters or an interpolated patch) and their
// tiling into field-of-view-sized tiles.

#include "cad/brep_model.h"

#include <scanplan/errors.h>
#include <scanplan/io/atomic_file.h>
#include <scanplan/raycast.h>
#include <scanplan/sweep.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IntCurvesFace_Intersector.hxx>
#include <Precision.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Lin.hxx>
#include <gp_Trsf.hxx>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <numeric>
#include <optional>

namespace scanplan {

namespace detail {
struct PatchSurface {
  Handle(Geom_BSplineSurface) surface;  // S(x, y) = (x, y, z(x, y)) in the patch frame
};
}  // namespace detail

namespace {

constexpr int kMaxGrid = 400;          // nodes per direction of a sweep grid
constexpr int kMaxFit = 120;           // fitted heights per direction of a patch
constexpr double kMaxTileSpread = 40;  // degrees between a tile's normals and its mean

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
  const double top = box.max.z() + 1;

  // Fitted heights: exact face heights on a regular grid, holes filled, then OCCT's
  // approximation z(x, y) within the tolerance.
  patch.nx = nodesFor(patch.x1 - patch.x0, spacing, kMaxFit);
  patch.ny = nodesFor(patch.y1 - patch.y0, spacing, kMaxFit);
  const int nx = patch.nx, ny = patch.ny;
  const double dx = (patch.x1 - patch.x0) / (nx - 1), dy = (patch.y1 - patch.y0) / (ny - 1);
  const RayCaster caster(mesh);
  std::vector<double> heights = faceHeights(part, caster, patch, top);
  const std::vector<double> exact = heights;
  fillHoles(heights, nx, ny);
  TColStd_Array2OfReal values(1, nx, 1, ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) values(i + 1, j + 1) = heights[i + nx * j];
  auto surface = std::make_shared<detail::PatchSurface>();
  try {
    GeomAPI_PointsToBSplineSurface fit;
    fit.Init(values, patch.x0, dx, patch.y0, dy, 3, 8, GeomAbs_C2, tolerance);
    if (!fit.IsDone()) throw LibraryError(part.file, "OCCT could not fit the interpolated patch");
    surface->surface = fit.Surface();
  } catch (const Standard_Failure& failure) {
    throw LibraryError(part.file, std::string("OCCT failed fitting the interpolated patch: ") +
                                      failure.GetMessageString());
  }
  patch.surface = surface;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      if (!std::isnan(exact[i + nx * j]))
        patch.max_deviation = std::max(
            patch.max_deviation,
            std::abs(patch.height(patch.x0 + i * dx, patch.y0 + j * dy) - exact[i + nx * j]));

  // The sweep grid: the patch evaluated, inside where a face lies under the node.
  SurfaceGrid& grid = patch.grid;
  grid.nu = nodesFor(patch.x1 - patch.x0, grid_spacing, kMaxGrid);
  grid.nv = nodesFor(patch.y1 - patch.y0, grid_spacing, kMaxGrid);
  for (int j = 0; j < grid.nv; ++j)
    for (int i = 0; i < grid.nu; ++i) {
      gp_Pnt p;
      gp_Vec du, dv;
      surface->surface->D1(patch.x0 + (patch.x1 - patch.x0) * i / (grid.nu - 1),
                           patch.y0 + (patch.y1 - patch.y0) * j / (grid.nv - 1), p, du, dv);
      const gp_Vec n = du.Crossed(dv);
      grid.points.push_back(patch.frame * Vec3(p.X(), p.Y(), p.Z()));
      grid.normals.push_back(patch.frame.linear() * Vec3(n.X(), n.Y(), n.Z()).normalized());
    }
  const auto hits = castDown(caster, patch, grid.nu, grid.nv, top).hits;
  for (const auto& hit : hits) grid.inside.push_back(hit.has_value());
  return patch;
}

void writePatch(const InterpolatedPatch& patch, const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  const bool step = extension == ".step" || extension == ".stp";
  if (!step && extension != ".brep")
    throw OutputError(path, "a patch is written as .step, .stp or .brep");
  // The patch restricted to the fitted cells with a corner over a face (so that it covers
  // the faces), one face per run of such cells along x, in the part frame.
  const int nx = patch.nx, ny = patch.ny;
  const double dx = (patch.x1 - patch.x0) / (nx - 1), dy = (patch.y1 - patch.y0) / (ny - 1);
  std::vector<char> over(static_cast<std::size_t>(nx) * ny, 0);
  {
    // A fitted node lies over a face when the nearest sweep-grid node does.
    const SurfaceGrid& g = patch.grid;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int gi =
            static_cast<int>(std::lround(static_cast<double>(i) * (g.nu - 1) / (nx - 1)));
        const int gj =
            static_cast<int>(std::lround(static_cast<double>(j) * (g.nv - 1) / (ny - 1)));
        over[i + nx * j] = g.inside[g.index(gi, gj)];
      }
  }
  gp_Trsf to_part;
  const Eigen::Matrix3d& r = patch.frame.linear();
  to_part.SetValues(r(0, 0), r(0, 1), r(0, 2), 0, r(1, 0), r(1, 1), r(1, 2), 0, r(2, 0), r(2, 1),
                    r(2, 2), 0);
  const Handle(Geom_Surface) surface =
      Handle(Geom_Surface)::DownCast(patch.surface->surface->Transformed(to_part));
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
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
      BRepBuilderAPI_MakeFace face(surface, patch.x0 + i * dx, patch.x0 + end * dx,
                                   patch.y0 + j * dy, patch.y0 + (j + 1) * dy,
                                   Precision::Confusion());
      if (face.IsDone()) builder.Add(compound, face.Face());
      i = end;
    }
  writeFileAtomically(path, [&](const std::string& temporary) {
    bool written = false;
    try {
      if (step) {
        STEPControl_Writer writer;
        written = writer.Transfer(compound, STEPControl_AsIs) == IFSelect_RetDone &&
                  writer.Write(temporary.c_str()) == IFSelect_RetDone;
      } else {
        written = BRepTools::Write(compound, temporary.c_str());
      }
    } catch (const Standard_Failure&) {
      written = false;
    }
    if (!written) throw OutputError(path, "cannot write the interpolated patch");
  });
}

namespace {

// Arc length along the first (u) or second parameter, averaged over the grid lines:
// result[i] is the mean length from node 0 to node i.
std::vector<double> meanArcLength(const SurfaceGrid& grid, bool along_u) {
  const int n = along_u ? grid.nu : grid.nv, lines = along_u ? grid.nv : grid.nu;
  std::vector<double> length(n, 0);
  for (int l = 0; l < lines; ++l) {
    double run = 0;
    for (int a = 1; a < n; ++a) {
      const std::size_t k0 = along_u ? grid.index(a - 1, l) : grid.index(l, a - 1);
      const std::size_t k1 = along_u ? grid.index(a, l) : grid.index(l, a);
      run += (grid.points[k1] - grid.points[k0]).norm();
      length[a] += run / lines;
    }
  }
  return length;
}

// Node boundaries of `count` tiles of equal mean arc length: tile t holds nodes
// [bounds[t], bounds[t + 1]).
std::vector<int> tileBounds(const std::vector<double>& length, int count) {
  const int n = static_cast<int>(length.size());
  std::vector<int> bounds = {0};
  for (int t = 1; t < count; ++t) {
    const double target = length.back() * t / count;
    const int b =
        static_cast<int>(std::lower_bound(length.begin(), length.end(), target) - length.begin());
    bounds.push_back(std::clamp(b, bounds.back() + 1, n - 1));
  }
  bounds.push_back(n);
  return bounds;
}

struct TileFit {
  double width = 0, height = 0, depth = 0;
  double spread = 0;          // largest angle between a node's normal and the tile's, degrees
  bool turns_along_u = true;  // the normals turn more along u than along v
};

// Fills the tile's frame and extents from its nodes; `along_u` when the field of view's
// width lies along the first parameter.
TileFit frameTile(const SurfaceGrid& grid, SweepTile& tile, bool along_u) {
  Vec3 normal = Vec3::Zero(), direction = Vec3::Zero();
  for (std::size_t k : tile.nodes) {
    normal += grid.normals[k];
    const int i = static_cast<int>(k % grid.nu), j = static_cast<int>(k / grid.nu);
    const int i1 = along_u ? std::min(i + 1, grid.nu - 1) : i,
              j1 = along_u ? j : std::min(j + 1, grid.nv - 1);
    const int i0 = along_u ? i1 - 1 : i, j0 = along_u ? j : j1 - 1;
    direction += grid.points[grid.index(i1, j1)] - grid.points[grid.index(i0, j0)];
  }
  tile.normal = normal.norm() > 1e-12 ? Vec3(normal.normalized()) : Vec3::UnitZ();
  Vec3 across = direction - direction.dot(tile.normal) * tile.normal;
  if (across.norm() < 1e-12) across = tile.normal.unitOrthogonal();
  tile.across = across.normalized();
  const Vec3 along = tile.normal.cross(tile.across);
  double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY, c0 = INFINITY,
         c1 = -INFINITY, mean_c = 0;
  for (std::size_t k : tile.nodes) {
    const Vec3& p = grid.points[k];
    const double a = p.dot(tile.across), b = p.dot(along), c = p.dot(tile.normal);
    a0 = std::min(a0, a), a1 = std::max(a1, a);
    b0 = std::min(b0, b), b1 = std::max(b1, b);
    c0 = std::min(c0, c), c1 = std::max(c1, c);
    mean_c += c / static_cast<double>(tile.nodes.size());
  }
  tile.width = a1 - a0;
  tile.height = b1 - b0;
  tile.centre = 0.5 * (a0 + a1) * tile.across + 0.5 * (b0 + b1) * along + mean_c * tile.normal;
  TileFit fit{tile.width, tile.height, c1 - c0};
  double turn_u = 0, turn_v = 0;
  for (std::size_t k : tile.nodes) {
    const Vec3& n = grid.normals[k];
    fit.spread =
        std::max(fit.spread, degrees(std::acos(std::clamp(n.dot(tile.normal), -1.0, 1.0))));
    const int i = static_cast<int>(k % grid.nu), j = static_cast<int>(k / grid.nu);
    if (i + 1 < grid.nu) turn_u += std::acos(std::clamp(n.dot(grid.normals[k + 1]), -1.0, 1.0));
    if (j + 1 < grid.nv)
      turn_v += std::acos(std::clamp(n.dot(grid.normals[k + grid.nu]), -1.0, 1.0));
  }
  fit.turns_along_u = turn_u >= turn_v;
  return fit;
}

}  // namespace

std::vector<SweepTile> sweepTiles(const SurfaceGrid& grid, const Scanner& scanner, double overlap) {
  if (grid.nu < 2 || grid.nv < 2) return {};
  const std::vector<double> length_u = meanArcLength(grid, true);
  const std::vector<double> length_v = meanArcLength(grid, false);
  const double w = scanner.fov_width * (1 - overlap), h = scanner.fov_height * (1 - overlap);
  auto count = [](double length, double size) {
    return std::max(1, static_cast<int>(std::ceil(length / size - 1e-9)));
  };
  // The field of view's width along u, or along v: whichever needs fewer tiles.
  const int wu = count(length_u.back(), w) * count(length_v.back(), h);
  const int wv = count(length_u.back(), h) * count(length_v.back(), w);
  const bool width_along_u = wu <= wv;
  int tiles_u = count(length_u.back(), width_along_u ? w : h);
  int tiles_v = count(length_v.back(), width_along_u ? h : w);
  constexpr int kMaxTiles = 4000;
  for (int round = 0;; ++round) {
    const std::vector<int> bu = tileBounds(length_u, std::min(tiles_u, grid.nu));
    const std::vector<int> bv = tileBounds(length_v, std::min(tiles_v, grid.nv));
    tiles_u = static_cast<int>(bu.size()) - 1;
    tiles_v = static_cast<int>(bv.size()) - 1;
    const bool rows_along_u = tiles_u >= tiles_v;
    const int rows = rows_along_u ? tiles_v : tiles_u, columns = rows_along_u ? tiles_u : tiles_v;
    std::vector<SweepTile> tiles;
    bool wide = false, tall = false;
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < columns; ++c) {
        const int column = r % 2 == 0 ? c : columns - 1 - c;
        const int tu = rows_along_u ? column : r, tv = rows_along_u ? r : column;
        SweepTile tile;
        tile.row = r;
        tile.column = column;
        for (int j = bv[tv]; j < bv[tv + 1]; ++j)
          for (int i = bu[tu]; i < bu[tu + 1]; ++i)
            if (grid.inside[grid.index(i, j)]) tile.nodes.push_back(grid.index(i, j));
        if (tile.nodes.empty()) continue;
        const TileFit fit = frameTile(grid, tile, width_along_u);
        wide = wide || fit.width > scanner.fov_width * (1 - overlap) * 1.02;
        tall = tall || fit.height > scanner.fov_height * (1 - overlap) * 1.02;
        // A tile deeper than the measuring volume is cut across its longer side; one whose
        // normals turn too far to be seen from one direction, across the turn.
        if (fit.depth > 0.8 * scanner.depth_of_field)
          (fit.width / scanner.fov_width >= fit.height / scanner.fov_height ? wide : tall) = true;
        if (fit.spread > kMaxTileSpread) (fit.turns_along_u == width_along_u ? wide : tall) = true;
        tiles.push_back(std::move(tile));
      }
    const bool can_grow = round < 30 && (tiles_u + 1) * (tiles_v + 1) <= kMaxTiles &&
                          (tiles_u < grid.nu - 1 || tiles_v < grid.nv - 1);
    if (!(wide || tall) || !can_grow) return tiles;
    // Cut more finely in the parameter direction that carries the extent too large.
    auto grow = [](int& n) { n += std::max(1, n / 4); };
    if (wide) grow(width_along_u ? tiles_u : tiles_v);
    if (tall) grow(width_along_u ? tiles_v : tiles_u);
  }
}

bool needsSweep(const std::vector<Vec3>& points, const Scanner& scanner) {
  if (points.size() < 2) return false;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) covariance += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  const Vec3 axis = solver.eigenvectors().col(2);  // largest spread
  double lo = INFINITY, hi = -INFINITY;
  for (const Vec3& p : points) {
    lo = std::min(lo, p.dot(axis));
    hi = std::max(hi, p.dot(axis));
  }
  return hi - lo >= 2 * scanner.fov_width;
}

}  // namespace scanplan
