#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>
#include <scanplan/io/points_csv.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <sstream>

namespace scanplan {

std::vector<ControlPoint> readPointsCsv(const std::string& path) {
  requireInputFile(path);
  // Lines may end in LF, CRLF or CR alone (spreadsheets on old Macs write those).
  std::ifstream file(path, std::ios::binary);
  std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  for (std::size_t k = 0; k < text.size(); ++k)
    if (text[k] == '\r') text[k] = k + 1 < text.size() && text[k + 1] == '\n' ? ' ' : '\n';
  std::istringstream in(text);
  std::vector<ControlPoint> points;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos ||
        line[line.find_first_not_of(" \t")] == '#')
      continue;
    std::vector<double> values;
    std::stringstream fields(line);
    std::string field;
    bool numeric = true;
    while (std::getline(fields, field, ',')) {
      try {
        std::size_t used = 0;
        values.push_back(std::stod(field, &used));
        if (field.find_first_not_of(" \t", used) != std::string::npos) numeric = false;
      } catch (const std::exception&) {
        numeric = false;
      }
    }
    const std::string where = "line " + std::to_string(number);
    if (!numeric) {
      // A header names its columns; a first line without a letter is data mistyped.
      const bool named =
          std::any_of(line.begin(), line.end(), [](unsigned char c) { return std::isalpha(c); });
      if (points.empty() && number == 1 && named) continue;
      throw InputError(path, where + ": not a number in '" + line + "'");
    }
    if (values.size() != 3 && values.size() != 6)
      throw InputError(path, where + ": expected x,y,z or x,y,z,nx,ny,nz, got " +
                                 std::to_string(values.size()) + " values");
    ControlPoint point;
    point.line = number;
    point.position = Vec3(values[0], values[1], values[2]);
    if (values.size() == 6) {
      Vec3 n(values[3], values[4], values[5]);
      if (!(n.norm() > 1e-12)) throw InputError(path, where + ": the normal is zero");
      point.normal = n.normalized();
    }
    if (!point.position.allFinite()) throw InputError(path, where + ": not a finite point");
    points.push_back(point);
  }
  if (points.empty()) throw InputError(path, "no points");
  return points;
}

std::vector<Marker> readMarkers(const std::string& path) {
  std::vector<Marker> markers;
  for (const ControlPoint& point : readPointsCsv(path))
    markers.push_back({point.position, point.normal.value_or(Vec3::UnitZ())});
  return markers;
}

void writeMarkers(const std::vector<Marker>& markers, const std::string& path) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "x,y,z,nx,ny,nz\n";
    out.precision(10);
    for (const Marker& m : markers)
      out << m.position.x() << ',' << m.position.y() << ',' << m.position.z() << ',' << m.normal.x()
          << ',' << m.normal.y() << ',' << m.normal.z() << '\n';
  });
}

}  // namespace scanplan
