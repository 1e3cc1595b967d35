#include "core/assets.h"
#include "scanner/sensor_yaml.h"

#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>
#include <scanplan/scanner/sensor.h>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <vector>

namespace scanplan {

double Scanner::baseline() const { return standoff * std::tan(radians(triangulation_angle)); }

double Scanner::reach() const {
  // The far end of the volume is its widest: the field of view grows with the distance.
  const double half_depth = depth_of_field / 2;
  const double far = (standoff + half_depth) / standoff;
  return std::sqrt(half_depth * half_depth + std::pow(fov_width / 2 * far, 2) +
                   std::pow(fov_height / 2 * far, 2));
}

Vec3 Scanner::projectorInScanner() const { return Vec3(baseline(), 0, 0); }

std::vector<Vec3> Scanner::camerasInScanner() const {
  std::vector<Vec3> at = {Vec3::Zero()};
  if (cameras == 2) at.emplace_back(2 * baseline(), 0, 0);
  return at;
}

Box Scanner::body() const {
  Box box;
  box.add(Vec3(-body_margin, -body_margin, -body_depth));
  box.add(Vec3((cameras == 2 ? 2 : 1) * baseline() + body_margin, body_margin, body_margin));
  return box;
}

double Scanner::acquisitionSeconds() const {
  return sweep_speed > 0 ? fov_height / sweep_speed : patterns * exposure;
}

void validate(const Scanner& s, const std::string& source) {
  auto fail = [&](const std::string& what) {
    throw InputError(source, "scanner '" + s.name + "': " + what);
  };
  auto positive = [&](double v, const char* name) {
    if (!(v > 0) || !(v <= kLongestLength))
      fail(std::string(name) + " must be a positive number of mm, at most 100,000 (100 m)");
  };
  auto angle = [&](double v, const char* name, double lo_inclusive) {
    bool ok = std::isfinite(v) && v < 90 && (lo_inclusive == 0 ? v >= 0 : v > 0);
    if (!ok)
      fail(std::string(name) + " must be within " + (lo_inclusive == 0 ? "[0, 90)" : "(0, 90)") +
           " degrees");
  };
  if (s.cameras != 1 && s.cameras != 2) fail("cameras must be 1 or 2");
  positive(s.standoff, "standoff");
  positive(s.depth_of_field, "depth_of_field");
  positive(s.fov_width, "fov_width");
  positive(s.fov_height, "fov_height");
  positive(s.point_spacing, "point_spacing");
  // A noise as wide as the measuring depth would make clouds of nothing but noise (and,
  // far beyond, of infinities).
  if (!(s.noise_sigma >= 0) || !(s.noise_sigma < s.depth_of_field))
    fail("noise_sigma must be zero or positive, and less than the depth of field");
  if (!(s.body_margin >= 0) || !(s.body_margin <= kLongestLength))
    fail("body_margin must be zero or a positive number of mm, at most 100,000 (100 m)");
  positive(s.body_depth, "body_depth");
  angle(s.triangulation_angle, "triangulation_angle", 1);
  angle(s.max_camera_angle, "max_camera_angle", 1);
  angle(s.max_projector_angle, "max_projector_angle", 1);
  angle(s.reflection_cone, "reflection_cone", 0);
  if (!(s.patterns >= 1 && s.patterns <= 1000 && s.patterns == std::round(s.patterns)))
    fail("patterns must be a whole number within [1, 1000]");
  if (!(s.exposure > 0 && s.exposure <= 10)) fail("exposure must be within (0, 10] s");
  if (!(s.sweep_speed == 0 || (s.sweep_speed >= 1 && s.sweep_speed <= 10000)))
    fail("sweep_speed must be 0 (a fringe head) or within [1, 10000] mm/s");
  for (const auto& [value, name] : {std::pair{s.probing_form, "probing_form"},
                                    {s.probing_size, "probing_size"},
                                    {s.sphere_spacing, "sphere_spacing"},
                                    {s.flatness_error, "flatness_error"}})
    if (!(value >= 0 && value < s.depth_of_field))
      fail(std::string(name) +
           " must be zero (not stated) or a positive number of mm, less "
           "than the depth of field");
  if (!(s.depth_of_field < 2 * s.standoff))
    fail(
        "depth_of_field must be shorter than twice the standoff (the volume would reach the "
        "camera)");
  if (s.point_spacing > std::min(s.fov_width, s.fov_height))
    fail("point_spacing must be smaller than the field of view");
  // A simulated cloud has a point per spacing² of the field of view.
  constexpr double kMostPoints = 1e8;
  if (s.fov_width / s.point_spacing * (s.fov_height / s.point_spacing) > kMostPoints)
    fail(
        fmt::format("point_spacing gives more than 100 million points over the field of view: "
                    "at least {:.3g} mm",
                    std::sqrt(s.fov_width * s.fov_height / kMostPoints)));
}

const std::array<ScannerParameter, 20>& scannerParameters() {
  static const std::array<ScannerParameter, 20> table = {{
      {"standoff", &Scanner::standoff},
      {"depth_of_field", &Scanner::depth_of_field},
      {"fov_width", &Scanner::fov_width},
      {"fov_height", &Scanner::fov_height},
      {"triangulation_angle", &Scanner::triangulation_angle},
      {"max_camera_angle", &Scanner::max_camera_angle},
      {"max_projector_angle", &Scanner::max_projector_angle},
      {"reflection_cone", &Scanner::reflection_cone},
      {"point_spacing", &Scanner::point_spacing},
      {"noise_sigma", &Scanner::noise_sigma},
      {"cameras", &Scanner::cameras},
      {"body_margin", &Scanner::body_margin},
      {"body_depth", &Scanner::body_depth},
      {"patterns", &Scanner::patterns},
      {"exposure", &Scanner::exposure},
      {"sweep_speed", &Scanner::sweep_speed},
      {"probing_form", &Scanner::probing_form},
      {"probing_size", &Scanner::probing_size},
      {"sphere_spacing", &Scanner::sphere_spacing},
      {"flatness_error", &Scanner::flatness_error},
  }};
  return table;
}

namespace {

Scanner presetIn(const std::string& name, std::vector<std::string>& chain);

// Applies a YAML mapping of scanner parameters on top of `scanner`; `chain`: the presets
// being read, each naming the next.
Scanner fromMapping(const YAML::Node& node, Scanner scanner, const std::string& source,
                    std::vector<std::string>& chain) {
  if (!node.IsMap())
    throw InputError(source, "the scanner must be a preset name or a mapping of parameters");
  if (node["preset"]) scanner = presetIn(node["preset"].as<std::string>(), chain);
  for (const auto& item : node) {
    const std::string key = item.first.as<std::string>();
    if (key == "preset") continue;
    if (key == "name") {
      scanner.name = item.second.as<std::string>();
      continue;
    }
    const auto& table = scannerParameters();
    const auto parameter = std::find_if(table.begin(), table.end(),
                                        [&](const ScannerParameter& p) { return key == p.name; });
    if (parameter == table.end())
      throw InputError(source, "unknown scanner parameter '" + key + "'");
    try {
      scanner.*parameter->value = item.second.as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(source, "scanner parameter '" + key + "' must be a number");
    }
  }
  validate(scanner, source);
  return scanner;
}

// Takes a document's events and keeps none: enough to tell whether another follows.
class IgnoredEvents : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

// Refuses a key given twice in `node` or in a mapping it holds (a scanner file is flat; a
// spec read for its scanner holds it one level down): yaml-cpp keeps the first silently.
void refuseRepeatedKeys(const YAML::Node& node, const std::string& path, int depth = 0) {
  if (!node.IsMap() || depth > 1) return;
  std::set<std::string> keys;
  for (const auto& entry : node) {
    const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : std::string();
    if (!key.empty() && !keys.insert(key).second)
      throw InputError(path, "key '" + key + "' given twice");
    refuseRepeatedKeys(entry.second, path, depth + 1);
  }
}

YAML::Node loadYaml(const std::string& path) {
  requireInputFile(path);
  try {
    std::ifstream in(path, std::ios::binary);
    const YAML::Node root =
        loadOneDocument({std::istreambuf_iterator<char>(in), {}}, path, "a scanner file");
    refuseRepeatedKeys(root, path);
    return root;
  } catch (const YAML::Exception& e) {
    throw InputError(path, "not valid YAML: " + std::string(e.what()));
  }
}

// $SCANPLAN_DATA/scanners, where presets may be added; empty when the variable is unset.
std::filesystem::path addedPresets() {
  const char* env = std::getenv("SCANPLAN_DATA");
  return env && *env ? std::filesystem::path(env) / "scanners" : std::filesystem::path();
}

}  // namespace

YAML::Node loadOneDocument(const std::string& text, const std::string& source,
                           const std::string& what) {
  // YAML is text: control characters other than tab and line ends are not allowed in it.
  for (std::size_t k = 0; k < text.size(); ++k)
    if (static_cast<unsigned char>(text[k]) < 0x20 && text[k] != '\t' && text[k] != '\n' &&
        text[k] != '\r')
      throw InputError(source, fmt::format("byte {} is a control character (0x{:02x}): {} is "
                                           "YAML, which is text",
                                           k + 1, static_cast<unsigned char>(text[k]), what));
  // Two documents at most are looked at: yaml-cpp's LoadAll loops without end on some
  // bytes that are no YAML (a NUL, a comma and a stray byte).
  std::istringstream in(text);
  YAML::Parser parser(in);
  IgnoredEvents ignored;
  if (parser.HandleNextDocument(ignored) && parser.HandleNextDocument(ignored))
    throw InputError(source,
                     "holds more than one YAML document (split by ---): " + what + " is one");
  return YAML::Load(text);
}

std::vector<std::string> scannerPresetNames() {
  std::set<std::string> names;
  for (const assets::File& preset : assets::scanner_presets) names.emplace(preset.name);
  std::error_code ec;
  if (const std::filesystem::path folder = addedPresets(); !folder.empty())
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec))
      if (entry.path().extension() == ".yaml") names.insert(entry.path().stem().string());
  return {names.begin(), names.end()};
}

