// A study file (docs/study.md): its lists, expanded into one row per plan.

#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>
#include <scanplan/io/study_yaml.h>

#include "scanner/sensor_yaml.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

namespace scanplan {
namespace {

class StudyReader {
 public:
  explicit StudyReader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& what) const { throw InputError(path_, what); }

  // The strings of list `key` (a single value is a list of one); `fallback` when absent.
  std::vector<std::string> strings(const YAML::Node& root, const char* key,
                                   std::vector<std::string> fallback) const {
    const YAML::Node node = root[key];
    if (!node) return fallback;
    std::vector<std::string> values;
    for (const YAML::Node& item : node.IsSequence() ? node : listOf(node)) {
      if (!item.IsScalar() || item.Scalar().empty())
        fail(fmt::format("{}: every entry is a non-empty name or path", key));
      values.push_back(item.Scalar());
    }
    if (values.empty()) fail(fmt::format("{}: the list is empty", key));
    return values;
  }

  // A path of the file, relative to its folder, made absolute: the plans may run elsewhere.
  std::string resolve(const std::string& file) const {
    const std::filesystem::path p(file);
    if (p.is_absolute()) return file;
    return std::filesystem::absolute(std::filesystem::path(path_).parent_path() / p)
        .lexically_normal()
        .string();
  }

  const std::string& path() const { return path_; }

 private:
  static YAML::Node listOf(const YAML::Node& node) {
    YAML::Node list(YAML::NodeType::Sequence);
    list.push_back(node);
    return list;
  }
  std::string path_;
};

// A scanner given as a file (a path ending .yaml or .yml) is resolved; a preset name is not.
std::string scannerEntry(const StudyReader& reader, const std::string& scanner) {
  const std::string ext = std::filesystem::path(scanner).extension().string();
  return ext == ".yaml" || ext == ".yml" ? reader.resolve(scanner) : scanner;
}

void checkOrientation(const StudyReader& reader, const std::string& rest) {
  if (rest == "auto" || rest == "all" || rest == "drawn") return;
  const bool digits = !rest.empty() && rest.size() <= 9 && rest[0] != '0' &&
                      std::all_of(rest.begin(), rest.end(), [](char c) {
                        return std::isdigit(static_cast<unsigned char>(c));
                      });
  if (!digits) reader.fail("orientations: '" + rest + "' is not auto, all, drawn or a face id");
}

std::vector<std::optional<double>> coverages(const StudyReader& reader, const YAML::Node& root) {
  std::vector<std::optional<double>> result;
  for (const std::string& text : reader.strings(root, "coverage", {})) {
    double share = 0;
    try {
      std::size_t used = 0;
      share = std::stod(text, &used);
      if (used != text.size()) throw std::invalid_argument(text);
    } catch (const std::exception&) {
      reader.fail("coverage: '" + text + "' is not a number");
    }
    if (!(share > 0 && share <= 1)) reader.fail("coverage: " + text + " is not within (0, 1]");
    result.push_back(share);
  }
  if (result.empty()) result.push_back(std::nullopt);
  return result;
}

// A folder name for a row: its varying settings, each reduced to letters, digits, . _ -,
// never starting with a dot (no "..", no hidden folder) and at most 100 characters.
std::string rowName(const std::vector<std::string>& parts) {
  std::string name;
  for (const std::string& part : parts) {
    if (part.empty()) continue;
    if (!name.empty()) name += "__";
    for (char c : part)
      name += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' ? c : '_';
  }
  if (name.empty()) name = "plan";
  if (name.front() == '.') name.front() = '_';
  return name.substr(0, 100);
}

std::string stem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

}  // namespace

Study loadStudy(const std::string& path) {
  requireInputFile(path);
  std::ifstream in(path);
  const StudyReader reader(path);
  YAML::Node root;
  try {
    root = loadOneDocument({std::istreambuf_iterator<char>(in), {}}, path, "a study");
  } catch (const YAML::Exception& e) {
    reader.fail("not valid YAML: " + std::string(e.what()));
  }
  if (!root.IsMap()) reader.fail("a study is a mapping with at least 'parts'");
  const std::set<std::string> known = {"parts",        "scanners", "specs",
                                       "orientations", "coverage", "registration"};
  for (const auto& entry : root)
    if (!known.count(entry.first.as<std::string>()))
      reader.fail("unknown key '" + entry.first.as<std::string>() + "'");
  if (!root["parts"]) reader.fail("parts: the study names no part");
  Study study;
  study.file = path;
  if (const YAML::Node registration = root["registration"]) {
    if (!registration.IsScalar() ||
        (registration.Scalar() != "true" && registration.Scalar() != "false"))
      reader.fail("registration: expected true or false");
    study.registration = registration.Scalar() == "true";
  }
  const auto parts = reader.strings(root, "parts", {});
  const auto scanners = reader.strings(root, "scanners", {""});
  const auto specs = reader.strings(root, "specs", {""});
  const auto rests = reader.strings(root, "orientations", {""});
  for (const std::string& rest : rests)
    if (!rest.empty()) checkOrientation(reader, rest);
  const auto shares = coverages(reader, root);
  const std::size_t count =
      parts.size() * scanners.size() * specs.size() * rests.size() * shares.size();
  if (count > kMostStudyRows)
    reader.fail(fmt::format("{} plans: a study holds at most {}", count, kMostStudyRows));
  std::set<std::string> names;
  for (const std::string& part : parts)
    for (const std::string& scanner : scanners)
      for (const std::string& spec : specs)
        for (const std::string& rest : rests)
          for (const std::optional<double>& share : shares) {
            StudyRow row{"",
                         reader.resolve(part),
                         scanner.empty() ? "" : scannerEntry(reader, scanner),
                         spec.empty() ? "" : reader.resolve(spec),
                         rest,
                         share};
            const std::string base =
                rowName({stem(part), scanners.size() > 1 ? stem(scanner) : "",
                         specs.size() > 1 ? stem(spec) : "", rests.size() > 1 ? rest : "",
                         shares.size() > 1 && share ? fmt::format("{:g}", *share) : ""});
            row.name = base;
            for (int k = 2; !names.insert(row.name).second; ++k)
              row.name = fmt::format("{}-{}", base, k);
            study.rows.push_back(std::move(row));
          }
  return study;
}

}  // namespace scanplan
