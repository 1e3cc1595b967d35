// scanplan info: what the importer read from a CAD or mesh file.

#include "commands.h"
#include "terminal.h"

#include <scanplan/cad/import.h>
#include <scanplan/cad/localization.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <iostream>
#include <map>

namespace scanplan::cli {
namespace {

using nlohmann::json;

json toJson(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

std::map<std::string, int> surfaceHistogram(const Part& part) {
  std::map<std::string, int> histogram;
  for (const Face& face : part.faces) ++histogram[std::string(toString(face.type))];
  return histogram;
}

json infoJson(const Part& part) {
  Box box = part.bounds();
  json solids = json::array();
  for (const Solid& solid : part.solids)
    solids.push_back({{"name", solid.name}, {"volume", solid.volume}, {"faces", solid.faces}});
  json tolerances = json::array(), dimensions = json::array(), datums = json::array();
  for (const GeometricTolerance& t : part.gdt.tolerances)
    tolerances.push_back(
        {{"type", t.type}, {"value", t.value}, {"datums", t.datums}, {"faces", t.faces}});
  for (const Dimension& d : part.gdt.dimensions)
    dimensions.push_back({{"type", d.type},
                          {"value", d.value},
                          {"lower", d.lower},
                          {"upper", d.upper},
                          {"faces", d.faces}});
  for (const Datum& d : part.gdt.datums) datums.push_back({{"name", d.name}, {"faces", d.faces}});
  int reoriented = 0, free_faces = 0;
  for (const Face& face : part.faces) {
    reoriented += face.reoriented;
    free_faces += face.solid < 0;
  }
  return {
      {"file", part.file},
      {"format", part.format},
      {"units", "mm"},
      {"file_unit", part.file_unit},
      {"bounds",
       {{"min", toJson(box.min)}, {"max", toJson(box.max)}, {"size", toJson(box.size())}}},
      {"solids", solids},
      {"faces", part.faces.size()},
      {"surface_types", surfaceHistogram(part)},
      {"reoriented_faces", reoriented},
      {"faces_outside_solids", free_faces},
      {"triangles", part.mesh.triangles.size()},
      {"area", part.area()},
      {"volume", part.volume()},
      {"mesh",
       {{"linear_deflection", part.linear_deflection},
        {"angular_deflection", degrees(part.angular_deflection)}}},
      {"gdt", {{"tolerances", tolerances}, {"dimensions", dimensions}, {"datums", datums}}},
      {"warnings", part.warnings},
  };
}

std::string faceList(const std::vector<int>& faces) {
  return faces.empty() ? "(no face)" : fmt::format("faces {}", fmt::join(faces, ", "));
}

void printInfo(const Part& part) {
  Box box = part.bounds();
  Vec3 size = box.size();
  fmt::print("file         {}\n", part.file);
  fmt::print("format       {} (file unit: {}; shown in mm)\n", part.format,
             part.file_unit.empty() ? "not declared" : part.file_unit);
  fmt::print("bounds       [{:.3f}, {:.3f}, {:.3f}] .. [{:.3f}, {:.3f}, {:.3f}]\n", box.min.x(),
             box.min.y(), box.min.z(), box.max.x(), box.max.y(), box.max.z());
  fmt::print("size         {:.3f} x {:.3f} x {:.3f} mm\n", size.x(), size.y(), size.z());
  int free_faces = 0;
  for (const Face& face : part.faces) free_faces += face.solid < 0;
  fmt::print("solids       {}\n", part.solids.size());
  fmt::print("faces        {}{}\n", part.faces.size(),
             free_faces ? fmt::format(" ({} outside any solid)", free_faces) : "");
  for (const auto& [type, count] : surfaceHistogram(part)) fmt::print("  {:<11}{}\n", type, count);
  fmt::print("triangles    {} (chordal tolerance {:.3g} mm)\n", part.mesh.triangles.size(),
             part.linear_deflection);
  fmt::print("area         {:.6g} mm²\n", part.area());
  fmt::print("volume       {:.6g} mm³\n", part.volume());
  const Gdt& gdt = part.gdt;
  fmt::print("GD&T         {} tolerances, {} dimensions, {} datums\n", gdt.tolerances.size(),
             gdt.dimensions.size(), gdt.datums.size());
  for (const GeometricTolerance& t : gdt.tolerances) {
    std::string datums = t.datums.empty() ? "" : fmt::format(" | {}", fmt::join(t.datums, " | "));
    fmt::print("  {:<20} {:g}{}  {}\n", t.type, t.value, datums, faceList(t.faces));
  }
  for (const Datum& d : gdt.datums) fmt::print("  datum {:<14} {}\n", d.name, faceList(d.faces));
  std::size_t without_value = 0;
  for (const Dimension& d : gdt.dimensions) {
    if (d.value == 0) {
      ++without_value;
      continue;
    }
    std::string range =
        d.lower == 0 && d.upper == 0 ? "" : fmt::format(" (-{:g}/+{:g})", d.lower, d.upper);
    fmt::print("  {:<20} {:g}{}  {}\n", d.type, d.value, range, faceList(d.faces));
  }
  if (without_value > 0)
    fmt::print("  ({} dimension entries without a value: presentation or callout only)\n",
               without_value);
  for (const std::string& warning : part.warnings) fmt::print("warning: {}\n", warning);
}

}  // namespace

void addInfoCommand(CLI::App& app, const GlobalOptions& global, Action& selected) {
  struct Options {
    std::string file;
    bool json = false;
    bool rest = false;
    ImportOptions import;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command =
      app.add_subcommand("info", "Show what scanplan reads from a CAD or mesh file");
  command->add_option("file", options->file, "STEP, IGES, BREP, STL, OBJ, PLY or OFF file")
      ->required();
  command->add_flag("--json", options->json, "Print the information as one JSON object");
  command->add_flag("--rest", options->rest,
                    "Also list the stable rest orientations on the working plane, steadiest first");
  command->add_option("--deflection", options->import.linear_deflection,
                      "Chordal tolerance of the mesh in mm (default: from the part size)");
  command->add_option(
      "--sharp-angle", options->import.sharp_angle,
      "Meshes without groups are split into faces at edges sharper than this (degrees)");
  command->callback([options, &global, &selected] {
    selected = [options, &global] {
      Part part = importPart(options->file, options->import, terminalProgress(global));
      clearProgress();
      nlohmann::json info = infoJson(part);
      std::vector<RestOrientation> rests;
      if (options->rest) {
        rests = restOrientations(part);
        info["rest_orientations"] = nlohmann::json::array();
        for (const RestOrientation& r : rests)
          info["rest_orientations"].push_back({{"down", toJson(r.down)},
                                               {"margin", r.margin},
                                               {"contact_area", r.contact_area},
                                               {"height", r.height}});
      }
      if (options->json) {
        std::cout << info.dump(2) << '\n';
        return 0;
      }
      printInfo(part);
      if (!options->rest) return 0;
      fmt::print(
          "rest orientations: {} (steadiest first; margin = distance from the centre of mass's "
          "projection to the contact edge / its height)\n",
          rests.size());
      for (std::size_t k = 0; k < rests.size(); ++k)
        fmt::print(
            "  {:>2}: down ({:+.3f}, {:+.3f}, {:+.3f})  margin {:.3f}  contact {:.0f} mm²  height "
            "{:.1f} mm\n",
            k + 1, rests[k].down.x(), rests[k].down.y(), rests[k].down.z(), rests[k].margin,
            rests[k].contact_area, rests[k].height);
      return 0;
    };
  });
}

}  // namespace scanplan::cli
