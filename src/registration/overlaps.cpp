// The registration's pair test on simulated surface points and markers.

#include "registration/overlaps.h"

#include <algorithm>
#include <map>

namespace scanplan::detail {

namespace {

bool disjoint(const Box& a, const Box& b) {
  return a.empty() || b.empty() || (a.max.array() < b.min.array()).any() ||
         (b.max.array() < a.min.array()).any();
}

}  // namespace

std::vector<int> shared(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> both;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(both));
  return both;
}

std::vector<SurfacePoint> markerPoints(const std::vector<Marker>& markers) {
  std::vector<SurfacePoint> points;
  for (const Marker& m : markers) points.push_back({m.position, m.normal, 0});
  return points;
}

Overlaps::Overlaps(const Simulator& simulator, const RegistrationOptions& options,
                   const std::vector<Marker>& markers)
    : simulator_(simulator),
      options_(options),
      spacing_(overlapSpacing(options, simulator.scanner())),
      points_(simulator.surfacePoints(spacing_, options.seed)),
      marker_list_(markers),
      markers_(markerPoints(markers)) {}

std::vector<std::vector<int>> Overlaps::markersSeenAt(std::span<const View> views,
                                                      double angle) const {
  if (angle == 0) return markers_.measured(simulator_, views);
  const IndexedPoints turned(
      markerPoints(markersAtTableAngle(marker_list_, *options_.table, angle)));
  return turned.measured(simulator_, views);
}

std::vector<double> Overlaps::tableAngles(std::span<const View> views) const {
  std::vector<double> angles(views.size(), 0.0);
  if (options_.table)
    for (std::size_t v = 0; v < views.size(); ++v) angles[v] = options_.table->angle(views[v]);
  return angles;
}

std::vector<Vec3> Overlaps::markerPositionsAt(double angle) const {
  std::vector<Vec3> positions;
  if (angle == 0)
    for (const SurfacePoint& p : markers_.points()) positions.push_back(p.position);
  else
    for (const Marker& m : markersAtTableAngle(marker_list_, *options_.table, angle))
      positions.push_back(m.position);
  return positions;
}

std::vector<std::vector<int>> Overlaps::markersSeen(std::span<const View> views) const {
  return markersSeen(views, tableAngles(views));
}

std::vector<std::vector<int>> Overlaps::markersSeen(std::span<const View> views,
                                                    const std::vector<double>& angles) const {
  if (!options_.table || marker_list_.empty()) return markers_.measured(simulator_, views);
  // The views grouped by their table angle, each group measured where it puts the markers.
  std::map<double, std::vector<std::size_t>> at_angle;
  for (std::size_t v = 0; v < views.size(); ++v) at_angle[angles[v]].push_back(v);
  std::vector<std::vector<int>> seen(views.size());
  for (const auto& [angle, indices] : at_angle) {
    std::vector<View> group;
    for (std::size_t v : indices) group.push_back(views[v]);
    std::vector<std::vector<int>> measured = markersSeenAt(group, angle);
    for (std::size_t k = 0; k < indices.size(); ++k) seen[indices[k]] = std::move(measured[k]);
  }
  return seen;
}

std::vector<Observation> Overlaps::observe(std::span<const View> views) const {
  const std::vector<double> angles = tableAngles(views);
  std::vector<std::vector<int>> on_points = points_.measured(simulator_, views);
  std::vector<std::vector<int>> on_markers = markersSeen(views, angles);
  std::map<double, std::vector<Vec3>> positions;  // of the markers, per table angle met
  std::vector<Observation> result(views.size());
  for (std::size_t v = 0; v < views.size(); ++v) {
    Observation& seen = result[v];
    seen.points = std::move(on_points[v]);
    seen.markers = std::move(on_markers[v]);
    seen.table_angle = angles[v];
    for (int i : seen.points) seen.box.add(points()[i].position);
    if (seen.markers.empty()) continue;
    auto at = positions.find(seen.table_angle);
    if (at == positions.end())
      at = positions.emplace(seen.table_angle, markerPositionsAt(seen.table_angle)).first;
    for (int i : seen.markers) seen.box.add(at->second[i]);
  }
  return result;
}

PairCheck Overlaps::check(const View& a, const Observation& oa, const View& b,
                          const Observation& ob) const {
  return test(a, oa, b, ob, true);
}

bool Overlaps::passes(const View& a, const Observation& oa, const View& b,
                      const Observation& ob) const {
  return test(a, oa, b, ob, false).passes();
}

PairCheck Overlaps::test(const View& a, const Observation& oa, const View& b, const Observation& ob,
                         bool value) const {
  PairCheck pair;
  pair.a = std::min(a.id, b.id);
  pair.b = std::max(a.id, b.id);
  if (disjoint(oa.box, ob.box)) return pair;
  std::vector<int> markers = shared(oa.markers, ob.markers);
  // Views taken at two table angles share only the markers that turn with the part.
  if (oa.table_angle != ob.table_angle)
    std::erase_if(markers, [&](int i) { return marker_list_[i].on == MarkerCarrier::Plane; });
  pair.shared_markers = markers.size();
  pair.markers = !referencePoints() && registers(markers);
  if (!value && pair.markers) return pair;  // passes whatever the overlap
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
  const bool overlaps = std::min(share_a, share_b) >= options_.min_overlap;
  if (value) {
    pair.condition = icpCondition(p, n);
    pair.stable = overlaps && pair.condition <= options_.max_condition;
  } else {
    pair.stable = overlaps && icpConditionWithin(p, n, options_.max_condition);
  }
  return pair;
}

bool Overlaps::constrained(const Observation& seen) const {
  std::vector<Vec3> p, n;
  for (int i : seen.points) {
    p.push_back(points()[i].position);
    n.push_back(points()[i].normal);
  }
  return icpConditionWithin(p, n, options_.max_condition) || registers(seen.markers);
}

bool Overlaps::framed(const std::vector<int>& markers) const {
  return referencePoints() && registers(markers);
}

bool Overlaps::referencePoints() const {
  return options_.method == RegistrationMode::ReferencePoints;
}

std::vector<Vec3> Overlaps::markerPositions(const std::vector<int>& markers) const {
  std::vector<Vec3> positions;
  for (int m : markers) positions.push_back(markers_.points()[m].position);
  return positions;
}

bool Overlaps::registers(const std::vector<int>& markers) const {
  return markersRegister(markerPositions(markers), options_.min_markers, options_.marker_spread);
}

}  // namespace scanplan::detail

namespace scanplan {

double overlapSpacing(const RegistrationOptions& options, const Scanner& scanner) {
  return options.point_spacing > 0 ? options.point_spacing : scanner.fov_height / 40;
}

}  // namespace scanplan
