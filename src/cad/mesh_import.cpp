// Triangle-mesh import (STL, OBJ, PLY, OFF) and the split of a mesh into faces: by its
// groups where the file has them, otherwise by sharp edges.

#include "cad/brep_import.h"

#include <scanplan/cad/ply.h>
#include <scanplan/core/disjoint_sets.h>
#include <scanplan/core/errors.h>

#include <OSD_Path.hxx>
#include <Poly_Triangulation.hxx>
#include <RWStl.hxx>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <sstream>
#include <unordered_map>

namespace scanplan::detail {
namespace {

// A mesh as read from a file: polygons already fanned into triangles; a group per
// triangle (-1 where the file has none) and the groups' names.
struct RawMesh {
  std::vector<Vec3> vertices;
  std::vector<Vec3i> triangles;
  std::vector<int> groups;
  std::vector<std::string> group_names;
};

// Adds `polygon` (0-based indices) as a fan of triangles. `first` is the number the file
// gives its first vertex (0 in OFF and PLY, 1 in OBJ), for the error naming a bad index.
void addPolygon(RawMesh& mesh, const std::vector<long long>& polygon, int group, int first,
                const std::string& path) {
  if (polygon.size() < 3)
    throw InputError(
        path, "a face of " + std::to_string(polygon.size()) + " vertices: a face needs at least 3");
  const auto n = static_cast<long long>(mesh.vertices.size());
  for (long long index : polygon)
    if (index < 0 || index >= n)
      throw InputError(path, "a face refers to vertex " + std::to_string(index + first) +
                                 " but the file has " + std::to_string(n) + " vertices, numbered " +
                                 std::to_string(first) + " to " + std::to_string(n - 1 + first));
  for (std::size_t k = 2; k < polygon.size(); ++k) {
    mesh.triangles.emplace_back(polygon[0], polygon[k - 1], polygon[k]);
    mesh.groups.push_back(group);
  }
}

// An ASCII STL, read strictly: every facet whole, every number a number. \throw InputError
// naming the line of the first word out of place.
RawMesh readAsciiStl(const std::string& path) {
  std::ifstream in(path);
  RawMesh mesh;
  std::string line;
  int line_no = 0;
  std::istringstream words;
  auto next = [&](const std::string& expected) {  // the next line, which must start so
    std::string first;
    while (std::getline(in, line)) {
      ++line_no;
      words.clear();
      words.str(line);
      if (words >> first) break;
    }
    if (!in && first.empty())
      throw InputError(path, "truncated STL file: '" + expected + "' expected at the end");
    std::string rest = first;
    for (std::size_t n = std::count(expected.begin(), expected.end(), ' '); n > 0; --n) {
      std::string word;
      words >> word;
      rest += " " + word;
    }
    if (rest != expected && !(expected == "facet normal" && first == "endsolid"))
      throw InputError(path, "line " + std::to_string(line_no) + ": '" + expected +
                                 "' expected, found '" + line + "'");
    return first;
  };
  auto point = [&] {
    Vec3 p;
    if (!(words >> p.x() >> p.y() >> p.z()) || !p.allFinite())
      throw InputError(path, "line " + std::to_string(line_no) + ": three numbers expected");
    return p;
  };
  next("solid");
  while (next("facet normal") != "endsolid") {
    point();
    next("outer loop");
    const int first = static_cast<int>(mesh.vertices.size());
    for (int k = 0; k < 3; ++k) {
      next("vertex");
      mesh.vertices.push_back(point());
    }
    next("endloop");
    next("endfacet");
    mesh.triangles.emplace_back(first, first + 1, first + 2);
    mesh.groups.push_back(-1);
  }
  return mesh;
}

// True when the file is a binary STL: exactly the size its triangle count gives (84 bytes
// of header and count, 50 per triangle). Its header may start with "solid" too.
bool isBinaryStl(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[84] = {};
  in.read(header, sizeof header);
  if (in.gcount() < 84) return false;
  std::uint32_t count = 0;
  std::memcpy(&count, header + 80, 4);
  std::error_code ec;
  return std::filesystem::file_size(path, ec) == 84 + 50 * static_cast<std::uintmax_t>(count);
}

RawMesh readStl(const std::string& path) {
  if (!isBinaryStl(path)) return readAsciiStl(path);
  Handle(Poly_Triangulation) tri = RWStl::ReadBinary(OSD_Path(path.c_str()));
  RawMesh mesh;
  if (tri.IsNull()) return mesh;
  for (int i = 1; i <= tri->NbNodes(); ++i) {
    gp_Pnt p = tri->Node(i);
    mesh.vertices.emplace_back(p.X(), p.Y(), p.Z());
  }
  for (int i = 1; i <= tri->NbTriangles(); ++i) {
    int a, b, c;
    tri->Triangle(i).Get(a, b, c);
    mesh.triangles.emplace_back(a - 1, b - 1, c - 1);
    mesh.groups.push_back(-1);
  }
  return mesh;
}

RawMesh readObj(const std::string& path) {
  std::ifstream in(path);
  RawMesh mesh;
  int group = -1;
  std::map<std::string, int> group_ids;
  std::string line;
  std::vector<long long> polygon;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "v") {
      Vec3 p;
      if (!(words >> p.x() >> p.y() >> p.z()))
        throw InputError(path, "line " + std::to_string(line_no) + ": malformed vertex");
      mesh.vertices.push_back(p);
    } else if (tag == "f") {
      polygon.clear();
      std::string corner;
      while (words >> corner) {
        long long index = 0;
        try {
          index = std::stoll(corner.substr(0, corner.find('/')));
        } catch (const std::exception&) {
          throw InputError(path, "line " + std::to_string(line_no) + ": malformed face");
        }
        // OBJ indices are 1-based; negative ones count back from the last vertex.
        polygon.push_back(index < 0 ? static_cast<long long>(mesh.vertices.size()) + index
                                    : index - 1);
      }
      addPolygon(mesh, polygon, group, 1, path);
    } else if (tag == "g" || tag == "o") {
      std::string name;
      std::getline(words >> std::ws, name);
      if (name.empty()) name = tag == "g" ? "default" : "object";
      auto [it, inserted] = group_ids.emplace(name, static_cast<int>(mesh.group_names.size()));
      if (inserted) mesh.group_names.push_back(name);
      group = it->second;
    }
  }
  return mesh;
}

