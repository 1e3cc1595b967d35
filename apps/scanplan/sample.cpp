// scanplan sample: the samples the spec's tasks ask for, and their clusters.

#include "commands.h"
#include "terminal.h"

#include <scanplan/cad/import.h>
#include <scanplan/cad/ply.h>
#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/pgm.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning.h>
#include <scanplan/sampling/clustering.h>
#include <scanplan/sampling/sampling.h>
#include <scanplan/scanner/visibility.h>
#include <scanplan/spec/spec.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <map>

namespace scanplan::cli {
namespace {

using nlohmann::json;

struct Options {
  std::string part;
  std::string spec;
  std::string out;
  std::string cvm_dir;
};

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

void writeSamples(const std::string& path, const std::vector<Sample>& samples,
                  const std::vector<Cluster>& clusters) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".json") {
    json list = json::array();
    for (const Sample& s : samples)
      list.push_back({{"position", vec(s.position)},
                      {"normal", vec(s.normal)},
                      {"face", s.face},
                      {"uv", {s.uv.x(), s.uv.y()}},
                      {"role", toString(s.role)},
                      {"task", toString(s.task)},
                      {"weight", s.weight},
                      {"cluster", s.cluster}});
    json groups = json::array();
    for (std::size_t c = 0; c < clusters.size(); ++c)
      groups.push_back({{"id", c},
                        {"samples", clusters[c].samples.size()},
                        {"mean_position", vec(clusters[c].mean_position)},
                        {"mean_normal", vec(clusters[c].mean_normal)}});
    writeFileAtomically(path, [&](std::ostream& out) {
      out << json{{"samples", list}, {"clusters", groups}}.dump(1) << '\n';
    });
    return;
  }
  if (ext != ".ply")
    throw OutputError(path, "unsupported output type '" + ext + "' (expected .ply or .json)");
  PlyElement vertex{"vertex", samples.size(), {}};
  auto add = [&](const char* name, PlyType type, auto value) {
    std::vector<double> values;
    values.reserve(samples.size());
    for (const Sample& sample : samples) values.push_back(static_cast<double>(value(sample)));
    vertex.add(name, type, std::move(values));
  };
  const char* axes[3] = {"x", "y", "z"};
  const char* normal_axes[3] = {"nx", "ny", "nz"};
  for (int k = 0; k < 3; ++k)
    add(axes[k], PlyType::Float32, [k](auto& s) { return s.position[k]; });
  for (int k = 0; k < 3; ++k)
    add(normal_axes[k], PlyType::Float32, [k](auto& s) { return s.normal[k]; });
  add("face", PlyType::Int32, [](auto& s) { return s.face; });
  add("cluster", PlyType::Int32, [](auto& s) { return s.cluster; });
  add("role", PlyType::UInt8, [](auto& s) { return static_cast<int>(s.role); });
  add("task", PlyType::UInt8, [](auto& s) { return static_cast<int>(s.task); });
  writePly(PlyData{{"scanplan samples, mm, part frame"}, {std::move(vertex)}}, path);
}

int run(const Options& options, const GlobalOptions& global) {
  Progress progress = terminalProgress(global);
  const Spec spec = options.spec.empty() ? defaultSpec() : loadSpec(options.spec);
  const Part part = importWithWarnings(options.part, {}, progress);
  const ResolvedSpec resolved = resolveSpec(part, spec);
  printWarnings("", resolved.warnings);
  report(progress, "sampling", 0);
  std::vector<Sample> samples =
      sampleTargets(part, resolved.targets, samplingOptionsFor(spec.scanner));
  report(progress, "clustering", 0);
  const std::vector<Cluster> clusters =
      clusterSamples(samples, clusteringOptionsFor(spec.scanner, spec.planner.seed));
  if (!options.out.empty()) writeSamples(options.out, samples, clusters);
  if (!options.cvm_dir.empty()) {
    // Each cluster's Combined Visibility Map, with the part standing on the working plane.
    std::error_code ec;
    std::filesystem::create_directories(options.cvm_dir, ec);
    if (ec) throw OutputError(options.cvm_dir, "cannot create the folder: " + ec.message());
    const SimulationOptions simulation =
        simulationOptionsFor(resolved, part, restingPlacement(part));
    const Simulator simulator(part, spec.scanner, simulation);
    std::vector<Sample> world = samples;
    for (Sample& s : world) {
      s.position = simulation.part_to_world * s.position;
      s.normal = simulation.part_to_world.linear() * s.normal;
    }
    const VisibilityOptions vo =
        plannerVisibility(spec.scanner, spec.planner.vm_step, spec.working_plane);
    for (std::size_t c = 0; c < clusters.size(); ++c) {
      report(progress, fmt::format("visibility map of cluster {} of {}", c + 1, clusters.size()),
             static_cast<double>(c) / static_cast<double>(clusters.size()));
      writePgm(
          combinedVisibilityMap(simulator, surfacePoints(world, clusters[c].samples), vo),
          (std::filesystem::path(options.cvm_dir) / fmt::format("cluster_{}.pgm", c)).string());
    }
  }
  clearProgress();

  std::map<std::string, int> by_task, by_role;
  std::map<int, int> by_face;
  for (const Sample& s : samples) {
    ++by_task[std::string(toString(s.task))];
    ++by_role[std::string(toString(s.role))];
    ++by_face[s.face];
  }
  fmt::print("part      {} ({} faces)\n", part.file, part.faces.size());
  fmt::print("samples   {}\n", samples.size());
  for (const auto& [task, count] : by_task) fmt::print("  task {:<9} {}\n", task, count);
  for (const auto& [role, count] : by_role) fmt::print("  role {:<9} {}\n", role, count);
  fmt::print("faces     {} sampled\n", by_face.size());
  std::vector<std::string> face_counts;
  for (const auto& [face, count] : by_face)
    face_counts.push_back(fmt::format("{}:{}", face, count));
  fmt::print("  {}\n", fmt::join(face_counts, " "));
  fmt::print("clusters  {}\n", clusters.size());
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    const Cluster& k = clusters[c];
    fmt::print(
        "  {:>4}: {:>5} samples at ({:.1f}, {:.1f}, {:.1f}) normal ({:.2f}, {:.2f}, {:.2f})\n", c,
        k.samples.size(), k.mean_position.x(), k.mean_position.y(), k.mean_position.z(),
        k.mean_normal.x(), k.mean_normal.y(), k.mean_normal.z());
  }
  if (!options.out.empty()) fmt::print("written   {}\n", options.out);
  return 0;
}

}  // namespace

void addSampleCommand(CLI::App& app, const GlobalOptions& global, Action& selected) {
  auto options = std::make_shared<Options>();
  CLI::App* command =
      app.add_subcommand("sample", "Sample the surfaces the spec's tasks target, and cluster them");
  command->add_option("part", options->part, "CAD or mesh file of the part")->required();
  command->add_option("--spec", options->spec, "Inspection spec (YAML); default: one global task")
      ->check(kNamedFile);
  command->add_option("-o,--out", options->out,
                      "Write the samples with their clusters (.ply or .json)");
  command->add_option(
      "--cvm", options->cvm_dir,
      "Write each cluster's Combined Visibility Map as a PGM image (azimuth across, "
      "elevation up) into this folder");
  command->callback([options, &global, &selected] {
    selected = [options, &global] { return run(*options, global); };
  });
}

}  // namespace scanplan::cli
