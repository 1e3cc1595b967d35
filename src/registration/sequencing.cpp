// Motion costs between views and the tour through them.

#include <scanplan/registration/sequencing.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace scanplan {

namespace {

// Moves that go over the part rise to this height: the clearance above its top.
double safeHeight(const Simulator& simulator, const SequenceOptions& options) {
  double top = 0;
  for (const SurfacePoint& p : simulator.facetPoints()) top = std::max(top, p.position.z());
  return top + options.clearance;
}

// The direct cost of the move between views a and b (directCosts); `blocked`: the straight
// path crosses the scene.
double moveCost(const Simulator& simulator, const View& a, const View& b, bool blocked, double safe,
                const SequenceOptions& options) {
  const Vec3 from = a.camera(), to = b.camera();
  const bool below = simulator.options().working_plane && (from.z() < 0 || to.z() < 0);
  double travel = (to - from).norm();
  if (blocked || below) {
    const double height = std::max({safe, from.z(), to.z()});
    travel = (height - from.z()) + (to - from).head<2>().norm() + (height - to.z());
  }
  const Eigen::AngleAxisd turn(a.camera_to_world.linear().transpose() * b.camera_to_world.linear());
  return travel + options.rotation_arm * std::abs(turn.angle());
}

}  // namespace

Eigen::MatrixXd directCosts(const Simulator& simulator, std::span<const View> views,
                            const SequenceOptions& options) {
  const auto n = static_cast<Eigen::Index>(views.size());
  std::vector<Ray> segments;
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j)
      segments.push_back(Ray{views[i].camera(), views[j].camera() - views[i].camera(), 0, 1});
  const std::vector<bool> blocked = simulator.occluded(segments);
  const double safe = safeHeight(simulator, options);
  Eigen::MatrixXd cost = Eigen::MatrixXd::Zero(n, n);
  std::size_t k = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j, ++k)
      cost(i, j) = cost(j, i) = moveCost(simulator, views[i], views[j], blocked[k], safe, options);
  return cost;
}

Eigen::MatrixXd directCosts(const Simulator& simulator, std::span<const View> from,
                            std::span<const View> to, const SequenceOptions& options) {
  std::vector<Ray> segments;
  for (const View& a : from)
    for (const View& b : to) segments.push_back(Ray{a.camera(), b.camera() - a.camera(), 0, 1});
  const std::vector<bool> blocked = simulator.occluded(segments);
  const double safe = safeHeight(simulator, options);
  const auto columns = static_cast<Eigen::Index>(to.size());
  Eigen::MatrixXd cost(static_cast<Eigen::Index>(from.size()), columns);
  for (Eigen::Index i = 0; i < cost.rows(); ++i)
    for (Eigen::Index j = 0; j < columns; ++j)
      cost(i, j) = moveCost(simulator, from[i], to[j], blocked[i * columns + j], safe, options);
  return cost;
}

Eigen::MatrixXd shortestPaths(const Eigen::MatrixXd& direct) {
  // Floyd-Warshall, a column at a time: through view k, column j (the moves into j) becomes
  // the shorter of itself and column k plus the move k -> j. Columns are independent within
  // a step; column k itself does not change (no cost is negative).
  Eigen::MatrixXd d = direct;
  const Eigen::Index n = d.rows();
  for (Eigen::Index k = 0; k < n; ++k)
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 64), [&](const auto& columns) {
      for (Eigen::Index j = columns.begin(); j < columns.end(); ++j)
        if (j != k) d.col(j) = d.col(j).cwiseMin((d.col(k).array() + d(k, j)).matrix());
    });
  return d;
}

std::vector<std::vector<char>> registrationLinks(std::span<const View> views,
                                                 const Registration& registration) {
  std::map<int, std::size_t> index;
  for (std::size_t v = 0; v < views.size(); ++v) index[views[v].id] = v;
  std::vector<std::vector<char>> links(views.size(), std::vector<char>(views.size(), 0));
  for (const PairCheck& pair : registration.pairs) {
    const auto a = index.find(pair.a), b = index.find(pair.b);
    if (a != index.end() && b != index.end() && registration.links(pair))
      links[a->second][b->second] = links[b->second][a->second] = 1;
  }
  // A view the robot registers is in the cell's frame, one registered by reference points in
  // theirs: any order suits it. A view ICP aligns once all scans are taken may follow any.
  for (std::size_t v = 0; v < views.size() && v < registration.views.size(); ++v) {
    const RegistrationMethod method = registration.views[v].method;
    if (method == RegistrationMethod::Robot || method == RegistrationMethod::ReferencePoints)
      for (std::size_t w = 0; w < views.size(); ++w) links[v][w] = links[w][v] = v != w;
    if (method == RegistrationMethod::Icp && !registration.aligned_as_taken)
      for (std::size_t w = 0; w < views.size(); ++w) links[v][w] = v != w;
  }
  return links;
}

