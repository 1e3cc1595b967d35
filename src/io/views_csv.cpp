#include <scanplan/errors.h>
#include <scanplan/io/atomic_file.h>
#include <scanplan/io/input_file.h>
#include <scanplan/io/views_csv.h>

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace scanplan {

void writeViewsCsv(const std::vector<View>& views, const std::string& path) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "id";
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) out << ",m" << r << c;
    out << ",target_x,target_y,target_z,task\n";
    for (const View& view : views) {
      out << view.id;
      const Eigen::Matrix4d& m = view.camera_to_world.matrix();
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) out << fmt::format(",{:.17g}", m(r, c));
      for (int k = 0; k < 3; ++k) out << fmt::format(",{:.17g}", view.target[k]);
      out << ',' << view.task << '\n';
    }
  });
}

std::vector<View> readViewsCsv(const std::string& path) {
  requireInputFile(path);
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line) || line.rfind("id,m00", 0) != 0)
    throw InputError(path, "not a views CSV: the first line is not the header 'id,m00,...'");
  std::vector<View> views;
  for (int number = 2; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    auto fail = [&](const std::string& why) {
      throw InputError(path, fmt::format("line {}: {}", number, why));
    };
    std::vector<std::string> fields;
    std::istringstream row(line);
    for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
    if (line.back() == ',') fields.emplace_back();
    if (fields.size() != 21) fail(fmt::format("{} fields, expected 21", fields.size()));
    auto number_at = [&](std::size_t i) {
      try {
        std::size_t used = 0;
        const double v = std::stod(fields[i], &used);
        if (used != fields[i].size()) throw std::invalid_argument(fields[i]);
        return v;
      } catch (const std::exception&) {
        throw InputError(path, fmt::format("line {}: field {} ('{}') is not a number", number,
                                           i + 1, fields[i]));
      }
    };
    View view;
    view.id = static_cast<int>(number_at(0));
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = number_at(1 + static_cast<std::size_t>(4 * r + c));
    if (!isRigid(m)) fail("the matrix is not a rigid transform");
    view.camera_to_world.matrix() = m;
    for (int k = 0; k < 3; ++k) view.target[k] = number_at(17 + static_cast<std::size_t>(k));
    view.task = fields[20];
    views.push_back(view);
  }
  return views;
}

}  // namespace scanplan
