#pragma once
// Checks on the files a command is given.

#include <scanplan/plan/plan.h>
#include <scanplan/spec/spec.h>

#include <string>
#include <vector>

namespace scanplan::cli {

// The files a command reads: `inputs`, and those `spec` names, itself included
// (specFiles()). Empty names are skipped.
std::vector<std::string> commandInputs(std::vector<std::string> inputs, const Spec& spec);

// The spec of a command reading the plan `plan` (from `plan_file`): the file `given`
// (--spec), else the one the plan was made with, else the default one.
Spec specFor(const std::string& given, const Plan& plan, const std::string& plan_file);

// Where specFor took the spec from, for the command's "spec" line.
std::string specSource(const std::string& given, const Plan& plan);

// The part of a command reading the plan `plan` (from `plan_file`): the file `given`, else
// the one the plan names, else a file of that name beside the plan. \throw InputError
// naming the plan when it names none.
std::string partFileFor(const std::string& given, const Plan& plan, const std::string& plan_file);

// \throw OutputError naming `out` when it is one of `inputs`.
void refuseInputAsOutput(const std::string& out, const std::vector<std::string>& inputs);

}  // namespace scanplan::cli
