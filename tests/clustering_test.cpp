// Clustering: every cluster keeps both conditions (checked pair by pair from the options);
// known groups are found; seeded.

#include "support.h"

#include <scanplan/cad/import.h>
#include <scanplan/sampling/clustering.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

namespace scanplan {
namespace {

std::vector<Sample> patch(const Vec3& centre, const Vec3& normal, double size, int n, int face) {
  std::vector<Sample> samples;
  const Vec3 u = normal.unitOrthogonal(), v = normal.cross(u);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      Sample s;
      s.position = centre + size * ((i + 0.5) / n - 0.5) * u + size * ((j + 0.5) / n - 0.5) * v;
      s.normal = normal;
      s.face = face;
      samples.push_back(s);
    }
  return samples;
}

// Every cluster keeps both conditions, checked here pair by pair from the options alone
// (distance, and the angle between the normals in degrees), and every sample lies in one.
void expectValid(const std::vector<Sample>& samples, const std::vector<Cluster>& clusters,
                 const ClusteringOptions& options) {
  std::vector<int> seen(samples.size(), 0);
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    const std::vector<int>& members = clusters[c].samples;
    for (std::size_t a = 0; a < members.size(); ++a)
      for (std::size_t b = a + 1; b < members.size(); ++b) {
        const Sample &p = samples[members[a]], &q = samples[members[b]];
        const double angle = std::acos(std::clamp(p.normal.dot(q.normal), -1.0, 1.0)) * 180 / M_PI;
        EXPECT_LT((p.position - q.position).norm(), options.max_distance)
            << "cluster " << c << ": " << members[a] << ", " << members[b];
        EXPECT_LT(angle, options.max_normal_angle)
            << "cluster " << c << ": " << members[a] << ", " << members[b];
      }
    EXPECT_FALSE(clusters[c].samples.empty());
    for (int i : clusters[c].samples) {
      ++seen[i];
      EXPECT_EQ(samples[i].cluster, static_cast<int>(c));
    }
  }
  for (std::size_t i = 0; i < samples.size(); ++i) EXPECT_EQ(seen[i], 1) << "sample " << i;
}

TEST(Clustering, TwoSeparateGroupsGiveTwoClusters) {
  std::vector<Sample> samples = patch(Vec3(0, 0, 0), Vec3::UnitZ(), 100, 10, 1);
  std::vector<Sample> other = patch(Vec3(1000, 0, 0), Vec3::UnitZ(), 100, 10, 2);
  samples.insert(samples.end(), other.begin(), other.end());
  ClusteringOptions options;
  std::vector<Cluster> clusters = clusterSamples(samples, options);
  ASSERT_EQ(clusters.size(), 2u);
  for (const Cluster& c : clusters) {
    std::set<int> faces;
    for (int i : c.samples) faces.insert(samples[i].face);
    EXPECT_EQ(faces.size(), 1u);
    EXPECT_EQ(c.samples.size(), 100u);
    EXPECT_TRUE(c.mean_normal.isApprox(Vec3::UnitZ(), 1e-12));
  }
  expectValid(samples, clusters, options);
}

TEST(Clustering, OppositeNormalsNeverShareACluster) {
  // Two faces of a thin plate: close in space, normals 180° apart.
  std::vector<Sample> samples = patch(Vec3(0, 0, 0), Vec3::UnitZ(), 50, 6, 1);
  std::vector<Sample> back = patch(Vec3(0, 0, -2), -Vec3::UnitZ(), 50, 6, 2);
  samples.insert(samples.end(), back.begin(), back.end());
  ClusteringOptions options;
  std::vector<Cluster> clusters = clusterSamples(samples, options);
  EXPECT_EQ(clusters.size(), 2u);
  expectValid(samples, clusters, options);
}

TEST(Clustering, LargeSurfaceIsSplitByTheFieldOfView) {
  std::vector<Sample> samples = patch(Vec3(0, 0, 0), Vec3::UnitZ(), 1000, 40, 1);
  ClusteringOptions options;
  std::vector<Cluster> clusters = clusterSamples(samples, options);
  // Diameter under 225 mm: a 1000 mm square needs more than (1000/225)^2 clusters.
  EXPECT_GE(clusters.size(), 20u);
  expectValid(samples, clusters, options);
}

TEST(Clustering, RandomCloudKeepsConditionsAndIsSeeded) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> coordinate(-300, 300), component(-1, 1);
  std::vector<Sample> samples(800);
  for (Sample& s : samples) {
    s.position = Vec3(coordinate(random), coordinate(random), coordinate(random));
    s.normal = Vec3(component(random), component(random), component(random)).normalized();
  }
  ClusteringOptions options;
  std::vector<Sample> a = samples, b = samples, c = samples;
  auto ca = clusterSamples(a, options);
  auto cb = clusterSamples(b, options);
  expectValid(a, ca, options);
  ASSERT_EQ(ca.size(), cb.size());
  for (std::size_t k = 0; k < ca.size(); ++k) EXPECT_EQ(ca[k].samples, cb[k].samples);
  options.seed = 2;
  auto cc = clusterSamples(c, options);
  expectValid(c, cc, options);
}

TEST(Clustering, NistPartSamples) {
  Part part = importPart(test::example("parts/nist_ctc_01_asme1_ap242-e1.stp"));
  std::vector<Sample> samples = sampleGlobal(part, {});
  ClusteringOptions options;
  std::vector<Cluster> clusters = clusterSamples(samples, options);
  EXPECT_GT(clusters.size(), 4u);
  expectValid(samples, clusters, options);
}

}  // namespace
}  // namespace scanplan
