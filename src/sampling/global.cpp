// Global sampling: all faces, decimated by distance and normal angle (nanoflann), each face
// keeping at least one sample.

#include <scanplan/sampling/sampling.h>

#include "core/kd_tree.h"

#include <cmath>
#include <unordered_map>

namespace scanplan {
std::vector<Sample> decimate(const std::vector<Sample>& samples, double radius, double angle,
                             FaceSamples faces) {
  if (samples.empty()) return {};
  detail::PositionCloud<Sample> cloud{samples};
  detail::PositionTree<Sample> tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  const double min_dot = std::cos(radians(angle));
  std::vector<char> removed(samples.size(), 0);
  // With KeepOne, each face's samples not removed yet: a face's last one is not removed.
  const bool keep_one = faces == FaceSamples::KeepOne;
  std::unordered_map<int, int> left;
  if (keep_one)
    for (const Sample& s : samples) ++left[s.face];
  const auto removable = [&](std::size_t j) { return !keep_one || left[samples[j].face] > 1; };
  std::vector<Sample> kept;
  detail::Neighbours neighbours;
  nanoflann::SearchParams params;
  params.sorted = false;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (removed[i]) continue;
    kept.push_back(samples[i]);
    // nanoflann's L2 adaptor works in squared distances; "closer than" the radius.
    tree.radiusSearch(samples[i].position.data(), radius * radius, neighbours, params);
    for (const auto& [j, distance2] : neighbours)
      if (j != i && !removed[j] && distance2 < radius * radius &&
          samples[j].normal.dot(samples[i].normal) >= min_dot && removable(j)) {
        removed[j] = 1;
        if (keep_one) --left[samples[j].face];
        kept.back().weight += samples[j].weight;
      }
  }
  return kept;
}

std::vector<Sample> sampleGlobal(const Part& part, const std::vector<int>& excluded,
                                 const SamplingOptions& options) {
  std::vector<int> faces;
  for (const Face& face : part.faces)
    if (std::find(excluded.begin(), excluded.end(), face.id) == excluded.end())
      faces.push_back(face.id);
  return decimate(sampleSurface(part, faces, Role::Normal, TaskType::Global, options),
                  options.decimation_radius, options.decimation_angle, FaceSamples::KeepOne);
}

}  // namespace scanplan
