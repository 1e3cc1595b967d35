#pragma once
// The self-contained HTML pages (the report, the spec editor): a page template from web/src
// with its bundled script and its data inlined, so that the one file opens from disk. Bulk
// arrays travel as base64 of little-endian typed arrays, which the page views as
// Float32Array, Uint8Array, ... without parsing numbers (private to the library).

#include "io/json_values.h"

#include <scanplan/cad/mesh.h>

#include <nlohmann/json.hpp>

#include <bit>
#include <string>
#include <string_view>
#include <vector>

namespace scanplan::detail {

std::string base64(const void* data, std::size_t size);

template <typename T>
std::string base64(const std::vector<T>& values) {
  static_assert(std::endian::native == std::endian::little, "typed arrays are little-endian");
  return base64(values.data(), values.size() * sizeof(T));
}

// x, y, z of each point, as the page's Float32Array takes them.
std::vector<float> floats(const std::vector<Vec3>& points);

// The mesh as the pages draw it: positions, triangle indices and each triangle's face id.
nlohmann::json meshJson(const TriangleMesh& mesh);

// What a page states at its top: the part's file (absolute), the spec's, scanplan's version
// and the date (UTC).
nlohmann::json headerJson(const std::string& part_file, const std::string& spec_file);

// Writes `page_template` with its slots /*@VIEWER@*/ filled by `script` and /*@DATA@*/ by
// `data` (JSON text), both escaped so that nothing in them ends their <script> element.
// \throw OutputError when it cannot be written.
void writePage(std::string_view page_template, std::string_view script, const std::string& data,
               const std::string& path);

// The same with `data` as JSON (nlohmann::json or ordered_json).
template <typename Json>
void writePage(std::string_view page_template, std::string_view script, const Json& data,
               const std::string& path) {
  writePage(page_template, script, data.dump(-1, ' ', false, Json::error_handler_t::replace), path);
}

}  // namespace scanplan::detail
