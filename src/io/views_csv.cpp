#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>
#include <scanplan/io/views_csv.h>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace scanplan {

void writeViewsCsv(const std::vector<View>& views, const std::string& path,
                   const std::vector<std::size_t>& setups) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "sequence,id";
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) out << ",m" << r << c;
    out << ",target_x,target_y,target_z,task,setup\n";
    for (std::size_t v = 0; v < views.size(); ++v) {
      const View& view = views[v];
      out << v + 1 << ',' << view.id;
      const Eigen::Matrix4d& m = view.camera_to_world.matrix();
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) out << fmt::format(",{:.17g}", m(r, c));
      for (int k = 0; k < 3; ++k) out << fmt::format(",{:.17g}", view.target[k]);
      out << ',' << view.task << ',' << (v < setups.size() ? setups[v] : 1) << '\n';
    }
  });
}

std::vector<View> readViewsCsv(const std::string& path) {
  requireInputFile(path);
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line) ||
      (line.rfind("sequence,id,m00", 0) != 0 && line.rfind("id,m00", 0) != 0))
    throw InputError(path,
                     "not a views CSV: the first line is not the header 'sequence,id,m00,...'");
  const std::size_t first = line.rfind("sequence", 0) == 0 ? 1 : 0;  // the id's field
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
    if (fields.size() != 21 + first && fields.size() != 22 + first)
      fail(fmt::format("{} fields, expected {} or {} (with the setup)", fields.size(), 21 + first,
                       22 + first));
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
    if (first == 1) number_at(0);  // the sequence
    View view;
    view.id = static_cast<int>(number_at(first));
    Eigen::Matrix4d m;
    for (std::size_t r = 0; r < 4; ++r)
      for (std::size_t c = 0; c < 4; ++c) m(r, c) = number_at(first + 1 + 4 * r + c);
    if (!isRigid(m)) fail("the matrix is not a rigid transform");
    view.camera_to_world.matrix() = m;
    for (std::size_t k = 0; k < 3; ++k) view.target[k] = number_at(first + 17 + k);
    view.task = fields[first + 20];
    if (fields.size() == 22 + first) {
      const std::string& setup = fields[first + 21];
      if (setup.empty() || setup.size() > 9 || setup[0] == '0' ||
          !std::all_of(setup.begin(), setup.end(), [](char c) { return c >= '0' && c <= '9'; }))
        fail(fmt::format("the setup '{}' is not a whole number from 1", setup));
    }
    views.push_back(view);
  }
  return views;
}

}  // namespace scanplan