RawMesh readOff(const std::string& path) {
  std::ifstream in(path);
  RawMesh mesh;
  // Comments start with '#'; the header is OFF (optionally with C/N/ST prefixes).
  std::stringstream body;
  for (std::string line; std::getline(in, line);) body << line.substr(0, line.find('#')) << '\n';
  std::string header;
  body >> header;
  if (header.size() < 3 || header.compare(header.size() - 3, 3, "OFF") != 0)
    throw InputError(path, "not an OFF file: it does not begin with OFF");
  long vertices = -1, faces = -1, edges = 0;
  if (!(body >> vertices >> faces >> edges) || vertices < 0 || faces < 0)
    throw InputError(path, "malformed OFF header: expected vertex, face and edge counts");
  bool colored = header.find('C') != std::string::npos;
  // Each index of a face takes two characters at least: a face announcing more than the
  // file holds is refused before anything is allocated for it.
  const std::size_t characters = body.str().size();
  std::string rest;
  for (long i = 0; i < vertices; ++i) {
    Vec3 p;
    if (!(body >> p.x() >> p.y() >> p.z()))
      throw InputError(path, (body.eof() ? "truncated OFF file: vertex " : "OFF file: vertex ") +
                                 std::to_string(i + 1) + " of " + std::to_string(vertices) +
                                 (body.eof() ? " is missing" : " is not three numbers"));
    if (colored) std::getline(body, rest);
    mesh.vertices.push_back(p);
  }
  std::vector<long long> polygon;
  for (long i = 0; i < faces; ++i) {
    int n = 0;
    if (!(body >> n) || n < 0)
      throw InputError(path, "truncated OFF file: face " + std::to_string(i + 1) + " of " +
                                 std::to_string(faces) + " is missing");
    if (static_cast<std::size_t>(n) > characters / 2)
      throw InputError(path, "OFF file: face " + std::to_string(i + 1) + " announces " +
                                 std::to_string(n) + " vertices, more than the file holds");
    polygon.resize(n);
    for (long long& index : polygon)
      if (!(body >> index))
        throw InputError(path, "truncated OFF file in face " + std::to_string(i + 1));
    std::getline(body, rest);  // optional face colour
    addPolygon(mesh, polygon, -1, 0, path);
  }
  return mesh;
}

