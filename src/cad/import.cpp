#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>

#include "cad/brep_import.h"

#include <fmt/format.h>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Standard_Failure.hxx>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <sstream>
#include <string_view>
#include <unordered_set>
#include <vector>

namespace scanplan {

std::string_view toString(SurfaceType type) {
  switch (type) {
    case SurfaceType::Plane: return "Plane";
    case SurfaceType::Cylinder: return "Cylinder";
    case SurfaceType::Cone: return "Cone";
    case SurfaceType::Sphere: return "Sphere";
    case SurfaceType::Torus: return "Torus";
    case SurfaceType::BSpline: return "BSpline";
    case SurfaceType::Bezier: return "Bezier";
    case SurfaceType::Revolution: return "Revolution";
    case SurfaceType::Extrusion: return "Extrusion";
    case SurfaceType::Offset: return "Offset";
    case SurfaceType::Mesh: return "Mesh";
    case SurfaceType::Other: break;
  }
  return "Other";
}

Box Part::bounds() const {
  Box box;
  for (const Face& face : faces) box.add(face.bounds);
  return box;
}

double Part::area() const {
  double total = 0;
  for (const Face& face : faces) total += face.area;
  return total;
}

double Part::volume() const {
  double total = 0;
  for (const Solid& solid : solids) total += solid.volume;
  return total;
}

const Face& Part::face(int id) const {
  if (id < 1 || id > static_cast<int>(faces.size()))
    throw InputError(file, "unknown face id " + std::to_string(id) + " (the part has " +
                               std::to_string(faces.size()) + " faces)");
  return faces[id - 1];
}

TriangleMesh Part::meshOf(const std::vector<int>& face_ids) const {
  TriangleMesh result;
  result.vertices = mesh.vertices;
  for (int id : face_ids) {
    const Face& f = face(id);
    for (int t = f.first_triangle; t < f.first_triangle + f.triangle_count; ++t) {
      result.triangles.push_back(mesh.triangles[t]);
      result.triangle_faces.push_back(id);
    }
  }
  return result;
}

namespace {

std::string formatOf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".step" || ext == ".stp" || ext == ".p21") return "STEP";
  if (ext == ".iges" || ext == ".igs") return "IGES";
  if (ext == ".brep" || ext == ".brp") return "BREP";
  if (ext == ".stl") return "STL";
  if (ext == ".obj") return "OBJ";
  if (ext == ".ply") return "PLY";
  if (ext == ".off") return "OFF";
  throw InputError(path,
                   "unsupported file type '" + ext +
                       "' (expected .step/.stp, .iges/.igs, .brep, .stl, .obj, .ply or .off)");
}

// The first and last `n` bytes of a file, to check its framing cheaply.
std::pair<std::string, std::string> headAndTail(const std::string& path, std::size_t n) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(0, std::ios::end);
  auto size = static_cast<std::size_t>(in.tellg());
  std::string head(std::min(n, size), '\0'), tail(std::min(n, size), '\0');
  in.seekg(0);
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  in.seekg(static_cast<std::streamoff>(size - tail.size()));
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  return {head, tail};
}

// STEP (ISO 10303-21) files open with ISO-10303-21; and close with END-ISO-10303-21;.
// OCCT's parser accepts a file cut at an entity boundary and silently loses the rest.
void checkStepFraming(const std::string& path) {
  auto [head, tail] = headAndTail(path, 4096);
  if (head.find("ISO-10303-21") == std::string::npos)
    throw InputError(path, "not a STEP file: it does not begin with ISO-10303-21;");
  if (tail.find("END-ISO-10303-21") == std::string::npos)
    throw InputError(path, "truncated STEP file: it does not end with END-ISO-10303-21;");
}

// The largest magnitude of a number in a STEP file: no length, angle, knot or weight of a
// part comes near it, and squares of larger ones overflow in the CAD kernel, which then
// meshes without end.
constexpr double kLargestStepNumber = 1e15;

