#pragma once
// Registration feasibility (docs/registration.md): which views can be put together, by
// markers they share or by ICP on the overlap of their simulated clouds.

#include <scanplan/core/geometry.h>
#include <scanplan/core/progress.h>
#include <scanplan/core/view.h>
#include <scanplan/scanner/simulation.h>

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace scanplan {

// What carries a marker: the working plane (or a fixture standing on it), the rotary
// table, or the part itself. Markers on the part travel with it from one rest orientation
// to the next, so they can join the setups of a plan (docs/registration.md).
enum class MarkerCarrier { Plane, Table, Part };
std::string_view toString(MarkerCarrier carrier);  // "plane", "table", "part"
inline constexpr std::array kMarkerCarriers{MarkerCarrier::Plane, MarkerCarrier::Table,
                                            MarkerCarrier::Part};

// A reference marker (a retro-reflective dot), world frame.
struct Marker {
  Vec3 position = Vec3::Zero();  // mm
  Vec3 normal = Vec3::UnitZ();   // unit
  MarkerCarrier on = MarkerCarrier::Plane;
  int face = 0;         // the face of the part (or of a fixture) it is stuck on; 0: none, unknown
  bool placed = false;  // proposed and placed (--place-markers), not one of the spec's
};

// A rotary table under the part, as registration sees it. The plan's frame turns with the
// table, so a view taken at table angle a sees the markers of the working plane turned by
// -a about the axis; the table's markers and the part's stay where they are.
struct TableTurn {
  Vec3 origin = Vec3::Zero();                // world frame at angle 0
  Vec3 axis = Vec3::UnitZ();                 // unit
  std::function<double(const View&)> angle;  // the table angle each view is taken at, radians
};

// The table turning about `axis` through `origin`, each view taken at `angle`'s; none when
// no marker lies on the working plane (the others turn with the part, so every view sees
// them where they are).
std::shared_ptr<const TableTurn> tableTurnFor(const Vec3& origin, const Vec3& axis,
                                              const std::vector<Marker>& markers,
                                              std::function<double(const View&)> angle);

// `markers` as a view taken at table angle `angle` sees them in the plan's frame.
std::vector<Marker> markersAtTableAngle(std::vector<Marker> markers, const TableTurn& table,
                                        double angle);

// Markers on the working plane (z = 0) on a square grid of `step`, over `footprint` (a
// world box, usually the part's) grown by `margin`; the grid cells under the footprint
// itself are left out (the part covers them). \throw InputError for step <= 0.
std::vector<Marker> markerGrid(const Box& footprint, double step, double margin);

// Markers stuck on the part: a square grid of `step` over the part as it stands in the
// world (`mesh`, world frame), each where a vertical ray from above first meets a
// surface facing up within 45 degrees.
std::vector<Marker> markersOnPart(const TriangleMesh& mesh, double step);

// What the plan relies on to put its views together (docs/registration.md):
// - Markers: markers the views share, and ICP on overlaps where markers are too few;
// - Geometry: ICP on overlaps only (markers, if any, are not used);
// - Robot: the robot's pose accuracy, refined by ICP where overlaps constrain the pose. A
//   view registers when the accuracy is within the tolerance in the directions its
//   overlaps leave free; with an accuracy within the tolerance, every view does.
// - ReferencePoints: the markers' positions are known in one frame beforehand (measured by
//   photogrammetry, or markers on a plate, a table or fixtures): a view registers in that
//   frame when it sees min_markers of them, not all within marker_spread of one line; the
//   views that do not are joined by ICP on overlaps.
// Default: Markers when markers are given, else Geometry.
enum class RegistrationMode { Default, Markers, Geometry, Robot, ReferencePoints };
std::string_view toString(RegistrationMode mode);
// The modes a spec or a plan names (every one but Default).
inline constexpr std::array kRegistrationModes{RegistrationMode::Markers,
                                               RegistrationMode::Geometry, RegistrationMode::Robot,
                                               RegistrationMode::ReferencePoints};

struct RegistrationOptions {
  RegistrationMode method = RegistrationMode::Default;
  double robot_accuracy = 0;  // mm, the robot's pose accuracy (Robot only; then required > 0)
  // A plan whose views do not all register fails `verify` (exit 3), unless this is false.
  bool required = true;
  // Markers: two views register when they share this many markers, not all within
  // `marker_spread` of one line; ReferencePoints: a view registers when it sees this many.
  // 3 is the fewest that fix a rigid transform; 4 adds one to spare, should a marker be
  // misread.
  int min_markers = 3;
  double marker_spread = 10;  // mm
  // The standard deviation of a marker centre as a view measures it, per axis, mm, for the
  // registration's error (docs/capability.md, "Error budget"); 0: a twentieth of the
  // scanner's point spacing, the centroiding precision assumed for a circular marker.
  double marker_sigma = 0;
  // ICP: the surface both views measure, as a share of what each measures, and the
  // condition number of its 6x6 point-to-plane covariance (Gelfand et al. 2003).
  double min_overlap = 0.2;
  double max_condition = 100;
  double point_spacing = 0;  // surface points for overlaps, mm; 0: fov_height / 40
  // Verification of the pairs the registration uses: Open3D point-to-plane ICP between
  // the simulated noisy clouds, from a start perturbed by `perturbation` mm and
  // `perturbation_angle` degrees; the pair fails when the points of the moved view end up,
  // in RMS, more than `tolerance` mm from where they belong.
  bool verify = true;
  // The scanner's software aligns each scan by ICP as it is taken, to the scans taken
  // before it: a view registered by ICP must follow one it registers to. False: the scans
  // are aligned once all are taken (from the robot's poses, refined by ICP), and views
  // registered by ICP may come in any order.
  bool aligned_as_taken = true;
  double cloud_spacing = 0;  // mm; 0: fov_height / 150 (about 1.5 mm for 225 mm)
  double perturbation = 3;
  double perturbation_angle = 2;
  double tolerance = 0.1;
  // Bridging: views added until the graph is connected, at most this many.
  bool bridging = true;
  int max_bridging_views = 20;
  std::uint64_t seed = 1;
  // The cell's rotary table, when views are taken at other angles than the plan's and
  // markers lie on the working plane; none: every view sees the markers where they are.
  std::shared_ptr<const TableTurn> table;
};

// The standard deviation of a marker centre, mm: `options.marker_sigma`, else a twentieth of
// the scanner's point spacing.
double markerSigma(const RegistrationOptions& options, const Scanner& scanner);

// \throw InputError naming `source` and the option out of range.
void validate(const RegistrationOptions& options, const std::string& source);

// True when the robot alone registers every view: method Robot, its accuracy within the
// tolerance.
bool robotRegistersAll(const RegistrationOptions& options);

// The condition number (largest over smallest eigenvalue) of the covariance of
// point-to-plane constraints [p x n; n] of the points, centred at their centroid and
// scaled by their mean distance to it (Gelfand et al., "Geometrically stable sampling for
// the ICP algorithm", 2003). Infinite for a plane, a sphere or a cylinder, and for fewer
// than 6 points. With `weights` (one per point, e.g. the area it stands for), each
// point's constraint counts by its weight.
double icpCondition(std::span<const Vec3> points, std::span<const Vec3> normals,
                    std::span<const double> weights = {});
// Whether icpCondition(points, normals, weights) is at most `limit`: the same answer,
// found without the 6 x 6 eigenvalues where a bound on them already exceeds the limit.
bool icpConditionWithin(std::span<const Vec3> points, std::span<const Vec3> normals, double limit,
                        std::span<const double> weights = {});

// True when at least `min_count` points are given and they are not all within `spread`
// of one line.
bool markersRegister(std::span<const Vec3> positions, int min_count, double spread);

// ICP between the simulated clouds of two views (docs/registration.md): where the points
// of the moved view end up after ICP, against where they belong.
struct IcpCheck {
  double error = std::numeric_limits<double>::infinity();      // RMS displacement left, mm
  double max_error = std::numeric_limits<double>::infinity();  // largest displacement, mm
  double rotation = 0;     // angle of the rotation left, degrees
  double fitness = 0;      // share of the moved cloud with a correspondence
  double rmse = 0;         // of the correspondences, mm
  std::size_t points = 0;  // of the moved cloud
  bool passed = false;     // error <= tolerance
};
IcpCheck checkIcp(const Simulator& simulator, const View& fixed, const View& moved,
                  const RegistrationOptions& options);

// A view's simulated noisy cloud at the options' cloud spacing, with the surface normals at
// its points (the ICP target's): made once per view and used by every pair it is in.
struct IcpCloud {
  int id = 0;  // the view's
  std::vector<Vec3> points, normals;
};
IcpCloud icpCloud(const Simulator& simulator, const View& view, const RegistrationOptions& options);

// The spacing of the surface points the overlaps are found on, mm:
// `options.point_spacing`, else a 40th of the scanner's field height.
double overlapSpacing(const RegistrationOptions& options, const Scanner& scanner);

// The spacing of the clouds ICP verifies pairs on, mm: `options.cloud_spacing`, else a
// 150th of the scanner's field height.
double icpCloudSpacing(const RegistrationOptions& options, const Scanner& scanner);

// checkIcp on clouds made beforehand.
IcpCheck checkIcp(const Simulator& simulator, const IcpCloud& fixed, const IcpCloud& moved,
                  const RegistrationOptions& options);

// What is known about one pair of views.
struct PairCheck {
  int a = 0, b = 0;  // view ids, a < b
  std::size_t shared_markers = 0;
  bool markers = false;                 // shared markers register them
  double overlap_area = 0;              // mm², measured by both
  double overlap_a = 0, overlap_b = 0;  // that area over what a, b measure
  // Of the overlap; left infinite where the overlap is too small to register.
  double condition = std::numeric_limits<double>::infinity();
  bool stable = false;          // overlap and condition within the limits
  std::optional<IcpCheck> icp;  // when verified
  // The pair test passes: the views share markers that register them, or a stable overlap
  // (which ICP, when verified, may still fail).
  bool passes() const { return markers || stable; }
  bool registrable() const { return markers || (stable && (!icp || icp->passed)); }
};

// How a view is registered: it fixes the frame (Reference), by markers it shares with the
// view it registers to, by ICP on their overlap, by the robot's accuracy, or by the known
// markers it sees (ReferencePoints, into their frame).
enum class RegistrationMethod { Reference, Markers, Icp, Robot, ReferencePoints, None };
std::string_view toString(RegistrationMethod method);
// Every method a view may be registered by (every one but None).
inline constexpr std::array kRegistrationMethods{
    RegistrationMethod::Reference, RegistrationMethod::Markers, RegistrationMethod::Icp,
    RegistrationMethod::Robot, RegistrationMethod::ReferencePoints};

// How one view is registered: to the view `to` (an id; 0 for the reference view, which
// fixes the frame, for views registered by reference points, into the markers' frame, and
// for views that cannot be registered).
struct ViewRegistration {
  RegistrationMethod method = RegistrationMethod::None;
  int to = 0;
  bool bridge = false;  // added to join the registration graph
  // Something could register to it: its own surface constrains ICP (condition within the
  // limit) or it sees enough markers. A view that is not can only be registered by
  // adding markers.
  bool constrained = true;
  std::vector<int> markers;  // the markers it sees: indices into the markers registered by
};

struct Registration {
  RegistrationMode method = RegistrationMode::Default;  // as used: never Default once planned
  bool required = true;                                 // RegistrationOptions::required
  bool aligned_as_taken = true;                         // RegistrationOptions::aligned_as_taken
  double robot_accuracy = 0;                            // mm, with the Robot method
  std::vector<ViewRegistration> views;                  // per view, in the order of the views
  std::vector<PairCheck> pairs;                         // pairs that overlap or share markers
  std::size_t markers = 0;                              // markers in the cell
  std::size_t components = 0;                           // of the registration graph, after bridging
  std::size_t bridging_views = 0;
  int reference = 0;      // id of the reference view (0: no view)
  bool verified = false;  // ICP pairs were verified

  std::size_t registered() const;
  // True when the pair registers: its views share markers, or it passed ICP verification
  // (is stable, without verification).
  bool links(const PairCheck& pair) const;
  // The checked pair of views a and b (either order); null when they were not checked.
  const PairCheck* pair(int a, int b) const;
  // links() of the pair of views a and b; false when they were not checked.
  bool linked(int a, int b) const;
};

// Appends `from`, the registration of views registered apart from `into`'s (in another rest
// orientation), with its view ids shifted by `id_offset`: views, pairs and counts; the
// reference stays `into`'s, unless it has none.
void appendRegistration(Registration& into, Registration from, int id_offset);

// Checks every pair of `views` and keeps a spanning forest of registrable pairs (markers
// first, then the most stable ICP pairs, each verified before it is used), which decides
// the views that register; each registers along the chain of registering pairs whose
// errors add up least. It adds no views: planning's bridging does (planning/bridging.h).
Registration registerViews(const Simulator& simulator, std::span<const View> views,
                           const std::vector<Marker>& markers, const RegistrationOptions& options,
                           const Progress& progress = {});

// Markers proposed so that views register where their geometry does not: a spanning
// forest over pairs of `views` that see enough `candidates` in common (the pairs
// `registration` links already first), then the fewest candidates giving each of its
// pairs min_markers in common (minimumMulticover), and more where those lie on a line
// (markersRegister). With reference points, the fewest candidates giving each view
// registered to nothing min_markers, counting the `placed` markers it sees already, and
// more where those lie on a line.
struct MarkerProposal {
  std::vector<Marker> markers;
  std::size_t views = 0;        // views registered to nothing that the proposal joins
  std::size_t lower_bound = 0;  // no proposal giving each of them min_markers is smaller
                                // (the multicover's bound)
  // Ids of the views registered to nothing that no candidate position serves: each sees
  // fewer than min_markers of them or only ones near a line (reference points), or shares
  // that many with no view it could register to (pairs).
  std::vector<int> unserved;

  // Adds `other`'s markers, views, bound and views unserved (another rest orientation's).
  void append(const MarkerProposal& other) {
    markers.insert(markers.end(), other.markers.begin(), other.markers.end());
    views += other.views;
    lower_bound += other.lower_bound;
    unserved.insert(unserved.end(), other.unserved.begin(), other.unserved.end());
  }
};
MarkerProposal proposeMarkers(const Simulator& simulator, std::span<const View> views,
                              const Registration& registration,
                              const std::vector<Marker>& candidates,
                              const std::vector<Marker>& placed,
                              const RegistrationOptions& options);

}  // namespace scanplan
