#pragma once
// A study (docs/study.md): the plans of parts x scanners x specs x orientations x coverage
// targets, read from YAML.
//
//   parts: [parts/housing.step, parts/bracket.stp]     # required; relative to the file
//   scanners: [generic-structured-light, heads/my-head.yaml]   # presets or scanner files
//   specs: [specs/gdt.yaml]                            # default: none (one global task)
//   orientations: [auto, all]                          # part.rest: auto, all, drawn, a face id
//   coverage: [1, 0.95]                                # shares of the coverable samples
//   registration: true                                 # false: plans without registration

#include <optional>
#include <string>
#include <vector>

namespace scanplan {

// One plan of a study. Empty strings leave the setting to the spec (and its defaults).
struct StudyRow {
  std::string name;     // unique within the study; a folder name: letters, digits, . _ -
  std::string part;     // absolute path
  std::string scanner;  // a preset name or a scanner file's absolute path
  std::string spec;     // absolute path
  std::string rest;     // auto, all, drawn or a face id
  std::optional<double> coverage;
};

struct Study {
  std::string file;
  bool registration = true;
  std::vector<StudyRow> rows;  // every combination, parts varying slowest
};

// The largest study a file may ask for.
inline constexpr std::size_t kMostStudyRows = 10'000;

// \throw InputError naming the file and the key: no such file, not YAML, an unknown key,
//        no parts, an orientation that is not auto, all, drawn or a face id, a coverage
//        outside (0, 1], or more than kMostStudyRows plans.
Study loadStudy(const std::string& path);

}  // namespace scanplan