// Refuses the number that may begin at text[k] (after a comma or parenthesis) when it is
// beyond kLargestStepNumber, naming `entity`.
void checkStepNumber(const std::string& text, std::size_t k, long entity, const std::string& path) {
  while (k < text.size() && (text[k] == ' ' || text[k] == '\n' || text[k] == '\r')) ++k;
  if (k >= text.size() ||
      !(std::isdigit(static_cast<unsigned char>(text[k])) || text[k] == '-' || text[k] == '+'))
    return;
  char* end = nullptr;
  const double value = std::strtod(text.c_str() + k, &end);
  if (!(std::abs(value) <= kLargestStepNumber))
    throw InputError(
        path,
        fmt::format("entity #{} holds the number {}, beyond the ±1e15 of any "
                    "length, angle or parameter of a part",
                    entity, text.substr(k, std::min<std::size_t>(end - (text.c_str() + k), 40))));
}

// The faces and solids a STEP file defines, to tell whether all came through.
struct StepCounts {
  std::size_t faces = 0, solids = 0;
};

// Counts the entity whose type begins at text[k] (after "#n =").
void countEntity(const std::string& text, std::size_t k, StepCounts& counts) {
  while (k < text.size() && std::isspace(static_cast<unsigned char>(text[k]))) ++k;
  std::size_t end = k;
  while (end < text.size() &&
         (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '_'))
    ++end;
  const std::string_view type(text.data() + k, end - k);
  counts.faces += type == "ADVANCED_FACE" || type == "FACE_SURFACE";
  counts.solids += type == "MANIFOLD_SOLID_BREP" || type == "BREP_WITH_VOIDS";
}