// PLY (any format readPly reads): vertices x, y, z and a face list vertex_indices (or
// vertex_index); a face scalar named group, face_id or segment becomes the group.
RawMesh readPlyMesh(const std::string& path) {
  const PlyData data = readPly(path);
  RawMesh mesh;
  const PlyElement* vertices = data.find("vertex");
  if (vertices != nullptr) {
    const std::vector<double>& x = plyColumn(data, "vertex", "x", path);
    const std::vector<double>& y = plyColumn(data, "vertex", "y", path);
    const std::vector<double>& z = plyColumn(data, "vertex", "z", path);
    for (std::size_t i = 0; i < vertices->count; ++i) mesh.vertices.emplace_back(x[i], y[i], z[i]);
  }
  const PlyElement* faces = data.find("face");
  if (faces == nullptr) return mesh;
  const PlyProperty* indices = faces->find("vertex_indices");
  if (indices == nullptr) indices = faces->find("vertex_index");
  if (indices == nullptr || !indices->is_list) return mesh;
  const PlyProperty* group = nullptr;
  for (const char* name : {"group", "face_id", "segment"})
    if (group == nullptr && faces->find(name) != nullptr && !faces->find(name)->is_list)
      group = faces->find(name);
  std::map<long, int> group_ids;
  for (std::size_t i = 0; i < faces->count; ++i) {
    int g = -1;
    if (group != nullptr) {
      const long key = std::lround(group->values[i]);
      auto [it, inserted] = group_ids.emplace(key, static_cast<int>(group_ids.size()));
      if (inserted) mesh.group_names.push_back("group " + std::to_string(key));
      g = it->second;
    }
    addPolygon(mesh, {indices->lists[i].begin(), indices->lists[i].end()}, g, 0, path);
  }
  return mesh;
}

// Splits the triangles into faces: connected regions of one group, or, without groups,
// regions whose neighbouring triangles meet at less than `sharp_angle` (radians).
std::vector<int> regionOfTriangles(const TriangleMesh& mesh, const std::vector<int>& groups,
                                   bool by_group, double sharp_angle) {
  const std::size_t n = mesh.triangles.size();
  std::unordered_map<std::uint64_t, std::vector<int>> edge_triangles;
  edge_triangles.reserve(n * 2);
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      auto a = static_cast<std::uint64_t>(mesh.triangles[t][k]);
      auto b = static_cast<std::uint64_t>(mesh.triangles[t][(k + 1) % 3]);
      if (a != b)
        edge_triangles[(std::min(a, b) << 32) | std::max(a, b)].push_back(static_cast<int>(t));
    }
  std::vector<Vec3> normals(n);
  for (std::size_t t = 0; t < n; ++t) normals[t] = mesh.normal(t);
  const double min_cos = std::cos(sharp_angle);
  auto joins = [&](int t, int u) {
    if (by_group) return groups[t] == groups[u];
    if (normals[t].isZero() || normals[u].isZero()) return true;  // degenerate: no edge
    return normals[t].dot(normals[u]) >= min_cos;
  };
  // Union-find over triangles joined across their shared edges.
  DisjointSets sets(n);
  for (const auto& [edge, triangles] : edge_triangles)
    for (std::size_t i = 0; i < triangles.size(); ++i)
      for (std::size_t j = i + 1; j < triangles.size(); ++j)
        if (joins(triangles[i], triangles[j])) sets.join(triangles[i], triangles[j]);
  std::vector<int> region(n);
  for (std::size_t t = 0; t < n; ++t) region[t] = sets.find(static_cast<int>(t));
  return region;
}

// A closed mesh is one solid; wound inward, it is turned outward. An open one is named in
// the part's warnings.
void closeSolid(Part& part) {
  EdgeReport edges = edgeReport(part.mesh, 0);
  if (edges.boundary == 0 && edges.non_manifold == 0 && edges.misoriented == 0) {
    double volume = signedVolume(part.mesh);
    if (volume < 0) {
      for (Vec3i& tri : part.mesh.triangles) std::swap(tri[1], tri[2]);
      for (Face& face : part.faces) face.reoriented = true;
      part.warnings.push_back("the mesh was wound inward; its triangles were turned outward");
    }
    Solid solid;
    solid.volume = std::abs(volume);
    for (Face& face : part.faces) {
      face.solid = 0;
      solid.faces.push_back(face.id);
    }
    part.solids.push_back(std::move(solid));
  } else {
    part.warnings.push_back("the mesh is not closed (" + std::to_string(edges.boundary) +
                            " boundary, " + std::to_string(edges.non_manifold) + " non-manifold, " +
                            std::to_string(edges.misoriented) +
                            " inconsistently wound edges): inside and outside are not checked");
  }
}

