// scanplan simulate: what each given view measures on the part.

#include "commands.h"
#include "files.h"
#include "terminal.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/cloud_ply.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/io/views_json.h>
#include <scanplan/planning.h>
#include <scanplan/scanner/simulation.h>
#include <scanplan/spec/spec.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <memory>

namespace scanplan::cli {
namespace {

using nlohmann::json;

struct Options {
  std::string part;
  std::string views;
  std::string spec;
  std::string scanner;
  std::string cloud_dir;
  bool json = false;
  bool no_working_plane = false;
  std::uint64_t seed = 1;
};

// What the simulator acquires from `view`: its measured area, faces and losses, and, with
// a cloud folder, its simulated cloud written there as view_ID.ply.
json simulatedView(const Simulator& simulator, const View& view, const Options& options) {
  Acquisition acquisition = simulator.acquire(view);
  json faces = json::array();
  for (std::size_t f = 0; f < acquisition.face_area.size(); ++f)
    if (acquisition.face_area[f] > 0)
      faces.push_back({{"id", f + 1}, {"area", acquisition.face_area[f]}});
  json losses = json::object();
  for (int k = 1; k < kLossKinds; ++k)
    losses[std::string(toString(static_cast<Loss>(k)))] = acquisition.counts[k];
  json entry = {{"id", view.id},
                {"measured_area", acquisition.measured_area},
                {"measured_facets", acquisition.counts[0]},
                {"facets", acquisition.facets.size()},
                {"faces", faces},
                {"losses", losses},
                {"rays", acquisition.rays}};
  if (!options.cloud_dir.empty()) {
    PointCloud cloud = simulator.cloud(view, options.seed);
    std::string file =
        (std::filesystem::path(options.cloud_dir) / fmt::format("view_{}.ply", view.id)).string();
    writePly(cloud, file);
    entry["cloud"] = file;
    entry["points"] = cloud.points.size();
  }
  return entry;
}

// The simulated views as text: per view its measured area and faces, its facets by loss,
// its cloud.
void printViews(const json& out, const Part& part, const Scanner& scanner) {
  fmt::print("part     {} ({} facets)\nscanner  {}\n", part.file, part.mesh.triangles.size(),
             printable(scanner.name));
  for (const json& entry : out["views"]) {
    std::vector<int> ids;
    for (const json& face : entry["faces"]) ids.push_back(face["id"].get<int>());
    fmt::print("view {}: {:.1f} mm² measured on {} faces{}\n", entry["id"].get<int>(),
               entry["measured_area"].get<double>(), ids.size(),
               ids.empty() ? "" : fmt::format(" ({})", fmt::join(ids, ", ")));
    std::string counts =
        fmt::format("  facets: {} measured", entry["measured_facets"].get<std::size_t>());
    for (const auto& [reason, count] : entry["losses"].items())
      if (count.get<std::size_t>() > 0)
        counts += fmt::format(", {} {}", count.get<std::size_t>(), reason);
    fmt::print("{}\n", counts);
    if (entry.contains("cloud"))
      fmt::print("  cloud: {} points -> {}\n", entry["points"].get<std::size_t>(),
                 entry["cloud"].get<std::string>());
  }
}

// The views to simulate, each with where the part stands for it, the scanner and the spec:
// of a plan, each view in its setup's placement (a plan over several rest orientations turns
// the part between setups), and unless --spec is given the plan's scanner and the spec it was
// made with, as the Python module's simulate; else the file's placement, the spec (--spec or
// the default) and its scanner. --scanner overrides either.
struct Simulated {
  std::vector<View> views;
  std::vector<Pose> placed;  // per view: part_to_world
  Scanner scanner;
  Spec spec;
};
Simulated toSimulate(const Options& options) {
  const ViewsFile file = readViews(options.views);
  Simulated s{file.views, std::vector<Pose>(file.views.size(), file.part_to_world), {}, {}};
  if (file.plan) {
    const Plan plan = readPlan(options.views);
    const std::vector<std::size_t> setup = viewOrientations(plan);
    for (std::size_t v = 0; v < s.views.size(); ++v)
      s.placed[v] = orientationPlacement(plan, setup[v]);
    s.spec = specFor(options.spec, plan, options.views);
    s.scanner = options.spec.empty() ? plan.scanner : s.spec.scanner;
  } else {
    s.spec = options.spec.empty() ? defaultSpec() : loadSpec(options.spec);
    s.scanner = s.spec.scanner;
  }
  if (!options.scanner.empty()) s.scanner = scannerNamed(options.scanner);
  return s;
}

int run(const Options& options, const GlobalOptions& global) {
  Progress progress = terminalProgress(global);
  const Simulated views = toSimulate(options);
  const Spec& spec = views.spec;
  Part part = importWithWarnings(options.part, {}, progress);

  const ResolvedSpec resolved = resolveSpec(part, spec);
  printWarnings("", resolved.warnings);
  // A simulator per placement of the part, made when a view first needs it.
  std::vector<std::pair<Pose, std::unique_ptr<Simulator>>> simulators;
  auto simulatorFor = [&](const Pose& placed) -> const Simulator& {
    for (const auto& [pose, simulator] : simulators)
      if (pose.matrix() == placed.matrix()) return *simulator;
    report(progress, "building ray-casting scene", 0);
    SimulationOptions simulation = simulationOptionsFor(resolved, part, placed);
    simulation.working_plane = simulation.working_plane && !options.no_working_plane;
    simulators.emplace_back(placed, std::make_unique<Simulator>(part, views.scanner, simulation));
    return *simulators.back().second;
  };

  if (!options.cloud_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.cloud_dir, ec);
    if (ec) throw OutputError(options.cloud_dir, "cannot create the folder: " + ec.message());
  }

  json out = {{"part", part.file}, {"scanner", views.scanner.name}, {"views", json::array()}};
  for (std::size_t v = 0; v < views.views.size(); ++v) {
    report(progress, fmt::format("simulating view {} of {}", v + 1, views.views.size()),
           static_cast<double>(v) / static_cast<double>(views.views.size()));
    out["views"].push_back(simulatedView(simulatorFor(views.placed[v]), views.views[v], options));
  }
  clearProgress();

  if (options.json)
    std::cout << out.dump(2) << '\n';
  else
    printViews(out, part, views.scanner);
  return 0;
}

}  // namespace

void addSimulateCommand(CLI::App& app, const GlobalOptions& global, Action& selected) {
  auto options = std::make_shared<Options>();
  CLI::App* command =
      app.add_subcommand("simulate", "Simulate what each view measures on the part");
  command->add_option("part", options->part, "CAD or mesh file of the part")->required();
  command->add_option("--views", options->views, "Views as JSON: a plan.json or its views array")
      ->required();
  command
      ->add_option(
          "--spec", options->spec,
          "Inspection spec (YAML): scanner, specular faces, markers (a plan's own without it)")
      ->check(kNamedFile);
  command->add_option("--scanner", options->scanner,
                      "Scanner preset or scanner file (YAML), overriding the spec's");
  command->add_option("-o,--cloud", options->cloud_dir,
                      "Write each view's simulated cloud as PLY into this folder");
  command->add_option("--seed", options->seed, "Seed of the simulated noise");
  command->add_flag("--no-working-plane", options->no_working_plane,
                    "The plane z = 0 does not occlude");
  command->add_flag("--json", options->json, "Print the results as one JSON object");
  command->callback([options, &global, &selected] {
    selected = [options, &global] { return run(*options, global); };
  });
}

}  // namespace scanplan::cli
