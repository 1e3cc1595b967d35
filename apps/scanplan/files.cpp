#include "files.h"

#include <scanplan/core/errors.h>
#include <scanplan/io/spec_yaml.h>

#include <filesystem>

namespace scanplan::cli {

std::vector<std::string> commandInputs(std::vector<std::string> inputs, const Spec& spec) {
  const std::vector<std::string> named = specFiles(spec);
  inputs.insert(inputs.end(), named.begin(), named.end());
  return inputs;
}

Spec specFor(const std::string& given, const Plan& plan, const std::string& plan_file) {
  return given.empty() ? planSpec(plan, plan_file) : loadSpec(given);
}

std::string specSource(const std::string& given, const Plan& plan) {
  if (!given.empty()) return given;
  if (!plan.spec) return "the default (the plan names none)";
  // The file's name as the plan gives it may hold control bytes.
  std::string source = plan.spec->file.empty() ? "the default" : printable(plan.spec->file);
  if (!plan.spec->rest.empty()) source += ", resting " + printable(plan.spec->rest);
  return source + " (the plan's)";
}

std::string partFileFor(const std::string& given, const Plan& plan, const std::string& plan_file) {
  if (!given.empty()) return given;
  if (plan.part_file.empty())
    throw InputError(plan_file, "names no part file; give the part on the command line");
  const std::filesystem::path beside = std::filesystem::path(plan_file).parent_path() /
                                       std::filesystem::path(plan.part_file).filename();
  std::error_code ec;  // a name the file system refuses is left for importPart to name
  if (!std::filesystem::exists(plan.part_file, ec) && std::filesystem::exists(beside, ec))
    return beside.string();
  return plan.part_file;
}

void refuseInputAsOutput(const std::string& out, const std::vector<std::string>& inputs) {
  std::error_code ec;
  for (const std::string& in : inputs)
    if (!in.empty() && std::filesystem::equivalent(in, out, ec))
      throw OutputError(out, "is an input of this command (" + in + "): choose another output");
}

}  // namespace scanplan::cli
