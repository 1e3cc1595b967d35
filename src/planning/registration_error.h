#pragma once
// How far each view of a plan may lie from where its registration puts it
// (docs/capability.md, "Error budget"): the covariance of a small rigid motion per view,
// from the method that registers it and the chain of views it registers through.

#include "registration/rigid_fit.h"

#include <scanplan/cad/part.h>
#include <scanplan/plan/plan.h>
#include <scanplan/spec/spec.h>

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <random>
#include <span>
#include <vector>

namespace scanplan::detail {

// A small rigid motion (rotation w, radians, then translation t, mm, about the world's
// origin): a point p moves by w x p + t.
using Twist = Eigen::Matrix<double, 6, 1>;

// The motion of `p` under `twist`.
Vec3 displacement(const Twist& twist, const Vec3& p);
// The rigid motion of a twist: a turn by w (about the origin), then a shift by t.
Pose poseOf(const Twist& twist);
// The row mapping a twist to the displacement of `p` along `n`: n . (w x p + t).
Eigen::Matrix<double, 1, 6> alongNormal(const Vec3& p, const Vec3& n);

// Covariance of point-to-plane ICP on an overlap: per point its position, normal and the
// variance of its distance along the normal (both views' noise, over the points it stands
// for).
TwistCovariance icpCovariance(std::span<const Vec3> points, std::span<const Vec3> normals,
                              std::span<const double> variances);

// How far along the outward normal, on average, the tangent planes at a fixed cloud's points
// lie off a surface whose principal curvatures sum to `curvature` (1/mm), the cloud `area`
// mm² per point. Point to plane, a moved point meets its nearest fixed point a step d away,
// whose plane stands off the surface there by the curvature along d times d²/2; over the
// square cell of that area around the fixed point, curvature × area / 24.
double samplingShift(double curvature, double area);

// A view's registration error: the covariance of its motion in the frame of its setup,
// through the chain of views it registers by (its own link's and its parent's added);
// `placed` false when it registers to nothing (its points join no frame).
struct ViewError {
  TwistCovariance covariance = TwistCovariance::Zero();
  TwistCovariance link = TwistCovariance::Zero();  // its own registration's
  // Its own registration's systematic motion: an ICP link's, where the fixed view's tangent
  // planes at its points stand off the overlap's curved faces (samplingShift).
  Twist bias = Twist::Zero();
  std::optional<std::size_t> parent;  // the view it registers to (none: its setup's frame)
  bool placed = true;
  std::size_t frame = 0;  // its setup's frame (PlannedOrientation::frame)
  // Registered by markers: the lower Cholesky factor of its group's joint covariance
  // (marker_adjustment.h), shared by the group's views, and its 6 rows' place in it; its
  // parent is the group's root.
  std::shared_ptr<const Eigen::MatrixXd> adjusted;
  std::size_t slot = 0;
};

// Per view of `plan` (in its order). Without a registration in the plan every view is
// placed, without error: the plan assumed them registered.
std::vector<ViewError> registrationErrors(const Part& part, const ResolvedSpec& spec,
                                          const Plan& plan);

// Where view `v` of `plan`, of orientation `k`, sees the markers of its orientation (in
// their order): those of the working plane turned against the table angle it is taken at.
std::vector<Vec3> markerPositions(const Plan& plan, std::size_t k, std::size_t v);

// The chains of `errors`: every view after the view it registers to, and that view (none:
// its setup's frame, or a loop cut where it closes).
struct Chains {
  std::vector<std::size_t> order;
  std::vector<std::optional<std::size_t>> parents;
};
Chains chainsOf(const std::vector<ViewError>& errors);

// L with L L^T `covariance` (negative eigenvalues taken as 0).
TwistCovariance squareRoot(const TwistCovariance& covariance);

// Draws of the views' motions as their chains make them: each link's error drawn once,
// and a view moved by its own link's and by every link its parent's chain runs through.
// Views that register through the same views move together by those links' errors, so
// only the links apart move them against one another.
class TwistDraws {
 public:
  explicit TwistDraws(const std::vector<ViewError>& errors);
  // One draw of every link, each view's motion the sum along its chain.
  std::vector<Twist> draw(std::mt19937_64& random) const;

 private:
  std::vector<TwistCovariance> roots_;  // per view, its link's covariance's square root
  std::vector<Twist> biases_;           // per view, its link's systematic motion
  Chains chains_;
  // The groups adjusted together, each drawn at once: its factor and its views.
  std::vector<std::pair<std::shared_ptr<const Eigen::MatrixXd>, std::vector<std::size_t>>> groups_;
  std::vector<int> group_of_;       // per view, its group (-1: none)
  std::vector<std::size_t> slots_;  // per view, its place in its group's factor
};

}  // namespace scanplan::detail
