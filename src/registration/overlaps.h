#pragma once
// The registration's pair test (docs/registration.md): the surface points overlaps are
// judged on, what views measure of them and of the markers, and whether two views register
// by the markers they share or the overlap of their surfaces. Used by the registration
// graph and by the registration-aware selection.

#include <scanplan/registration/registration.h>

#include <span>
#include <vector>

namespace scanplan::detail {

// What a view measures: surface points and markers, indices in ascending order.
struct Observation {
  std::vector<int> points;
  std::vector<int> markers;
  Box box;                 // around both
  double table_angle = 0;  // the view is taken at, radians (RegistrationOptions::table)
};

// The indices in both of the ascending lists `a` and `b`, ascending.
std::vector<int> shared(const std::vector<int>& a, const std::vector<int>& b);

// Markers as points on the surface, for the simulation to measure (face 0).
std::vector<SurfacePoint> markerPoints(const std::vector<Marker>& markers);

class Overlaps {
 public:
  // Surface points every options.point_spacing (0: fov_height / 40); `markers` as given.
  Overlaps(const Simulator& simulator, const RegistrationOptions& options,
           const std::vector<Marker>& markers);

  std::vector<Observation> observe(std::span<const View> views) const;
  // The markers each view measures, indices ascending (observe's, without the surface);
  // with a table, each where the view's table angle puts it.
  std::vector<std::vector<int>> markersSeen(std::span<const View> views) const;
  std::size_t markers() const { return markers_.points().size(); }

  // The pair test without ICP verification. The condition number is left out of pairs
  // that share neither markers nor enough overlap, which cannot be stable. With the
  // ReferencePoints method, the markers two views share do not register them to each other:
  // each registers to the markers' frame, or not (framed).
  PairCheck check(const View& a, const Observation& oa, const View& b, const Observation& ob) const;
  // check(a, oa, b, ob).passes(), without the condition number's value.
  bool passes(const View& a, const Observation& oa, const View& b, const Observation& ob) const;

  // Something could register to the view: its own surface constrains ICP (condition within
  // the limit) or it sees enough markers.
  bool constrained(const Observation& seen) const;

  // With the ReferencePoints method, whether a view seeing `markers` (indices) registers in
  // the markers' frame: min_markers of them, not all within marker_spread of one line.
  bool framed(const std::vector<int>& markers) const;

  // The markers' positions (indices), at table angle 0.
  std::vector<Vec3> markerPositions(const std::vector<int>& markers) const;

  const std::vector<SurfacePoint>& points() const { return points_.points(); }
  double spacing() const { return spacing_; }

 private:
  bool referencePoints() const;
  // check(), with the overlap's condition number (`value`); else only what passes() needs
  // (the condition only as within the limit or not, the overlap not at all when markers
  // register the pair).
  PairCheck test(const View& a, const Observation& oa, const View& b, const Observation& ob,
                 bool value) const;
  // Whether the markers (indices) are enough and spread enough to register by.
  bool registers(const std::vector<int>& markers) const;

  // The table angle each view is taken at (0 without a table).
  std::vector<double> tableAngles(std::span<const View> views) const;
  // The markers' positions as a view taken at table angle `angle` sees them.
  std::vector<Vec3> markerPositionsAt(double angle) const;
  // The markers each view measures, the view taken at `angles`' angle.
  std::vector<std::vector<int>> markersSeen(std::span<const View> views,
                                            const std::vector<double>& angles) const;
  // The markers each view measures, for views all taken at table angle `angle`.
  std::vector<std::vector<int>> markersSeenAt(std::span<const View> views, double angle) const;

  const Simulator& simulator_;
  const RegistrationOptions& options_;
  double spacing_ = 0;
  IndexedPoints points_;
  std::vector<Marker> marker_list_;
  IndexedPoints markers_;  // at table angle 0, indexed once: every observation measures them
};

}  // namespace scanplan::detail
