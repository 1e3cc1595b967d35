#pragma once
// What OCCT 7.6's AP242 PMI reader leaves out, read from the STEP text itself:
// - tolerance magnitudes written as a complex measure entity
//   (LENGTH_MEASURE_WITH_UNIT & MEASURE_REPRESENTATION_ITEM), which it reads as 0;
// - the unit of dimension nominal values written as 'nominal value' measure
//   representation items that are also qualified representation items, which it leaves
//   unconverted (inches stay inches; the unqualified ones it converts);
// - the items of an ITEM_IDENTIFIED_REPRESENTATION_USAGE written as a SET_REPRESENTATION_ITEM
//   (how the NIST models name a datum feature's faces), which it reads as none.

#include <map>
#include <string>
#include <vector>

namespace scanplan::detail {

struct StepPmiMeasures {
  std::map<std::string, double> tolerance_magnitudes;  // by tolerance name, mm
  // mm per unit of the qualified 'nominal value' items (when they share one unit)
  double nominal_value_scale = 1;
};

// Scans a STEP Part 21 file. Never throws on content it does not understand: those
// entries are simply absent from the result.
StepPmiMeasures scanStepPmiMeasures(const std::string& path);

// The item-identified usages whose items form a SET_REPRESENTATION_ITEM: the entity id of
// each one's definition → the entity ids of its items, in the file's order.
std::map<long, std::vector<long>> scanSetItemUsages(const std::string& path);

}  // namespace scanplan::detail
