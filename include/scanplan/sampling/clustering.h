#pragma once
// Clustering of samples into groups that one view can take (docs/sampling.md): any two
// samples of a cluster are closer than the field of view and their normals differ by
// less than 90°.

#include <scanplan/sampling/sampling.h>

#include <cstdint>
#include <vector>

namespace scanplan {

struct Cluster {
  std::vector<int> samples;           // indices into the sample list
  Vec3 mean_position = Vec3::Zero();  // mm
  Vec3 mean_normal = Vec3::UnitZ();   // unit (the normalised sum of normals)
};

struct ClusteringOptions {
  double max_distance = 225;     // samples of a cluster are closer than this, mm
  double max_normal_angle = 90;  // ... and their normals differ by less than this, degrees
  double normal_weight = 0.5;    // k-means: a unit normal difference counts as this many
                                 // max_distance of position difference
  int iterations = 10;           // k-means refinement passes, at most
  std::uint64_t seed = 1;        // order in which clusters are grown
};

// Options with the distance limit set to the scanner's field of view (its smaller side).
ClusteringOptions clusteringOptionsFor(const Scanner& scanner, std::uint64_t seed);

// Groups `samples` and writes each one's cluster index into Sample::cluster. Clusters
// are grown greedily from seeds taken in a seeded random order, each taking the nearest
// samples that keep both conditions, then refined by k-means on position and normal in
// which a sample only moves to a cluster whose conditions it keeps. Deterministic for a
// given input and seed.
std::vector<Cluster> clusterSamples(std::vector<Sample>& samples,
                                    const ClusteringOptions& options = {});

}  // namespace scanplan
