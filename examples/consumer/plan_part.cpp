// Plans a part with its default spec and writes plan.json: plan_part PART OUT.json
#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/planning.h>
#include <scanplan/spec/spec.h>

#include <iostream>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: plan_part PART OUT.json\n";
    return 1;
  }
  try {
    const scanplan::Part part = scanplan::importPart(argv[1]);
    scanplan::Plan plan = scanplan::planViews(part, scanplan::defaultSpec());
    scanplan::writePlanFiles(plan, argv[2]);
    std::cout << plan.views.size() << " views, " << plan.measuredCount() << " of "
              << plan.samples.size() << " samples measured\n";
  } catch (const scanplan::Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return e.exitCode();
  }
}
