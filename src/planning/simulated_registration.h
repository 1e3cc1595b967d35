#pragma once
// The registration as a run of the cell makes it, for the virtual inspection
// (docs/capability.md, "Virtual inspection"): each view measures the centres of the markers
// it sees with noise, and is placed by the rigid fit of those centres onto the centres the
// view it registers to measured (reference points: onto the known centres), the fits
// composed along the chain. The capability model's first-order covariance of that fit
// (registration_error.h) is not used for marker links, so the inspection checks it. ICP
// links and the robot take a draw of the covariance the model gives them: an ICP run per
// link and per run would take minutes.

#include "planning/registration_error.h"

#include <scanplan/core/view.h>

#include <map>
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
  // where the registration puts them (world); identity for views placed nowhere.
  std::vector<Pose> draw(std::mt19937_64& random) const;

 private:
  enum class Kind { Fixed, Markers, Known, Drawn };
  struct Link {
    Kind kind = Kind::Fixed;
    std::map<int, Vec3> seen;                        // marker: where the view sees its centre
    std::vector<int> fitted;                         // the markers its fit takes (shared, or known)
    TwistCovariance root = TwistCovariance::Zero();  // Drawn: L with L L^T its covariance
  };
  std::vector<Link> links_;
  Chains chains_;
  double sigma_;
};

}  // namespace scanplan::detail
