// The Python module `scanplan` (pybind11, docs/python.md): read a part, make or read a
// spec, plan, simulate, verify, inspect, and write the plan, its report and its robot
// programs. Points, normals and poses come as numpy arrays; errors as exceptions of the
// exit codes' classes; the work runs with the GIL released and reports progress to an
// optional callback.

#include "arrays.h"
#include "errors.h"
#include "study.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/core/version.h>
#include <scanplan/io/inspection_files.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning.h>
#include <scanplan/planning/inspection.h>
#include <scanplan/report/report.h>
#include <scanplan/robot/motion.h>
#include <scanplan/robot/program.h>
#include <scanplan/scanner/simulation.h>
#include <scanplan/spec/spec.h>

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <exception>
#include <filesystem>

namespace py = pybind11;
using namespace py::literals;

namespace scanplan::python {
namespace {

// A Python progress callback called from the library's threads: each call takes the GIL
// (which also guards `error_`); an exception it raises ends the calls and is raised again
// once the work is done.
class Callback {
 public:
  explicit Callback(py::object function) : function_(std::move(function)) {}

  Progress progress() {
    if (function_.is_none()) return {};
    return [this](std::string_view stage, double fraction) {
      py::gil_scoped_acquire gil;
      if (error_) return;
      try {
        function_(std::string(stage), fraction);
      } catch (py::error_already_set&) {
        error_ = std::current_exception();
      }
    };
  }

