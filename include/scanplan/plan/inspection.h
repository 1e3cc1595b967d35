#pragma once
// A virtual inspection of a plan (docs/capability.md, "Virtual inspection"): what each
// characteristic measures over Monte Carlo runs of the plan's scans, against the value of
// the part simulated.

#include <scanplan/core/geometry.h>
#include <scanplan/plan/plan.h>

#include <string>
#include <vector>

namespace scanplan {

// A deviation declared on the simulated part, on its faces (part frame): a face offset
// along its normal, bowed (its middle raised by `amount` along the normal, its rim kept),
// moved by `move`, or a cylinder's diameter changed by `amount`.
struct Deviation {
  enum class Kind { Offset, Bow, Move, Diameter };
  Kind kind = Kind::Offset;
  std::vector<int> faces;  // 1-based ids
  double amount = 0;       // mm
  Vec3 move = Vec3::Zero();
};

// One characteristic as the inspection measures it.
struct InspectedCharacteristic {
  int characteristic = 0;     // its id
  bool evaluated = false;     // its value could be found in every run
  std::string not_evaluated;  // why not, when not
  double true_value = 0;      // of the simulated part, by the same evaluation without error
  double mean = 0;            // of the measured values
  double bias = 0;            // mean - true value
  double uncertainty = 0;     // U: twice the runs' standard deviation (k = 2)
  double ratio = 0;           // width / (2 (U + |bias|)); 0 without a width
  // U + |bias| is known within ± this at 95 % from the runs' number (spreadPrecision)
  double precision = 0;
  // The error |measured - true| that 95 % of the runs stay under (the smallest that at
  // least 95 % do): how the capability model defines its U, which it is compared with
  double error_95 = 0;
  Verdict verdict = Verdict::NotCapable;
  double points = 0;           // on its faces, per run on average
  std::vector<double> values;  // per run
};

struct Inspection {
  int runs = 0;                    // taken
  double precision_asked = 0;      // InspectionOptions::precision; 0: a fixed number of runs
  std::vector<int> imprecise;      // ids of those the runs ran out before knowing so well
  double spacing = 0;              // mm, of the simulated points at the standoff
  std::size_t views_left_out = 0;  // registered to nothing: their points join no frame
  // Registered by ICP in every run, on its clouds; the other ICP links are drawn from the
  // capability model's covariance.
  std::size_t icp_registered = 0;
  // Of those links over all runs: registered again from another start after landing
  // further from where the view belongs than registration.tolerance, as the cell's operator
  // registers again a view that does not fit; and still that far after three starts, left
  // so in their run.
  std::size_t icp_restarted = 0, icp_failed = 0;
  std::vector<Deviation> deviations;
  std::vector<InspectedCharacteristic> characteristics;
};

}  // namespace scanplan