std::vector<double> insertionPathLengths(const Eigen::MatrixXd& cost) {
  std::vector<int> path;
  std::vector<double> lengths;
  double length = 0;
  for (int v = 0; v < static_cast<int>(cost.rows()); ++v) {
    // At either end, or between two nodes of the path: where it adds least.
    double best = path.empty() ? 0 : cost(v, path.front());
    std::size_t where = 0;
    if (!path.empty() && cost(path.back(), v) < best) {
      best = cost(path.back(), v);
      where = path.size();
    }
    for (std::size_t k = 1; k < path.size(); ++k) {
      const double extra = cost(path[k - 1], v) + cost(v, path[k]) - cost(path[k - 1], path[k]);
      if (extra < best) {
        best = extra;
        where = k;
      }
    }
    path.insert(path.begin() + static_cast<long>(where), v);
    lengths.push_back(length += best);
  }
  return lengths;
}

double pathLength(const Eigen::MatrixXd& cost, std::span<const int> order) {
  double length = 0;
  for (std::size_t k = 1; k < order.size(); ++k) length += cost(order[k - 1], order[k]);
  return length;
}

namespace {

// Nodes of `order` (after the first) with no linked node before them.
std::size_t violations(const std::vector<std::vector<char>>& linked,
                       const std::vector<int>& order) {
  std::size_t count = 0;
  for (std::size_t k = 1; k < order.size(); ++k) {
    bool follows = false;
    for (std::size_t j = 0; j < k && !follows; ++j) follows = linked[order[k]][order[j]];
    count += !follows;
  }
  return count;
}

}  // namespace

std::vector<int> nearestNeighbourOrder(const Eigen::MatrixXd& cost,
                                       const std::vector<std::vector<char>>& linked, int start) {
  const auto n = static_cast<int>(cost.rows());
  if (n == 0) return {};
  std::vector<int> order{start};
  std::vector<char> visited(static_cast<std::size_t>(n), 0), reachable(visited);
  visited[start] = 1;
  auto reach = [&](int u) {  // the nodes that may follow u
    for (int v = 0; v < n; ++v)
      if (!linked.empty() && linked[v][u]) reachable[v] = 1;
  };
  reach(start);
  while (static_cast<int>(order.size()) < n) {
    int best = -1;
    for (int pass = 0; pass < 2 && best < 0; ++pass)  // linked nodes first, then any
      for (int v = 0; v < n; ++v)
        if (!visited[v] && (pass == 1 || reachable[v]) &&
            (best < 0 || cost(order.back(), v) < cost(order.back(), best)))
          best = v;
    order.push_back(best);
    visited[best] = 1;
    reach(best);
  }
  return order;
}

std::vector<int> twoOpt(const Eigen::MatrixXd& cost, const std::vector<std::vector<char>>& linked,
                        std::vector<int> order) {
  const std::size_t n = order.size();
  std::size_t broken = linked.empty() ? 0 : violations(linked, order);
  for (bool improved = true; improved;) {
    improved = false;
    for (std::size_t i = 1; i + 1 < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        // Reversing order[i..j] replaces the edges (i-1, i) and (j, j+1).
        double delta = cost(order[i - 1], order[j]) - cost(order[i - 1], order[i]);
        if (j + 1 < n) delta += cost(order[i], order[j + 1]) - cost(order[j], order[j + 1]);
        if (delta > -1e-9) continue;
        std::reverse(order.begin() + static_cast<std::ptrdiff_t>(i),
                     order.begin() + static_cast<std::ptrdiff_t>(j) + 1);
        const std::size_t now = linked.empty() ? 0 : violations(linked, order);
        if (now > broken) {  // undo: the move breaks the registration rule
          std::reverse(order.begin() + static_cast<std::ptrdiff_t>(i),
                       order.begin() + static_cast<std::ptrdiff_t>(j) + 1);
          continue;
        }
        broken = now;
        improved = true;
      }
  }
  return order;
}

