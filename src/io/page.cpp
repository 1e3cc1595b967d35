#include "io/page.h"

#include <scanplan/core/atomic_file.h>
#include <scanplan/core/version.h>

#include <cstdint>
#include <ctime>
#include <filesystem>
#include <stdexcept>

namespace scanplan::detail {

std::string base64(const void* data, std::size_t size) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const unsigned v =
        bytes[i] << 16 | (i + 1 < size ? bytes[i + 1] << 8 : 0) | (i + 2 < size ? bytes[i + 2] : 0);
    out += kDigits[v >> 18 & 63];
    out += kDigits[v >> 12 & 63];
    out += i + 1 < size ? kDigits[v >> 6 & 63] : '=';
    out += i + 2 < size ? kDigits[v & 63] : '=';
  }
  return out;
}

std::vector<float> floats(const std::vector<Vec3>& points) {
  std::vector<float> values;
  values.reserve(points.size() * 3);
  for (const Vec3& p : points)
    for (int k = 0; k < 3; ++k) values.push_back(static_cast<float>(p[k]));
  return values;
}

nlohmann::json meshJson(const TriangleMesh& mesh) {
  std::vector<std::uint32_t> indices;
  for (const Vec3i& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) indices.push_back(static_cast<std::uint32_t>(t[k]));
  const std::vector<std::int32_t> faces(mesh.triangle_faces.begin(), mesh.triangle_faces.end());
  return {{"positions", base64(floats(mesh.vertices))},
          {"indices", base64(indices)},
          {"faces", base64(faces)}};
}

nlohmann::json headerJson(const std::string& part_file, const std::string& spec_file) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", &utc);
  std::error_code ec;
  const std::filesystem::path part = std::filesystem::absolute(part_file, ec);
  return {{"part", (ec ? std::filesystem::path(part_file) : part).lexically_normal().string()},
          {"spec", spec_file},
          {"version", version()},
          {"date", date}};
}

namespace {

// "</" inside <script> would end the element; "<\/" reads the same in JSON and JS strings.
std::string escapeScript(std::string text, std::string_view closing) {
  for (std::size_t at = text.find(closing); at != std::string::npos;
       at = text.find(closing, at + 3))
    text.replace(at, 2, "<\\/");
  return text;
}

}  // namespace

void writePage(std::string_view page_template, std::string_view script, const std::string& data,
               const std::string& path) {
  std::string page(page_template);
  auto fill = [&](std::string_view slot, const std::string& content) {
    const std::size_t at = page.find(slot);
    if (at == std::string::npos) throw std::logic_error("page template without a slot");
    page.replace(at, slot.size(), content);
  };
  fill("/*@VIEWER@*/", escapeScript(std::string(script), "</script"));
  // The data is JSON, where '<' stands only inside strings: as \u003c, no text of it can
  // end the element or open a comment ("<!--") that changes how the page parses.
  std::string escaped;
  escaped.reserve(data.size());
  for (const char c : data) {
    if (c == '<')
      escaped += "\\u003c";
    else
      escaped += c;
  }
  fill("/*@DATA@*/", escaped);
  writeFileAtomically(path, [&](std::ostream& out) { out << page; });
}

}  // namespace scanplan::detail
