#pragma once
// The registration as a run of the cell makes it, for the virtual inspection
// (docs/capability.md, "Virtual inspection"): each view measures the centres of the markers
// it sees with noise; the views of a group registered by shared markers are placed by
// fitting all their poses and one position per marker to those centres at once (marker
// adjustment, by alternating rigid fits), the views registered by reference points by the
// rigid fit of their centres onto the known ones; and the placements compose along the
// chains. The capability model's first-order covariances of those fits
// (registration_error.h, marker_adjustment.h) are not used, so the inspection checks
// them. ICP links are given by the inspection, registered by ICP in each run, or else take
// a draw of the covariance the model gives them; the robot and marker links across setups
// take such a draw (the two setups' markers lie in frames of their own).

#include "planning/registration_error.h"

#include <scanplan/core/view.h>

#include <map>
#include <memory>
#include <optional>
#include <random>
#include <vector>

namespace scanplan::detail {

class SimulatedRegistration {
 public:
  // `errors` as registrationErrors gives them for `plan`; `marker_sigma`, mm per axis, the
  // noise of a marker's centre as a view measures it.
  SimulatedRegistration(const Plan& plan, const std::vector<ViewError>& errors,
                        double marker_sigma);
  // One run: per view, the rigid motion that carries its points from where they are to
  // where the registration puts them (world); identity for views placed nowhere. Where
  // `links` gives a view's own link (its motion against the view it registers to, as ICP
  // found it in the run: simulated_icp.h), that replaces the draw of its covariance.
  std::vector<Pose> draw(std::mt19937_64& random,
                         const std::vector<std::optional<Pose>>& links = {}) const;

 private:
  enum class Kind { Fixed, Known, Drawn };  // Fixed: the reference, or placed by its group
  struct Link {
    Kind kind = Kind::Fixed;
    std::map<int, Vec3> seen;                        // marker: where the view sees its centre
    TwistCovariance root = TwistCovariance::Zero();  // Drawn: L with L L^T its covariance
    Twist bias = Twist::Zero();  // Drawn: its systematic motion (ViewError::bias)
  };
  // A group adjusted together: its views, the root (held fixed) first, and per view the
  // markers it sees that another view of the group sees too: (index into the group's
  // markers, marker).
  struct Group {
    std::vector<std::size_t> views;
    std::size_t markers = 0;
    std::vector<std::vector<std::pair<std::size_t, int>>> seen;
    std::shared_ptr<const Eigen::MatrixXd> factor;  // ViewError::adjusted
  };
  using Measured = std::vector<std::map<int, Vec3>>;  // per view, the centres it measured
  // The group's markers that two of its views see, and where each view sees them.
  void indexMarkers(Group& group) const;
  // The group's views' motions relative to its root, into `own`.
  void adjust(const Group& group, const Measured& measured, std::vector<Pose>& own) const;
  // The first-order solution of the group's fit for the centres `measured`: the start.
  std::vector<Pose> start(const Group& group, const Measured& measured) const;

  std::vector<std::size_t> slots_;  // per view, its place in its group's factor

  std::vector<Link> links_;
  std::vector<Group> groups_;
  Chains chains_;
  double sigma_;
};

}  // namespace scanplan::detail