namespace {

// Where a run of nodes can go: after the node order[after], reversed or not, and how much
// that shortens the path.
struct RunMove {
  std::size_t after;
  bool reversed;
  double gain;
};

// The moves of the run order[first, first + size) that shorten the path, the most first.
std::vector<RunMove> runMoves(const Eigen::MatrixXd& cost, const std::vector<int>& order,
                              std::size_t first, std::size_t size) {
  const std::size_t n = order.size(), end = first + size;
  const int head = order[first], tail = order[end - 1], before = order[first - 1];
  double removed = cost(before, head), reversal = 0;  // reversal: the run's own change
  if (end < n) removed += cost(tail, order[end]) - cost(before, order[end]);
  for (std::size_t k = first + 1; k < end; ++k)
    reversal += cost(order[k], order[k - 1]) - cost(order[k - 1], order[k]);
  std::vector<RunMove> moves;
  for (std::size_t j = 0; j < n; ++j) {
    if (j + 1 >= first && j < end) continue;  // where it is, or inside it
    const int a = order[j];
    const bool last = j + 1 == n;
    const double kept = last ? 0 : cost(a, order[j + 1]);
    const double straight = cost(a, head) + (last ? 0 : cost(tail, order[j + 1])) - kept;
    const double turned = cost(a, tail) + (last ? 0 : cost(head, order[j + 1])) - kept + reversal;
    if (removed - straight > 1e-9) moves.push_back({j, false, removed - straight});
    if (removed - turned > 1e-9) moves.push_back({j, true, removed - turned});
  }
  std::sort(moves.begin(), moves.end(),
            [](const RunMove& x, const RunMove& y) { return x.gain > y.gain; });
  return moves;
}

// `order` with the run order[first, first + size) moved as `move` says.
std::vector<int> moved(const std::vector<int>& order, std::size_t first, std::size_t size,
                       const RunMove& move) {
  std::vector<int> run(order.begin() + static_cast<std::ptrdiff_t>(first),
                       order.begin() + static_cast<std::ptrdiff_t>(first + size));
  if (move.reversed) std::reverse(run.begin(), run.end());
  std::vector<int> result;
  result.reserve(order.size());
  for (std::size_t j = 0; j < order.size(); ++j) {
    if (j >= first && j < first + size) continue;
    result.push_back(order[j]);
    if (j == move.after) result.insert(result.end(), run.begin(), run.end());
  }
  return result;
}

}  // namespace

std::vector<int> orOpt(const Eigen::MatrixXd& cost, const std::vector<std::vector<char>>& linked,
                       std::vector<int> order) {
  std::size_t broken = linked.empty() ? 0 : violations(linked, order);
  for (bool improved = true; improved;) {
    improved = false;
    for (std::size_t size = 1; size <= 3; ++size)
      for (std::size_t first = 1; first + size <= order.size(); ++first)
        for (const RunMove& move : runMoves(cost, order, first, size)) {
          std::vector<int> candidate = moved(order, first, size, move);
          const std::size_t now = linked.empty() ? 0 : violations(linked, candidate);
          if (now > broken) continue;  // the move breaks the registration rule
          order = std::move(candidate);
          broken = now;
          improved = true;
          break;
        }
  }
  return order;
}

std::vector<int> improvedOrder(const Eigen::MatrixXd& cost,
                               const std::vector<std::vector<char>>& linked,
                               std::vector<int> order) {
  for (double length = pathLength(cost, order);;) {
    order = orOpt(cost, linked, twoOpt(cost, linked, std::move(order)));
    const double now = pathLength(cost, order);
    if (now > length - 1e-9) return order;
    length = now;
  }
}

Sequence sequenceViews(const Simulator& simulator, std::span<const View> views,
                       const Registration& registration, const SequenceOptions& options) {
  const Eigen::MatrixXd cost = shortestPaths(directCosts(simulator, views, options));
  return sequenceViews(cost, cost, views, registration);
}

Sequence sequenceViews(const Eigen::MatrixXd& order_cost, const Eigen::MatrixXd& length_cost,
                       std::span<const View> views, const Registration& registration) {
  Sequence sequence;
  const std::size_t n = views.size();
  if (n == 0) return sequence;
  int start = 0;
  for (std::size_t v = 0; v < n; ++v)
    if (views[v].id == registration.reference) start = static_cast<int>(v);
  const std::vector<std::vector<char>> linked = registrationLinks(views, registration);

  const std::vector<int> nearest = nearestNeighbourOrder(order_cost, linked, start);
  std::vector<int> best = improvedOrder(order_cost, linked, nearest);
  const std::vector<int> plain =
      improvedOrder(order_cost, linked, nearestNeighbourOrder(order_cost, {}, start));
  if (violations(linked, plain) <= violations(linked, best) &&
      pathLength(order_cost, plain) < pathLength(order_cost, best))
    best = plain;
  for (int k : best) sequence.views.push_back(views[k].id);
  sequence.length = pathLength(length_cost, best);
  sequence.nearest_neighbour_length = pathLength(length_cost, nearest);
  return sequence;
}

}  // namespace scanplan
