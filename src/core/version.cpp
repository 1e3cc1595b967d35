#include <scanplan/core/version.h>

namespace scanplan {

std::string_view version() { return SCANPLAN_VERSION; }

}  // namespace scanplan