// Every entity a STEP file's data section refers to (#n) must be defined there, once:
// OCCT's translator follows a dangling reference into a crash, and takes one of two
// definitions silently. No number may be out of range.
StepCounts checkStepEntities(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t k = text.find("DATA;");
  StepCounts counts;
  if (k == std::string::npos) return counts;
  std::unordered_set<long> defined;
  std::vector<std::pair<long, long>> references;  // (referenced, by the entity)
  long entity = 0;
  bool in_string = false, statement_start = true;
  for (k += 5; k < text.size(); ++k) {
    const char c = text[k];
    if (in_string) {
      if (c == '\'' && k + 1 < text.size() && text[k + 1] == '\'')
        ++k;
      else if (c == '\'')
        in_string = false;
      continue;
    }
    if (c == '\'') in_string = true;
    if (c == ';') statement_start = true;
    if ((c == ',' || c == '(') && k + 1 < text.size()) checkStepNumber(text, k + 1, entity, path);
    if (c != '#') {
      if (!std::isspace(static_cast<unsigned char>(c)) && c != ';') statement_start = false;
      continue;
    }
    long id = 0;
    while (k + 1 < text.size() && std::isdigit(static_cast<unsigned char>(text[k + 1])))
      if ((id = id * 10 + (text[++k] - '0')) > 999'999'999'999)
        throw InputError(path, "an entity number of more than 12 digits");
    std::size_t next = k + 1;
    while (next < text.size() && std::isspace(static_cast<unsigned char>(text[next]))) ++next;
    if (statement_start && next < text.size() && text[next] == '=') {
      if (!defined.insert(id).second)
        throw InputError(path, "entity #" + std::to_string(id) + " is defined twice");
      entity = id;
      countEntity(text, next + 1, counts);
    } else {
      references.push_back({id, entity});
    }
    statement_start = false;
  }
  for (const auto& [id, by] : references)
    if (!defined.count(id))
      throw InputError(path, "entity #" + std::to_string(by) + " refers to #" + std::to_string(id) +
                                 ", which the file does not define");
  return counts;
}

// Warns of faces and solids the file defines that did not come through the translator (a
// face whose geometry is corrupt, a negative radius, is dropped with its solid).
void warnOfLostEntities(Part& part, const StepCounts& counts) {
  if (part.faces.size() < counts.faces)
    part.warnings.push_back(
        fmt::format("the file defines {} faces, of which {} could be read: "
                    "the others' geometry is corrupt",
                    counts.faces, part.faces.size()));
  if (part.solids.size() < counts.solids)
    part.warnings.push_back(
        fmt::format("the file defines {} solids, of which {} could be read: "
                    "a face of the others could not be",
                    counts.solids, part.solids.size()));
}

// IGES files end with the one-line Terminate section, marked 'T' in column 73.
void checkIgesFraming(const std::string& path) {
  auto [head, tail] = headAndTail(path, 1024);
  std::size_t end = tail.find_last_not_of(" \r\n\t");
  std::size_t start = end == std::string::npos ? std::string::npos : tail.rfind('\n', end);
  std::string last = tail.substr(start == std::string::npos ? 0 : start + 1,
                                 end == std::string::npos ? 0 : end - start);
  if (last.size() < 73 || last[72] != 'T')
    throw InputError(path, "truncated IGES file: its last line is not the Terminate section");
}

// The tables of an OCCT BREP file, and the other words it holds after its header: the
// kinds of shape, the end of a list of sub-shapes, the continuities of edges, and the mark
// before a polygon's parameters.
const std::unordered_set<std::string> kBrepTables = {
    "Locations", "Curve2ds", "Curves",         "Polygon3D", "PolygonOnTriangulations",
    "Polygon2D", "Surfaces", "Triangulations", "TShapes"};

bool isBrepWord(const std::string& word) {
  static const std::unordered_set<std::string> kWords = {"Ve", "Ed", "Wi", "Fa", "Sh", "So",
                                                         "CS", "Co", "*",  "C0", "C1", "C2",
                                                         "C3", "CN", "G1", "G2", "p"};
  return kWords.count(word) > 0 || kBrepTables.count(word) > 0;
}

// Whether `word` is a decimal number, or an index written against a continuity ("2CN").
bool isBrepNumber(const std::string& word) {
  std::size_t end = word.find_first_not_of("+-.0123456789eE");
  if (end == 0) return false;
  if (end != std::string::npos && !(end + 2 == word.size() && isBrepWord(word.substr(end))))
    return false;
  const std::string number = word.substr(0, end);
  char* rest = nullptr;
  std::strtod(number.c_str(), &rest);
  return rest == number.c_str() + number.size();
}

// An OCCT BREP file is plain ASCII: after its header, numbers and a few words, and each
// table opens with the count of its entries ("Curves 15"). A byte that is no text, a
// number with a letter in it, or a count beyond what the file's size could hold sends
// OCCT's reader into a loop without end, or makes it read nonsense without a word.
void checkBrepText(const std::string& path) {
  const auto size = std::filesystem::file_size(path);
  std::ifstream in(path, std::ios::binary);
  std::string line;
  bool header = true;
  for (long number = 1; std::getline(in, line); ++number) {
    for (const char c : line)
      if ((static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\r') ||
          static_cast<unsigned char>(c) > 0x7e)
        throw InputError(path, fmt::format("line {}: a byte that is no text (0x{:02x}): an OCCT "
                                           "BREP file is plain ASCII",
                                           number, static_cast<unsigned char>(c)));
    std::istringstream in_line(line);
    const std::vector<std::string> words{std::istream_iterator<std::string>(in_line), {}};
    header = header && !(!words.empty() && words[0] == "Locations");
    for (const std::string& word : words)
      if (!header && !isBrepWord(word) && !isBrepNumber(word))
        throw InputError(path, fmt::format("line {}: '{}' is neither a number nor a word of an "
                                           "OCCT BREP file",
                                           number, word));
    if (words.size() < 2 || !kBrepTables.count(words[0])) continue;
    const double count = std::strtod(words[1].c_str(), nullptr);
    if (!(count >= 0 && count <= static_cast<double>(size)))
      throw InputError(path, fmt::format("line {}: the table {} announces {:.0f} entries, more "
                                         "than a file of {} bytes can hold",
                                         number, words[0], count, size));
  }
}

// Refuses a part without triangles, larger or farther than the simulation keeps to
// 0.01 mm, or with a face without a boundary; warns of one under a millimetre across.
void checkImported(Part& part, const std::string& path) {
  if (part.mesh.empty()) throw InputError(path, "no triangles: the geometry could not be meshed");
  double extent = part.bounds().size().maxCoeff();
  if (!(extent <= kLongestLength))
    throw InputError(path, fmt::format("the part is {:.3g} mm across, more than 100 m: check the "
                                       "length unit the file declares ({})",
                                       extent, part.file_unit.empty() ? "none" : part.file_unit));
  // Ray casting and the simulation work in single precision, which keeps 0.01 mm only
  // within 100 m of the origin.
  const Box box = part.bounds();
  const double reach = std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
  if (!(reach <= kLongestLength))
    throw InputError(path, fmt::format("the part lies {:.3g} mm from the origin of its file, "
                                       "more than 100 m, where the simulation keeps less than "
                                       "0.01 mm: move it nearer the origin",
                                       reach));
  // A face without a boundary (an untrimmed plane) has an area without end.
  for (const Face& face : part.faces)
    if (!(face.area <= kLongestLength * kLongestLength))
      throw InputError(path, fmt::format("face {} has an area of {:.3g} mm², more than the part "
                                         "can hold: it has no boundary",
                                         face.id, face.area));
  if (extent < 1.0)
    part.warnings.push_back("the part is only " + std::to_string(extent) +
                            " mm across: check the length unit the file declares (" +
                            (part.file_unit.empty() ? "none" : part.file_unit) + ")");
}

}  // namespace

InputError detail::kernelError(const std::string& path, const Standard_Failure& failure) {
  return InputError(path, std::string("the CAD kernel failed on it: ") +
                              (failure.GetMessageString() ? failure.GetMessageString() : "") +
                              " (" + failure.DynamicType()->Name() + ")");
}

Part importPart(const std::string& path, const ImportOptions& options, const Progress& progress) {
  // OCCT's readers print their statistics on stdout through its default messenger; the
  // library speaks through its errors and `progress` only.
  static std::once_flag silenced;
  std::call_once(silenced, [] { Message::DefaultMessenger()->ChangePrinters().Clear(); });
  namespace fs = std::filesystem;
  std::error_code ec;
  requireInputFile(path);
  if (fs::file_size(path, ec) == 0) throw InputError(path, "empty file");
  const bool finite = std::isfinite(options.linear_deflection) &&
                      std::isfinite(options.relative_deflection) &&
                      std::isfinite(options.mesh_unit);
  if (!finite || !(options.linear_deflection >= 0) || !(options.relative_deflection > 0) ||
      !(options.angular_deflection > 0 && options.angular_deflection < 90) ||
      !(options.sharp_angle >= 0 && options.sharp_angle <= 180) || !(options.mesh_unit > 0))
    throw InputError(path,
                     "invalid import options (deflections and mesh unit must be positive, "
                     "the angular deflection within (0, 90) degrees, the sharp-edge angle "
                     "within [0, 180] degrees)");

  std::string format = formatOf(path);
  StepCounts defined;
  if (format == "STEP") {
    report(progress, "checking STEP entities", 0);
    checkStepFraming(path);
    defined = checkStepEntities(path);
  }
  if (format == "IGES") checkIgesFraming(path);
  if (format == "BREP") checkBrepText(path);

  Part part;
  try {
    part = format == "STEP" || format == "IGES" || format == "BREP"
               ? detail::importBRep(path, format, options, progress)
               : detail::importMesh(path, format, options, progress);
  } catch (const Standard_Failure& failure) {
    throw detail::kernelError(path, failure);
  }
  checkImported(part, path);
  warnOfLostEntities(part, defined);
  return part;
}

}  // namespace scanplan
