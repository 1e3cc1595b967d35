#include "io/json_values.h"
#include "scanner/sensor_yaml.h"

#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>
#include <scanplan/io/inspection_files.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

namespace scanplan {
namespace {

double number(const YAML::Node& node, const std::string& path, const std::string& where) {
  double value = 0;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(path, where + " must be a number");
  }
  if (!std::isfinite(value) || std::abs(value) > 100)
    throw InputError(path, where + " must be a number of mm within [-100, 100]");
  return value;
}

Deviation deviationOf(const YAML::Node& entry, const std::string& path, const std::string& where) {
  if (!entry.IsMap()) throw InputError(path, where + " is not a map");
  Deviation d;
  const YAML::Node faces = entry["faces"];
  if (!faces || !faces.IsSequence() || faces.size() == 0)
    throw InputError(path, where + ": faces must be a list of face ids");
  for (const YAML::Node& f : faces) {
    int id = 0;
    try {
      id = f.as<int>();
    } catch (const YAML::Exception&) {
      throw InputError(path, where + ": face ids are whole numbers 1, 2, ...");
    }
    if (id < 1) throw InputError(path, where + ": face ids are whole numbers 1, 2, ...");
    d.faces.push_back(id);
  }
  int kinds = 0;
  for (const auto& item : entry) {
    const std::string key = item.first.as<std::string>();
    if (key == "faces") continue;
    ++kinds;
    if (key == "offset" || key == "bow" || key == "diameter") {
      d.kind = key == "offset" ? Deviation::Kind::Offset
               : key == "bow"  ? Deviation::Kind::Bow
                               : Deviation::Kind::Diameter;
      d.amount = number(item.second, path, where + ": " + key);
    } else if (key == "move") {
      if (!item.second.IsSequence() || item.second.size() != 3)
        throw InputError(path, where + ": move must be [x, y, z] in mm");
      d.kind = Deviation::Kind::Move;
      for (int a = 0; a < 3; ++a) d.move[a] = number(item.second[a], path, where + ": move");
    } else {
      throw InputError(
          path, where + ": unknown key '" + key + "' (offset, bow, move or diameter, with faces)");
    }
  }
  if (kinds != 1)
    throw InputError(path, where + ": give exactly one of offset, bow, move or diameter");
  return d;
}

std::string_view kindName(Deviation::Kind kind) {
  switch (kind) {
    case Deviation::Kind::Offset: return "offset";
    case Deviation::Kind::Bow: return "bow";
    case Deviation::Kind::Move: return "move";
    case Deviation::Kind::Diameter: return "diameter";
  }
  return "?";
}

// The number `key` of `object`. \throw InputError naming `where`.
double numberAt(const nlohmann::json& object, const char* key, const std::string& path,
                const std::string& where) {
  if (!object.contains(key) || !object[key].is_number())
    throw InputError(path, where + ": '" + key + "' is not a number");
  return object[key].get<double>();
}

InspectedCharacteristic inspectedFrom(const nlohmann::json& entry, const Plan& plan,
                                      const std::string& path, const std::string& where) {
  if (!entry.is_object() || !entry.contains("id") || !entry["id"].is_number_integer() ||
      !entry.contains("evaluated") || !entry["evaluated"].is_boolean())
    throw InputError(path, where + ": needs an integer 'id' and a true or false 'evaluated'");
  InspectedCharacteristic k;
  k.characteristic = entry["id"].get<int>();
  if (std::none_of(plan.characteristics.begin(), plan.characteristics.end(),
                   [&](const Characteristic& c) { return c.id == k.characteristic; }))
    throw InputError(
        path, where + ": the plan has no characteristic " + std::to_string(k.characteristic));
  k.evaluated = entry["evaluated"].get<bool>();
  if (!k.evaluated) {
    if (entry.contains("not_evaluated") && entry["not_evaluated"].is_string())
      k.not_evaluated = entry["not_evaluated"].get<std::string>();
    return k;
  }
  k.true_value = numberAt(entry, "true_value", path, where);
  k.mean = numberAt(entry, "mean", path, where);
  k.bias = numberAt(entry, "bias", path, where);
  k.uncertainty = numberAt(entry, "uncertainty", path, where);
  k.ratio = numberAt(entry, "ratio", path, where);
  // Written since the inspection states its precision.
  if (entry.contains("precision")) k.precision = numberAt(entry, "precision", path, where);
  if (entry.contains("error_95")) k.error_95 = numberAt(entry, "error_95", path, where);
  k.points = numberAt(entry, "points", path, where);
  const std::string verdict = entry.value("verdict", std::string());
  bool known = false;
  for (Verdict v :
       {Verdict::Capable, Verdict::Marginal, Verdict::NotCapable, Verdict::Untoleranced})
    if (toString(v) == verdict) k.verdict = v, known = true;
  if (!known) throw InputError(path, where + ": unknown verdict '" + verdict + "'");
  const nlohmann::json& values = entry.value("values", nlohmann::json());
  if (!values.is_array()) throw InputError(path, where + ": 'values' is not a list");
  for (const nlohmann::json& v : values) {
    if (!v.is_number()) throw InputError(path, where + ": a value is not a number");
    k.values.push_back(v.get<double>());
  }
  return k;
}

}  // namespace

