#pragma once
// Files compiled into the library (cmake/Embed.cmake), so that nothing is read from the
// source tree: the report's and the spec editor's pages with their bundled scripts, and the
// scanner presets.

#include <span>
#include <string_view>

namespace scanplan::assets {

extern const std::string_view viewer_js;
extern const std::string_view report_html;
extern const std::string_view editor_js;
extern const std::string_view editor_html;

struct File {
  std::string_view name, text;
};
extern const std::span<const File> scanner_presets;  // data/scanners/<name>.yaml, by name

}  // namespace scanplan::assets