  void raiseIfFailed() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  py::object function_;
  std::exception_ptr error_;
};

// `value` as JSON text, which is YAML too.
std::string jsonText(const py::object& value) {
  return py::module_::import("json").attr("dumps")(value).cast<std::string>();
}

// A spec from None (the default), a dict shaped as the YAML file, or a Spec.
Spec specOf(const py::object& spec) {
  if (spec.is_none()) return defaultSpec();
  if (py::isinstance<py::dict>(spec)) return specFromText(jsonText(spec), "<dict>");
  if (!py::isinstance<Spec>(spec))
    throw py::type_error("spec: expected a scanplan.Spec, a dict or None, not " +
                         py::str(py::type::of(spec).attr("__name__")).cast<std::string>());
  return spec.cast<Spec>();
}

// The spec of a call on `plan`: as specOf, but None is the spec the plan was made with.
Spec specOf(const py::object& spec, const Plan& plan) {
  return spec.is_none() ? planSpec(plan, "<plan>") : specOf(spec);
}

py::object toPython(const nlohmann::json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

Part readPart(const std::string& path, bool read_gdt, const py::object& progress) {
  Callback callback(progress);
  ImportOptions options;
  options.read_gdt = read_gdt;
  Part part;
  {
    py::gil_scoped_release release;
    part = importPart(path, options, callback.progress());
  }
  callback.raiseIfFailed();
  return part;
}

Plan plan(const Part& part, const py::object& spec, bool registration, const py::object& progress) {
  const Spec resolved = specOf(spec);
  Callback callback(progress);
  PlanningOptions options;
  options.registration = registration;
  Plan result;
  {
    py::gil_scoped_release release;
    result = planViews(part, resolved, options, callback.progress());
  }
  callback.raiseIfFailed();
  return result;
}

// The clouds the views of `plan` record, each in its rest orientation's placement (or the
// views `views`, (n, 4, 4) camera-to-world matrices, with the plan's first placement),
// with the plan's scanner unless `spec` is given: per view a dict of numpy arrays.
py::list simulate(const Part& part, const Plan& plan, const py::object& spec,
                  const py::object& views, std::uint64_t seed) {
  Spec resolved = specOf(spec, plan);
  if (spec.is_none()) resolved.scanner = plan.scanner;
  const bool own = views.is_none();
  const std::vector<View> simulated =
      own ? plan.views : viewsFrom(views, resolved.scanner.standoff);
  const std::vector<std::size_t> orientation =
      own ? viewOrientations(plan) : std::vector<std::size_t>(simulated.size(), 0);
  std::vector<PointCloud> clouds(simulated.size());
  {
    py::gil_scoped_release release;
    const ResolvedSpec placed = resolveSpec(part, resolved);
    for (std::size_t k = 0; k < std::max<std::size_t>(1, plan.orientations.size()); ++k) {
      const Simulator simulator(part, resolved.scanner,
                                simulationOptionsFor(placed, part, orientationPlacement(plan, k)));
      for (std::size_t v = 0; v < simulated.size(); ++v)
        if (orientation[v] == k) clouds[v] = simulator.cloud(simulated[v], seed);
    }
  }
  py::list result;
  for (std::size_t v = 0; v < simulated.size(); ++v)
    result.append(py::dict("id"_a = simulated[v].id, "points"_a = rows(clouds[v].points),
                           "normals"_a = rows(clouds[v].normals),
                           "faces"_a = py::array(py::cast(clouds[v].faces)),
                           "incidence"_a = py::array(py::cast(clouds[v].incidence))));
  return result;
}

py::dict verify(const Plan& plan, const Part& part, const py::object& spec,
                const py::object& progress) {
  const Spec resolved = specOf(spec, plan);
  Callback callback(progress);
  PlanCheck check;
  {
    py::gil_scoped_release release;
    check = verifyPlan(plan, part, resolved, {}, callback.progress());
  }
  callback.raiseIfFailed();
  return py::dict("holds"_a = check.holds(), "coverage_differences"_a = check.coverage_differences,
                  "registration_differences"_a = check.registration_differences,
                  "sequence_missing"_a = check.sequence_missing,
                  "sequence_breaks"_a = check.sequence_breaks,
                  "unregistered"_a = check.unregistered,
                  "registration_required"_a = check.registration_required);
}

// The deviations of the simulated part: None, a deviations file's path, or its list of
// dicts ({"faces": [ids], "offset": mm}, ...).
std::vector<Deviation> deviationsOf(const py::object& deviations) {
  if (deviations.is_none()) return {};
  if (py::isinstance<py::str>(deviations)) return loadDeviations(deviations.cast<std::string>());
  return deviationsFromText(jsonText(py::dict("deviations"_a = deviations)), "<deviations>");
}

// A virtual inspection of the plan: inspection.json as Python objects.
py::object inspect(const Plan& plan, const Part& part, const py::object& spec,
                   const std::optional<int>& runs, double precision, double spacing,
                   const std::string& icp, const py::object& deviations, std::uint64_t seed,
                   const py::object& progress) {
  const Spec resolved = specOf(spec, plan);
  InspectionOptions options;
  options.runs = runs.value_or(precision > 0 ? kMostPreciseRuns : options.runs);
  options.precision = precision;
  options.spacing = spacing;
  options.seed = seed;
  if (icp != "drawn" && icp != "registered")
    throw UsageError("icp", "'" + icp + "': expected drawn or registered");
  options.icp = icp == "registered" ? InspectionOptions::IcpLinks::Registered
                                    : InspectionOptions::IcpLinks::Drawn;
  options.deviations = deviationsOf(deviations);
  Callback callback(progress);
  Inspection result;
  {
    py::gil_scoped_release release;
    result = inspectPlan(part, resolveSpec(part, resolved), plan, options, callback.progress());
  }
  callback.raiseIfFailed();
  return toPython(inspectionJson(result, plan));
}

// Writes the plan's robot program (export's formats: krl, rapid, fanuc, urscript, json) and
// says what it holds.
py::dict writeProgramFile(const Plan& plan, const Part& part, const std::string& path,
                          const std::string& format, const py::object& spec, std::size_t setup,
                          bool allow_collisions) {
  checkProgramLanguage(format);
  const Spec resolved = specOf(spec, plan);
  RobotProgram program;
  {
    py::gil_scoped_release release;
    const ProgramRequest request{std::filesystem::path(path).stem().string(), setup,
                                 "plan of " + plan.part_file, "setup"};
    program = planProgram(plan, part, resolveSpec(part, resolved), request);
    checkClearMoves(program, allow_collisions, path);
    writeRobotProgram(program, format, path);
  }
  std::vector<int> views;
  for (const ProgramStep& step : program.steps) views.push_back(step.view);
  std::vector<std::string> uncleared;
  for (const RobotMove& move : program.uncleared) uncleared.push_back(toString(move));
  return py::dict("views"_a = views, "unreached"_a = program.unreached, "uncleared"_a = uncleared,
                  "seconds"_a = programSeconds(program));
}

void writeReportFile(const Plan& plan, const Part& part, const std::string& path,
                     const py::object& spec, const py::object& progress) {
  const Spec resolved = specOf(spec, plan);
  Callback callback(progress);
  {
    py::gil_scoped_release release;
    checkPlanPart(plan, part);
    writeReport(plan, part, resolved, path, {}, callback.progress());
  }
  callback.raiseIfFailed();
}

py::list tolerances(const Part& part) {
  py::list result;
  for (const GeometricTolerance& t : part.gdt.tolerances)
    result.append(py::dict("type"_a = t.type, "value"_a = t.value, "datums"_a = t.datums,
                           "faces"_a = t.faces));
  return result;
}

py::list dimensions(const Part& part) {
  py::list result;
  for (const Dimension& d : part.gdt.dimensions)
    result.append(py::dict("type"_a = d.type, "value"_a = d.value, "lower"_a = d.lower,
                           "upper"_a = d.upper, "faces"_a = d.faces));
  return result;
}

void bindPart(py::module_& m) {
  py::class_<Part>(m, "Part", "A part read from a CAD or mesh file, in millimetres")
      .def_readonly("file", &Part::file)
      .def_readonly("format", &Part::format)
      .def_property_readonly("face_count", [](const Part& p) { return p.faces.size(); })
      .def_property_readonly("area", &Part::area)
      .def_property_readonly("volume", &Part::volume)
      .def_property_readonly("bounds",
                             [](const Part& p) {
                               const Box box = p.bounds();
                               return rows(std::vector<Vec3>{box.min, box.max});
                             })
      .def_property_readonly("vertices", &meshVertices, "(n, 3) float64, a view of the mesh")
      .def_property_readonly("triangles", &meshTriangles, "(n, 3) int32, a view of the mesh")
      .def_property_readonly("triangle_faces", &meshTriangleFaces,
                             "(n,) int32 face id per triangle, a view of the mesh")
      .def_property_readonly("tolerances", &tolerances)
      .def_property_readonly("dimensions", &dimensions)
      .def("__repr__", [](const Part& p) {
        return "<scanplan.Part " + p.file + ": " + std::to_string(p.faces.size()) + " faces>";
      });
}

void bindSpec(py::module_& m) {
  py::class_<Spec>(m, "Spec", "An inspection spec (docs/design.md, the spec)")
      .def_readonly("source", &Spec::source)
      .def_property_readonly("scanner", [](const Spec& s) { return s.scanner.name; })
      .def_property_readonly("tasks",
                             [](const Spec& s) {
                               std::vector<std::string> tasks;
                               for (const Task& t : s.tasks) tasks.emplace_back(toString(t.type));
                               return tasks;
                             })
      .def("__repr__", [](const Spec& s) {
        return "<scanplan.Spec " + (s.source.empty() ? std::string("default") : s.source) + ">";
      });
}

void bindPlan(py::module_& m) {
  py::class_<Plan>(m, "Plan", "A plan: views, samples and what measures them")
      .def_property_readonly("views", &viewPoses, "(n, 4, 4) camera-to-world matrices, mm")
      .def_property_readonly("view_ids", &viewIds)
      .def_property_readonly("targets", &viewTargets, "(n, 3) points the views aim at, mm")
      .def_property_readonly("samples", &samplePositions, "(m, 3) sample positions, world, mm")
      .def_property_readonly("normals", &sampleNormals, "(m, 3) sample normals")
      .def_property_readonly("sample_faces", &sampleFaces, "(m,) face id per sample")
      .def_property_readonly("measured", &sampleMeasured, "(m,) bool: a view measures it")
      .def_property_readonly(
          "sequence",
          [](const Plan& p) { return p.sequence ? py::cast(p.sequence->views) : py::none(); })
      .def_property_readonly("measured_share",
                             [](const Plan& p) {
                               return p.samples.empty() ? 0.0
                                                        : static_cast<double>(p.measuredCount()) /
                                                              static_cast<double>(p.samples.size());
                             })
      .def_readonly("seconds", &Plan::seconds)
      .def(
          "to_json", [](const Plan& p) { return toPython(planJson(p)); },
          "The plan as plan.json holds it, as Python objects")
      .def("__repr__", [](const Plan& p) {
        return "<scanplan.Plan " + std::to_string(p.views.size()) + " views, " +
               std::to_string(p.measuredCount()) + " of " + std::to_string(p.samples.size()) +
               " samples measured>";
      });
}

void bindFunctions(py::module_& m) {
  m.def("import_part", &readPart, "path"_a, "read_gdt"_a = true, "progress"_a = py::none(),
        "Reads a STEP, IGES, BREP or mesh file (STL, OBJ, PLY, OFF)");
  m.def("default_spec", &defaultSpec, "The generic structured-light scanner, one global task");
  m.def("load_spec", &loadSpec, "path"_a, "Reads a spec file (YAML)");
  m.def(
      "spec_from_dict", [](const py::dict& d) { return specOf(d); }, "spec"_a,
      "A spec from a dict shaped as the YAML file; its files are relative to the current folder");
  m.def("plan", &plan, "part"_a, "spec"_a = py::none(), "registration"_a = true,
        "progress"_a = py::none(),
        "Plans the views for `part` (spec: a Spec, a dict, or None for the default); "
        "progress(stage, fraction) is called as it goes");
  m.def("simulate", &simulate, "part"_a, "plan"_a, "spec"_a = py::none(), "views"_a = py::none(),
        "seed"_a = 1, "The clouds the plan's views (or `views`, (n, 4, 4)) record");
  m.def("verify", &verify, "plan"_a, "part"_a, "spec"_a = py::none(), "progress"_a = py::none(),
        "Checks the plan again on its part: coverage, registration and sequence");
  m.def(
      "write_plan", [](Plan& p, const std::string& path) { writePlanFiles(p, path); }, "plan"_a,
      "path"_a, "Writes plan.json with the surface patches beside it");
  m.def("read_plan", &readPlan, "path"_a, "Reads a plan.json");
  m.def("write_report", &writeReportFile, "plan"_a, "part"_a, "path"_a, "spec"_a = py::none(),
        "progress"_a = py::none(), "Writes the 3D HTML report of the plan");
  m.def("inspect", &inspect, "plan"_a, "part"_a, "spec"_a = py::none(), "runs"_a = py::none(),
        "precision"_a = 0.0, "spacing"_a = 0.0, "icp"_a = "drawn", "deviations"_a = py::none(),
        "seed"_a = 1, "progress"_a = py::none(),
        "Inspects the plan virtually: each characteristic over Monte Carlo runs of its scans "
        "(inspection.json as a dict)");
  m.def("write_program", &writeProgramFile, "plan"_a, "part"_a, "path"_a, "format"_a,
        "spec"_a = py::none(), "setup"_a = 0, "allow_collisions"_a = false,
        "Writes the plan's robot program (krl, rapid, fanuc, urscript or json) in the cell it "
        "was planned in, or another spec's; setup: 1 to N for a plan over several rest "
        "orientations");
  m.def("scanner_presets", &scannerPresetNames, "The scanner presets' names");
}

}  // namespace
}  // namespace scanplan::python

PYBIND11_MODULE(scanplan, m) {
  using namespace scanplan::python;
  m.doc() = "scanplan: view planning for robotic 3D scanning inspection";
  m.attr("__version__") = std::string(scanplan::version());
  bindErrors(m);
  bindPart(m);
  bindSpec(m);
  bindPlan(m);
  bindFunctions(m);
  bindStudy(m);
}
