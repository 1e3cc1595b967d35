// The registration's pair test on simulated surface points and markers.

#include "registration/overlaps.h"

#include <algorithm>

namespace scanplan::detail {

namespace {

bool disjoint(const Box& a, const Box& b) {
  return a.empty() || b.empty() || (a.max.array() < b.min.array()).any() ||
         (b.max.array() < a.min.array()).any();
}

std::vector<int> shared(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> both;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(both));
  return both;
}

double pointSpacing(const Simulator& simulator, const RegistrationOptions& options) {
  return options.point_spacing > 0 ? options.point_spacing : simulator.scanner().fov_height / 40;
}

}  // namespace

std::vector<SurfacePoint> markerPoints(const std::vector<Marker>& markers) {
  std::vector<SurfacePoint> points;
  for (const Marker& m : markers) points.push_back({m.position, m.normal, 0});
  return points;
}

Overlaps::Overlaps(const Simulator& simulator, const RegistrationOptions& options,
                   const std::vector<Marker>& markers)
    : simulator_(simulator),
      options_(options),
      spacing_(pointSpacing(simulator, options)),
      points_(simulator.surfacePoints(spacing_, options.seed)),
      markers_(markerPoints(markers)) {}

std::vector<std::vector<int>> Overlaps::markersSeen(std::span<const View> views) const {
  return markers_.measured(simulator_, views);
}

std::vector<Observation> Overlaps::observe(std::span<const View> views) const {
  std::vector<std::vector<int>> on_points = points_.measured(simulator_, views);
  std::vector<std::vector<int>> on_markers = markersSeen(views);
  std::vector<Observation> result(views.size());
  for (std::size_t v = 0; v < views.size(); ++v) {
    Observation& seen = result[v];
    seen.points = std::move(on_points[v]);
    seen.markers = std::move(on_markers[v]);
    for (int i : seen.points) seen.box.add(points()[i].position);
    for (int i : seen.markers) seen.box.add(markers_.points()[i].position);
  }
  return result;
}

PairCheck Overlaps::check(const View& a, const Observation& oa, const View& b,
                          const Observation& ob) const {
  PairCheck pair;
  pair.a = std::min(a.id, b.id);
  pair.b = std::max(a.id, b.id);
  if (disjoint(oa.box, ob.box)) return pair;
  const std::vector<int> markers = shared(oa.markers, ob.markers);
  pair.shared_markers = markers.size();
  pair.markers = !referencePoints() && registers(markers);
  const std::vector<int> overlap = shared(oa.points, ob.points);
  if (overlap.empty()) return pair;
  pair.overlap_area = static_cast<double>(overlap.size()) * spacing_ * spacing_;
  const double share_a =
      static_cast<double>(overlap.size()) / static_cast<double>(oa.points.size());
  const double share_b =
      static_cast<double>(overlap.size()) / static_cast<double>(ob.points.size());
  pair.overlap_a = a.id < b.id ? share_a : share_b;
  pair.overlap_b = a.id < b.id ? share_b : share_a;
  if (!pair.markers && std::min(share_a, share_b) < options_.min_overlap) return pair;
  std::vector<Vec3> p, n;
  for (int i : overlap) {
    p.push_back(points()[i].position);
    n.push_back(points()[i].normal);
  }
  pair.condition = icpCondition(p, n);
  pair.stable = std::min(share_a, share_b) >= options_.min_overlap &&
                pair.condition <= options_.max_condition;
  return pair;
}

bool Overlaps::constrained(const Observation& seen) const {
  std::vector<Vec3> p, n;
  for (int i : seen.points) {
    p.push_back(points()[i].position);
    n.push_back(points()[i].normal);
  }
  return icpCondition(p, n) <= options_.max_condition || registers(seen.markers);
}

bool Overlaps::framed(const std::vector<int>& markers) const {
  return referencePoints() && registers(markers);
}

bool Overlaps::referencePoints() const {
  return options_.method == RegistrationMode::ReferencePoints;
}

bool Overlaps::registers(const std::vector<int>& markers) const {
  std::vector<Vec3> positions;
  for (int m : markers) positions.push_back(markers_.points()[m].position);
  return markersRegister(positions, options_.min_markers, options_.marker_spread);
}

}  // namespace scanplan::detail