Inspection readInspection(const std::string& path, const Plan& plan) {
  requireInputFile(path);
  std::ifstream in(path, std::ios::binary);
  const nlohmann::json root = detail::parseJson(in, path);
  if (!root.is_object() || !root.contains("runs") || !root["runs"].is_number_integer() ||
      !root.contains("characteristics") || !root["characteristics"].is_array())
    throw InputError(path, "not an inspection: needs 'runs' and a 'characteristics' list");
  Inspection inspection;
  inspection.runs = root["runs"].get<int>();
  if (inspection.runs < 2) throw InputError(path, "'runs' must be at least 2");
  inspection.spacing = numberAt(root, "spacing", path, "the inspection");
  if (root.contains("precision_asked"))
    inspection.precision_asked = numberAt(root, "precision_asked", path, "the inspection");
  if (root.contains("imprecise")) {
    const nlohmann::json& ids = root["imprecise"];
    if (!ids.is_array() ||
        !std::all_of(ids.begin(), ids.end(), [](const auto& id) { return id.is_number_integer(); }))
      throw InputError(path, "the inspection: 'imprecise' is not a list of characteristic ids");
    inspection.imprecise = ids.get<std::vector<int>>();
  }
  if (root.contains("views_left_out") && root["views_left_out"].is_number_unsigned())
    inspection.views_left_out = root["views_left_out"].get<std::size_t>();
  for (auto [key, count] : {std::pair{"icp_registered", &inspection.icp_registered},
                            {"icp_restarted", &inspection.icp_restarted},
                            {"icp_failed", &inspection.icp_failed}})
    if (root.contains(key) && root[key].is_number_unsigned()) *count = root[key].get<std::size_t>();
  const nlohmann::json& list = root["characteristics"];
  for (std::size_t k = 0; k < list.size(); ++k)
    inspection.characteristics.push_back(
        inspectedFrom(list[k], plan, path, "characteristic " + std::to_string(k + 1)));
  return inspection;
}

std::vector<Deviation> deviationsFromText(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = loadOneDocument(text, source, "a deviations file");
  } catch (const YAML::Exception& e) {
    throw InputError(source, "not valid YAML: " + std::string(e.what()));
  }
  const YAML::Node list = root.IsMap() ? root["deviations"] : YAML::Node();
  if (!list || !list.IsSequence())
    throw InputError(source, "no 'deviations:' list of {faces, offset | bow | move | diameter}");
  std::vector<Deviation> result;
  for (std::size_t k = 0; k < list.size(); ++k)
    result.push_back(deviationOf(list[k], source, "deviation " + std::to_string(k + 1)));
  return result;
}

std::vector<Deviation> loadDeviations(const std::string& path) {
  requireInputFile(path);
  std::ifstream in(path, std::ios::binary);
  return deviationsFromText({std::istreambuf_iterator<char>(in), {}}, path);
}

nlohmann::json inspectionJson(const Inspection& inspection, const Plan& plan) {
  using nlohmann::json;
  json deviations = json::array();
  for (const Deviation& d : inspection.deviations) {
    json entry = {{"faces", d.faces}, {"kind", kindName(d.kind)}};
    if (d.kind == Deviation::Kind::Move)
      entry["move"] = {d.move.x(), d.move.y(), d.move.z()};
    else
      entry["amount"] = d.amount;
    deviations.push_back(entry);
  }
  json list = json::array();
  for (const InspectedCharacteristic& k : inspection.characteristics) {
    json entry = {{"id", k.characteristic}, {"evaluated", k.evaluated}};
    for (const Characteristic& c : plan.characteristics)
      if (c.id == k.characteristic) {
        entry["kind"] = c.kind;
        entry["limits"] = {c.lower, c.upper};
        entry["datums"] = c.datums;
      }
    if (!k.evaluated) {
      entry["not_evaluated"] = k.not_evaluated;
    } else {
      entry.update({{"true_value", k.true_value},
                    {"mean", k.mean},
                    {"bias", k.bias},
                    {"uncertainty", k.uncertainty},
                    {"ratio", k.ratio},
                    {"precision", k.precision},
                    {"error_95", k.error_95},
                    {"verdict", toString(k.verdict)},
                    {"points", k.points},
                    {"values", k.values}});
    }
    list.push_back(entry);
  }
  return {{"runs", inspection.runs},
          {"precision_asked", inspection.precision_asked},
          {"imprecise", inspection.imprecise},
          {"spacing", inspection.spacing},
          {"views_left_out", inspection.views_left_out},
          {"icp_registered", inspection.icp_registered},
          {"icp_restarted", inspection.icp_restarted},
          {"icp_failed", inspection.icp_failed},
          {"deviations", deviations},
          {"characteristics", list}};
}

void writeInspection(const Inspection& inspection, const Plan& plan, const std::string& path) {
  const nlohmann::json root = inspectionJson(inspection, plan);
  writeFileAtomically(path, [&](std::ostream& out) { out << root.dump(1) << '\n'; });
}

}  // namespace scanplan
