#include "cad/step_pmi_units.h"

#include <cctype>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <unordered_map>

namespace scanplan::detail {
namespace {

// Entity records of the DATA section: id → text after '=' (quotes respected).
std::unordered_map<long, std::string> readRecords(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  std::unordered_map<long, std::string> records;
  std::string record;
  bool quoted = false;
  for (char c : text) {
    if (c == '\'') quoted = !quoted;  // '' inside a string toggles twice
    if (c == '\n' || c == '\r') continue;
    if (c == ';' && !quoted) {
      std::size_t start = record.find_first_not_of(' ');
      std::size_t eq = record.find('=');
      if (start != std::string::npos && record[start] == '#' && eq != std::string::npos) {
        try {
          records[std::stol(record.substr(start + 1, eq - start - 1))] = record.substr(eq + 1);
        } catch (const std::exception&) {
        }
      }
      record.clear();
      continue;
    }
    record += c;
  }
  return records;
}

class UnitResolver {
 public:
  explicit UnitResolver(const std::unordered_map<long, std::string>& records) : records_(records) {}

  // Millimetres per unit of length unit entity `id`; 0 when unknown.
  double millimetres(long id, int depth = 0) const {
    auto it = records_.find(id);
    if (it == records_.end() || depth > 8) return 0;
    const std::string& r = it->second;
    static const std::regex si(R"(SI_UNIT\(\s*(\.[A-Z]+\.|\$)\s*,\s*\.METRE\.\s*\))");
    static const std::regex conversion(R"(CONVERSION_BASED_UNIT\(\s*'[^']*'\s*,\s*#(\d+)\s*\))");
    std::smatch m;
    if (std::regex_search(r, m, si)) {
      const std::string prefix = m[1];
      if (prefix == "$") return 1000;
      if (prefix == ".MILLI.") return 1;
      if (prefix == ".CENTI.") return 10;
      if (prefix == ".DECI.") return 100;
      if (prefix == ".MICRO.") return 1e-3;
      if (prefix == ".KILO.") return 1e6;
      return 0;
    }
    if (std::regex_search(r, m, conversion)) {
      auto [value, unit] = measure(std::stol(m[1]));
      return value * millimetres(unit, depth + 1);
    }
    return 0;
  }

  // The value and unit id of measure entity `id` (MEASURE_WITH_UNIT and its subtypes).
  std::pair<double, long> measure(long id) const {
    auto it = records_.find(id);
    if (it == records_.end()) return {0, 0};
    return measureIn(it->second);
  }

  static std::pair<double, long> measureIn(const std::string& record) {
    static const std::regex with_unit(
        R"(MEASURE_WITH_UNIT\(\s*[A-Z_]+\(\s*([-+0-9.Ee]+)\s*\)\s*,\s*#(\d+)\s*\))");
    std::smatch m;
    if (!std::regex_search(record, m, with_unit)) return {0, 0};
    return {std::stod(m[1]), std::stol(m[2])};
  }

 private:
  const std::unordered_map<long, std::string>& records_;
};

}  // namespace

StepPmiMeasures scanStepPmiMeasures(const std::string& path) {
  StepPmiMeasures result;
  const auto records = readRecords(path);
  const UnitResolver units(records);
  static const std::regex tolerance(
      R"(([A-Z_]*TOLERANCE)\(\s*'((?:[^']|'')*)'\s*,\s*'(?:[^']|'')*'\s*,\s*#(\d+))");
  std::map<std::string, int> name_uses;
  std::set<double> nominal_scales;
  for (const auto& [id, record] : records) {
    std::smatch m;
    if (record.find("TOLERANCE(") != std::string::npos && std::regex_search(record, m, tolerance)) {
      const std::string name = m[2];
      auto [value, unit] = units.measure(std::stol(m[3]));
      double scale = units.millimetres(unit);
      if (++name_uses[name] == 1 && scale > 0) result.tolerance_magnitudes[name] = value * scale;
    }
    // Only the items that are also qualified (QUALIFIED_REPRESENTATION_ITEM, as NIST FTC 06
    // and 07 write them) keep their unit through OCCT's reader; it converts the others by
    // their own unit (FTC 08's inches).
    if (record.find("REPRESENTATION_ITEM('nominal value')") != std::string::npos &&
        record.find("QUALIFIED_REPRESENTATION_ITEM(") != std::string::npos) {
      auto [value, unit] = UnitResolver::measureIn(record);
      double scale = units.millimetres(unit);
      if (scale > 0) nominal_scales.insert(scale);
    }
  }
  // Names used by several tolerances cannot be told apart.
  for (const auto& [name, uses] : name_uses)
    if (uses > 1) result.tolerance_magnitudes.erase(name);
  if (nominal_scales.size() == 1) result.nominal_value_scale = *nominal_scales.begin();
  return result;
}

std::map<long, std::vector<long>> scanSetItemUsages(const std::string& path) {
  static const std::regex head(
      R"(^\s*ITEM_IDENTIFIED_REPRESENTATION_USAGE\(\s*'(?:[^']|'')*'\s*,\s*(?:\$|'(?:[^']|'')*')\s*,)"
      R"(\s*#(\d+)\s*,\s*#\d+\s*,\s*$)");
  const std::string set = "SET_REPRESENTATION_ITEM((";
  std::map<long, std::vector<long>> usages;
  // The usage's head is its name, description and two references: a longer one is not one
  // (and would take std::regex deep into its recursion).
  constexpr std::size_t kLongestHead = 4096;
  for (const auto& [id, record] : readRecords(path)) {
    const std::size_t at = record.find(set);
    std::smatch m;
    const std::string before = at == std::string::npos ? std::string() : record.substr(0, at);
    if (at == std::string::npos || before.size() > kLongestHead ||
        !std::regex_search(before, m, head))
      continue;
    std::vector<long> items;
    std::size_t i = at + set.size();
    for (;;) {  // "#854, #853)": the item ids up to the list's closing parenthesis
      i = record.find_first_not_of(" ,", i);
      if (i == std::string::npos || record[i] != '#') break;
      std::size_t end = i + 1;
      while (end < record.size() && std::isdigit(static_cast<unsigned char>(record[end]))) ++end;
      if (end == i + 1 || end - i > 12) break;
      items.push_back(std::stol(record.substr(i + 1, end - i - 1)));
      i = end;
    }
    if (i != std::string::npos && record[i] == ')') {
      std::vector<long>& all = usages[std::stol(m[1])];
      all.insert(all.end(), items.begin(), items.end());
    }
  }
  return usages;
}

}  // namespace scanplan::detail