Scanner scannerPreset(const std::string& name) {
  std::vector<std::string> chain;
  return presetIn(name, chain);
}

namespace {

// The preset `name`, read while the presets of `chain` are (one names the next): a preset
// naming one of them, itself included, is an error.
Scanner presetIn(const std::string& name, std::vector<std::string>& chain) {
  namespace fs = std::filesystem;
  // A preset is named by letters, digits, '.', '_' and '-' (no path, no file name too long).
  const bool plain =
      !name.empty() && name.size() <= 100 && std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
      });
  Scanner scanner;
  scanner.name = name;
  std::error_code missing;
  if (const fs::path folder = addedPresets(); plain && !folder.empty()) {
    const fs::path file = folder / (name + ".yaml");
    if (fs::exists(file, missing)) {
      try {
        if (std::find(chain.begin(), chain.end(), name) != chain.end())
          throw InputError(file.string(), fmt::format("the scanner presets {} -> {} name one "
                                                      "another in a loop",
                                                      fmt::join(chain, " -> "), name));
        chain.push_back(name);
        Scanner read = fromMapping(loadYaml(file.string()), scanner, file.string(), chain);
        chain.pop_back();
        return read;
      } catch (const YAML::Exception& e) {
        throw InputError(file.string(), e.what());
      }
    }
  }
  const auto& presets = assets::scanner_presets;
  const auto own = std::find_if(presets.begin(), presets.end(),
                                [&](const assets::File& preset) { return preset.name == name; });
  if (!plain || own == presets.end())
    throw InputError(name, fmt::format("unknown scanner preset (known: {})",
                                       fmt::join(scannerPresetNames(), ", ")));
  // A built-in preset names no other, so no loop goes through one.
  return fromMapping(YAML::Load(std::string(own->text)), scanner, name + " (built in)", chain);
}

}  // namespace

Scanner scannerFromYaml(const YAML::Node& root, const std::string& source) {
  try {
    if (root.IsMap() && root["scanner"]) {
      const YAML::Node& node = root["scanner"];
      if (node.IsScalar()) {
        try {
          return scannerPreset(node.as<std::string>());
        } catch (const InputError& e) {  // named by the preset: name the spec too
          throw InputError(source, "scanner '" + e.file() + "': " + e.reason());
        }
      }
      std::vector<std::string> chain;
      return fromMapping(node, Scanner{}, source, chain);
    }
    std::vector<std::string> chain;
    return fromMapping(root, Scanner{}, source, chain);
  } catch (const YAML::Exception& e) {
    throw InputError(source, e.what());
  }
}

Scanner loadScanner(const std::string& path) { return scannerFromYaml(loadYaml(path), path); }

Scanner scannerNamed(const std::string& name) {
  const std::string extension = std::filesystem::path(name).extension().string();
  std::error_code ec;
  if (extension == ".yaml" || extension == ".yml" || std::filesystem::is_regular_file(name, ec))
    return loadScanner(name);
  return scannerPreset(name);
}

}  // namespace scanplan
