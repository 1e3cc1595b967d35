#include <scanplan/sampling/clustering.h>

#include "core/kd_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace scanplan {

ClusteringOptions clusteringOptionsFor(const Scanner& scanner, std::uint64_t seed) {
  ClusteringOptions options;
  options.max_distance = std::min(scanner.fov_width, scanner.fov_height);
  options.seed = seed;
  return options;
}

namespace {

class Compatibility {
 public:
  Compatibility(const std::vector<Sample>& samples, const ClusteringOptions& options)
      : samples_(samples),
        max_distance2_(options.max_distance * options.max_distance),
        min_dot_(std::cos(radians(options.max_normal_angle))) {}

  bool pair(int a, int b) const {
    return (samples_[a].position - samples_[b].position).squaredNorm() < max_distance2_ &&
           samples_[a].normal.dot(samples_[b].normal) > min_dot_;
  }
  // `candidate` keeps both conditions with every member (but `except`).
  bool withAll(int candidate, const std::vector<int>& members, int except = -1) const {
    for (int m : members)
      if (m != except && !pair(candidate, m)) return false;
    return true;
  }

 private:
  const std::vector<Sample>& samples_;
  double max_distance2_, min_dot_;
};

void updateMeans(const std::vector<Sample>& samples, Cluster& cluster) {
  Vec3 position = Vec3::Zero(), normal = Vec3::Zero();
  for (int i : cluster.samples) {
    position += samples[i].position;
    normal += samples[i].normal;
  }
  cluster.mean_position =
      position / static_cast<double>(std::max<std::size_t>(cluster.samples.size(), 1));
  cluster.mean_normal = normal.norm() > 1e-12 ? Vec3(normal.normalized()) : Vec3::UnitZ();
}

// Greedy growth from seeds in a seeded random order: each seed takes the unowned samples
// within max_distance, nearest first, that are compatible with all its members. `owner`
// gets each sample's cluster.
std::vector<Cluster> grownClusters(const std::vector<Sample>& samples,
                                   const Compatibility& compatible,
                                   const ClusteringOptions& options, std::vector<int>& owner) {
  detail::PositionCloud<Sample> cloud{samples};
  detail::PositionTree<Sample> tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  std::vector<int> order(samples.size());
  std::iota(order.begin(), order.end(), 0);
  std::mt19937_64 random(options.seed);
  std::shuffle(order.begin(), order.end(), random);
  owner.assign(samples.size(), -1);
  std::vector<Cluster> clusters;
  detail::Neighbours near;
  nanoflann::SearchParams sorted;
  sorted.sorted = true;
  for (int seed : order) {
    if (owner[seed] >= 0) continue;
    Cluster cluster;
    cluster.samples.push_back(seed);
    owner[seed] = static_cast<int>(clusters.size());
    tree.radiusSearch(samples[seed].position.data(), options.max_distance * options.max_distance,
                      near, sorted);
    for (const auto& [j, distance2] : near) {
      const int candidate = static_cast<int>(j);
      if (owner[candidate] >= 0 || !compatible.withAll(candidate, cluster.samples)) continue;
      cluster.samples.push_back(candidate);
      owner[candidate] = static_cast<int>(clusters.size());
    }
    updateMeans(samples, cluster);
    clusters.push_back(std::move(cluster));
  }
  return clusters;
}

// k-means refinement: each sample goes to the nearest centroid (position, normal) whose
// cluster it is compatible with; a move never breaks a condition, nor empties a cluster.
void refineClusters(const std::vector<Sample>& samples, const Compatibility& compatible,
                    const ClusteringOptions& options, std::vector<Cluster>& clusters,
                    std::vector<int>& owner) {
  const double w = options.normal_weight * options.max_distance;
  auto cost = [&](int i, const Cluster& c) {
    return (samples[i].position - c.mean_position).squaredNorm() +
           w * w * (samples[i].normal - c.mean_normal).squaredNorm();
  };
  std::vector<std::pair<double, int>> candidates;
  for (int pass = 0; pass < options.iterations; ++pass) {
    bool moved = false;
    for (int i = 0; i < static_cast<int>(samples.size()); ++i) {
      const int from = owner[i];
      if (clusters[from].samples.size() == 1) continue;  // keep every cluster alive
      // Every other cluster cheaper than its own, cheapest first.
      const double current = cost(i, clusters[from]);
      candidates.clear();
      for (int to = 0; to < static_cast<int>(clusters.size()); ++to)
        if (to != from && !clusters[to].samples.empty())
          if (const double c = cost(i, clusters[to]); c < current) candidates.push_back({c, to});
      std::sort(candidates.begin(), candidates.end());
      const auto best = std::find_if(candidates.begin(), candidates.end(), [&](const auto& c) {
        return compatible.withAll(i, clusters[c.second].samples);
      });
      if (best == candidates.end()) continue;
      auto& members = clusters[from].samples;
      members.erase(std::find(members.begin(), members.end(), i));
      clusters[best->second].samples.push_back(i);
      owner[i] = best->second;
      moved = true;
    }
    for (Cluster& c : clusters) updateMeans(samples, c);
    if (!moved) break;
  }
}

}  // namespace

std::vector<Cluster> clusterSamples(std::vector<Sample>& samples,
                                    const ClusteringOptions& options) {
  if (samples.empty()) return {};
  const Compatibility compatible(samples, options);
  std::vector<int> owner;
  std::vector<Cluster> clusters = grownClusters(samples, compatible, options, owner);
  refineClusters(samples, compatible, options, clusters, owner);
  for (Cluster& c : clusters) std::sort(c.samples.begin(), c.samples.end());
  for (std::size_t c = 0; c < clusters.size(); ++c)
    for (int i : clusters[c].samples) samples[i].cluster = static_cast<int>(c);
  return clusters;
}

}  // namespace scanplan