// Triangles without area (corners coincident or in a line, as a polygon collapsed to a
// segment gives) are named in the part's warnings: they measure nothing.
void warnOfEmptyTriangles(Part& part) {
  std::size_t empty = 0;
  for (std::size_t t = 0; t < part.mesh.triangles.size(); ++t) empty += !(part.mesh.area(t) > 0);
  if (empty > 0)
    part.warnings.push_back(std::to_string(empty) + " of the mesh's " +
                            std::to_string(part.mesh.triangles.size()) +
                            " triangles have no area (corners coincident or in a line)");
}

}  // namespace

Part importMesh(const std::string& path, const std::string& format, const ImportOptions& options,
                const Progress& progress) {
  report(progress, "reading " + format, 0);
  RawMesh raw = format == "STL"   ? readStl(path)
                : format == "OBJ" ? readObj(path)
                : format == "PLY" ? readPlyMesh(path)
                                  : readOff(path);
  if (raw.triangles.empty()) throw InputError(path, "no triangles: the mesh is empty");
  for (const Vec3& p : raw.vertices)
    if (!p.allFinite()) throw InputError(path, "a vertex has a non-finite coordinate");

  Part part;
  part.file = path;
  part.format = format;
  part.unit_scale = options.mesh_unit;
  part.file_unit = options.mesh_unit == 1 ? "mm" : "";

  // Weld coincident vertices so that neighbouring triangles share their edges.
  TriangleMesh welded;
  std::vector<int> rep = weldVertices(raw.vertices, 0);
  std::vector<int> index(raw.vertices.size(), -1);
  for (std::size_t i = 0; i < raw.vertices.size(); ++i)
    if (rep[i] == static_cast<int>(i)) {
      index[i] = static_cast<int>(welded.vertices.size());
      welded.vertices.push_back(raw.vertices[i] * options.mesh_unit);
    }
  for (const Vec3i& tri : raw.triangles)
    welded.triangles.emplace_back(index[rep[tri[0]]], index[rep[tri[1]]], index[rep[tri[2]]]);

  report(progress, "splitting mesh into faces", 0);
  bool by_group = std::any_of(raw.groups.begin(), raw.groups.end(), [](int g) { return g >= 0; });
  std::vector<int> region =
      regionOfTriangles(welded, raw.groups, by_group, radians(options.sharp_angle));

  // Faces numbered by their first triangle; triangles reordered so each face is contiguous.
  std::unordered_map<int, int> face_of_region;
  for (int r : region) face_of_region.emplace(r, static_cast<int>(face_of_region.size()) + 1);
  std::vector<int> order(welded.triangles.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return face_of_region[region[a]] < face_of_region[region[b]];
  });
  part.mesh.vertices = welded.vertices;
  part.faces.resize(face_of_region.size());
  for (int t : order) {
    int id = face_of_region[region[t]];
    Face& face = part.faces[id - 1];
    if (face.triangle_count == 0) {
      face.id = id;
      face.type = SurfaceType::Mesh;
      face.first_triangle = static_cast<int>(part.mesh.triangles.size());
      if (by_group && raw.groups[t] >= 0) face.name = raw.group_names[raw.groups[t]];
    }
    part.mesh.triangles.push_back(welded.triangles[t]);
    part.mesh.triangle_faces.push_back(id);
    std::size_t added = part.mesh.triangles.size() - 1;
    face.area += part.mesh.area(added);
    for (int k = 0; k < 3; ++k) face.bounds.add(part.mesh.vertices[welded.triangles[t][k]]);
    ++face.triangle_count;
  }

  closeSolid(part);
  warnOfEmptyTriangles(part);
  report(progress, "splitting mesh into faces", 1);
  return part;
}

}  // namespace scanplan::detail
