#pragma once
// Geometric dimensioning and tolerancing read from AP242 semantic PMI (ISO 10303-242),
// as OpenCASCADE's XDE exposes it. These are the `gdt` task's targets.

#include <string>
#include <vector>

namespace scanplan {

// A geometric tolerance (ASME Y14.5 / ISO 1101 characteristic) on one or more faces.
struct GeometricTolerance {
  std::string type;  // "flatness", "position", "profile_of_surface", ...
  double value = 0;  // tolerance zone size, mm (or degrees for angularity)
  // Datum references in order of precedence: "A", "B"; a common datum (two datum features
  // taken as one, COMMON_DATUM_LIST) as "A-B".
  std::vector<std::string> datums;
  std::vector<int> faces;  // 1-based ids of the toleranced faces
};

// A dimension with its tolerance (size or location).
struct Dimension {
  std::string type;             // "diameter", "linear_distance", "radius", ...
  double value = 0;             // nominal value, mm (degrees for angular dimensions)
  double lower = 0, upper = 0;  // allowed deviation below and above the value, as
                                // magnitudes (>= 0), mm; both 0 when none is given
  std::vector<int> faces;       // faces of the dimensioned features, both ends
};

// A datum feature: the faces that establish datum `name`.
struct Datum {
  std::string name;  // "A", "B", ...
  std::vector<int> faces;
};

struct Gdt {
  std::vector<GeometricTolerance> tolerances;
  std::vector<Dimension> dimensions;
  std::vector<Datum> datums;     // one per datum letter, faces merged
  std::size_t datum_labels = 0;  // datum entries in the file (AP242 repeats a datum
                                 // for each tolerance frame that references it)

  bool empty() const { return tolerances.empty() && dimensions.empty() && datums.empty(); }
};

// One thing the inspection must verify: a geometric tolerance or a dimension with a value,
// on its faces (plan.json `characteristics`).
struct Characteristic {
  int id = 0;                       // 1-based: the tolerances in file order, then dimensions
  std::string kind;                 // the tolerance's or the dimension's type
  bool dimension = false;           // a dimension (a nominal value with limits)
  double value = 0;                 // tolerance zone; a dimension's nominal value
  double lower = 0, upper = 0;      // the limits: [0, zone] for a tolerance, the nominal
                                    // value less and plus its deviations for a dimension
  std::vector<std::string> datums;  // in order of precedence
  std::vector<int> faces;           // sorted, unique

  // The tolerance's width: the zone, or the span between a dimension's limits (0: a
  // dimension given without deviations, which nothing verifies against).
  double width() const { return upper - lower; }
};

// The characteristics of `gdt`: every geometric tolerance, then every dimension with a
// value, each with its faces.
std::vector<Characteristic> characteristics(const Gdt& gdt);

// The datum letters of a datum reference: "A" for "A", "A" and "B" for a common "A-B".
std::vector<std::string> datumLetters(const std::string& reference);
// The faces of the datum features a reference names, sorted; none when a letter names none.
std::vector<int> datumFaces(const Gdt& gdt, const std::string& reference);

// The faces of the datum features `c` references, sorted and unique.
std::vector<int> datumFaces(const Gdt& gdt, const Characteristic& c);

// Whether every datum a geometric tolerance references names faces (a dimension has no
// datums): else its frame cannot be fitted.
bool datumsLinked(const Gdt& gdt, const Characteristic& c);

// Whether a measurement can verify `c`: it has a width, faces, and datums that name faces.
bool verifiable(const Gdt& gdt, const Characteristic& c);

// The faces of the verifiable characteristics of `gdt`, sorted and unique.
std::vector<int> verifiedFaces(const Gdt& gdt);
// The faces of the datum features they reference, sorted and unique.
std::vector<int> verifiedDatumFaces(const Gdt& gdt);
// Both: every face a verifiable characteristic is judged on, sorted and unique.
std::vector<int> judgedFaces(const Gdt& gdt);

}  // namespace scanplan
