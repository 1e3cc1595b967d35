#pragma once
// The ICP links of a plan registered as the cell registers them, for the virtual
// inspection (docs/capability.md, "Virtual inspection"). In each run a view registered by
// ICP starts where the robot puts it, off by the registration's start perturbation, and
// point-to-plane ICP brings the points of its simulated cloud that the view it registers
// to measures too onto the surface that view measured in the same run: the part as
// designed, moved along the normal by that view's noise and acceptance errors, and by where the
// tangent planes at that view's points, at the scanner's own spacing, stand off a curved
// surface (samplingShift), the curvature averaged over the surface each simulated point
// stands for, as its noise is that of the scanner's points there. Every part of the link's error
// (the overlap's shape and extent, both views' noise and acceptance errors, the fixed cloud's
// sampling, the start, the correspondences found anew at every step) is ICP's own, not the model's
// covariance.

#include "core/kd_tree.h"
#include "planning/evaluation.h"

#include <scanplan/registration/registration.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace scanplan::detail {

// Where the fixed view's surface lies off the part as designed at a point of it (part
// frame, with the outward normal): its acceptance errors' shift along the normal, the
// standard deviation of its noise there, and the surface each of its points stands for
// (mm²; 0: the surface itself, unsampled).
struct SurfaceOffset {
  double shift = 0, sigma = 0, area = 0;
};
using FixedSurface = std::function<SurfaceOffset(const Vec3& at, const Vec3& normal)>;

// The points view `fixed` measured at `at`, as a point of view `moved` meets them (no
// shift): `sigma`, the standard deviation along `normal` of the mean of the fixed view's
// points within that point's share of the surface, so one fixed point's noise times
// √(moved density / fixed density) (where the fixed view is the sparser, neighbouring
// moved points meet the same fixed points and their noise); `area`, the surface each fixed
// point stands for.
SurfaceOffset fixedPoints(const Scanner& scanner, const View& fixed, const View& moved,
                          const Vec3& at, const Vec3& normal);

class SimulatedIcp {
 public:
  // `nominal`, the part as designed over every face ICP may meet; `chordal`, the chordal
  // tolerance of the part's mesh, mm.
  SimulatedIcp(const Nominal& nominal, const RegistrationOptions& options, double chordal);
  ~SimulatedIcp();

  // The rigid motion (part frame) that carries the points of `moved` (with their faces),
  // those of the moved view's cloud the fixed view measures too, from where they lie to where ICP
  // onto the fixed view's `surface` puts them; `spacing`, the moved cloud's point spacing, mm;
  // `seed` draws the start and the surface's noise. None for fewer than 100 points.
  std::optional<Pose> link(const std::vector<SurfacePoint>& moved, const FixedSurface& surface,
                           double spacing, std::uint64_t seed) const;

 private:
  struct Designed;
  // A moved point where it belongs, its face, its draw of the fixed surface's noise (in
  // standard deviations) and the curvature the fixed cloud's points bend by around it.
  struct Moved {
    SurfacePoint at;
    double noise = 0, curvature = 0;
  };
  // The twist (about `centre`) of one Gauss-Newton step from `pose`, and the
  // correspondences it used: those farther than `cutoff` are left out.
  struct Step {
    Twist twist = Twist::Zero();
    std::size_t used = 0;
  };
  Step step(const std::vector<Moved>& moved, const Pose& pose, const Vec3& centre,
            const FixedSurface& surface, double cutoff) const;

  // The sum of principal curvatures (signed for the outward normal) averaged over the
  // designed points within the square of side `spacing` a point at `p` stands for (a disc
  // of that area); the curvature of face `own` at `p` where none lies there.
  double footprintCurvature(const Vec3& p, int own, double spacing) const;

  // The point of the faces of the point's own (`own`) and of the designed points nearest
  // it that lies nearest `p`, on their exact surfaces where they have one, but within the
  // faces' bounds: a dense fixed cloud's nearest point. That cloud has points on every
  // face its view measures, however small; the designed points, 1 mm apart at random, may
  // miss a sliver.
  std::optional<SurfacePoint> correspondence(const Vec3& p, int own) const;

  const Nominal& nominal_;
  double bounds_;  // mm: an exact surface's point this near the face's triangles is on it
  std::unique_ptr<Designed> designed_;
  RegistrationOptions options_;
};

}  // namespace scanplan::detail
