#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>
#include <scanplan/io/views_csv.h>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace scanplan {

namespace {

std::string matrixName(int r, int c) { return fmt::format("m{}{}", r, c); }

const char* const kTarget[3] = {"target_x", "target_y", "target_z"};

std::vector<std::string> fieldsOf(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream row(line);
  for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

// The TCP of a view: the centre of its measuring volume, turned as the camera.
std::string tcpFields(const View& view, double standoff) {
  const Pose& pose = view.camera_to_world;
  const Vec3 tcp = pose * Vec3(0, 0, standoff), abc = zyxAngles(pose.linear());
  Eigen::Quaterniond q(pose.linear());
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return fmt::format(
      ",{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}", tcp.x(),
      tcp.y(), tcp.z(), abc.x(), abc.y(), abc.z(), q.w(), q.x(), q.y(), q.z());
}

}  // namespace

void writeViewsCsv(const ViewsCsv& csv, const std::string& path) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "sequence,id";
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) out << ',' << matrixName(r, c);
    out << ",target_x,target_y,target_z,task,setup,frame,"
           "tcp_x,tcp_y,tcp_z,tcp_a,tcp_b,tcp_c,tcp_qw,tcp_qx,tcp_qy,tcp_qz\n";
    for (std::size_t v = 0; v < csv.views.size(); ++v) {
      const View& view = csv.views[v];
      out << v + 1 << ',' << view.id;
      const Eigen::Matrix4d& m = view.camera_to_world.matrix();
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) out << fmt::format(",{:.17g}", m(r, c));
      for (int k = 0; k < 3; ++k) out << fmt::format(",{:.17g}", view.target[k]);
      out << ',' << view.task << ',' << (v < csv.setups.size() ? csv.setups[v] : 1) << ','
          << csv.frame << tcpFields(view, csv.standoff) << '\n';
    }
  });
}

std::vector<View> readViewsCsv(const std::string& path) {
  requireInputFile(path);
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) throw InputError(path, "not a views CSV: the file is empty");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const std::vector<std::string> header = fieldsOf(line);
  std::map<std::string, std::size_t> column;
  for (std::size_t i = 0; i < header.size(); ++i) column.emplace(header[i], i);
  std::vector<std::string> needed = {"id", "task", kTarget[0], kTarget[1], kTarget[2]};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) needed.push_back(matrixName(r, c));
  for (const std::string& name : needed)
    if (!column.count(name))
      throw InputError(path, "not a views CSV: the header line has no column '" + name + "'");
  std::vector<View> views;
  for (int number = 2; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> fields = fieldsOf(line);
    auto fail = [&](const std::string& why) {
      throw InputError(path, fmt::format("line {}: {}", number, why));
    };
    if (fields.size() != header.size())
      fail(fmt::format("{} fields, the header has {}", fields.size(), header.size()));
    auto number_of = [&](const std::string& name) {
      const std::size_t i = column.at(name);
      try {
        std::size_t used = 0;
        const double v = std::stod(fields[i], &used);
        if (used != fields[i].size()) throw std::invalid_argument(fields[i]);
        return v;
      } catch (const std::exception&) {
        fail(fmt::format("{} ('{}') is not a number", name, fields[i]));
      }
      return 0.0;
    };
    if (column.count("sequence")) number_of("sequence");
    View view;
    view.id = static_cast<int>(number_of("id"));
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = number_of(matrixName(r, c));
    if (!isRigid(m)) fail("the matrix is not a rigid transform");
    view.camera_to_world.matrix() = m;
    for (int k = 0; k < 3; ++k) view.target[k] = number_of(kTarget[k]);
    view.task = fields[column.at("task")];
    if (auto it = column.find("setup"); it != column.end()) {
      const std::string& setup = fields[it->second];
      if (setup.empty() || setup.size() > 9 || setup[0] == '0' ||
          !std::all_of(setup.begin(), setup.end(), [](char c) { return c >= '0' && c <= '9'; }))
        fail(fmt::format("the setup '{}' is not a whole number from 1", setup));
    }
    views.push_back(view);
  }
  return views;
}

}  // namespace scanplan
