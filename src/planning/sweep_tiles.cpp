// Sweep positioning (docs/sweep.md): a surface grid cut into field-of-view-sized tiles.

#include <scanplan/planning/sweep_tiles.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace scanplan {
namespace {

constexpr double kMaxTileSpread = 40;  // degrees between a tile's normals and its mean

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
