// The HTML report: the page (web/src/report.html) with the viewer bundle (three.js and
// web/src/viewer.js) and the plan's data inlined (io/page.h).

#include "core/assets.h"
#include "io/page.h"

#include <scanplan/core/errors.h>
#include <scanplan/io/inspection_files.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/planning/evidence.h>
#include <scanplan/report/report.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string_view>

namespace scanplan {
namespace {

using nlohmann::json;

using detail::base64;
using detail::floats;
using detail::vec;

// Per face, the mean density of the points its samples get (points per mm², all the views
// measuring each sample together, pointQuality; an unmeasured sample counts 0).
std::map<int, double> faceDensities(const Plan& plan, const PlanScene& scene) {
  std::map<int, const View*> views;
  for (const SceneView& v : scene.views) views[v.view.id] = &v.view;
  std::map<int, std::pair<double, std::size_t>> sums;  // face: density sum, samples
  const Scanner& scanner = plan.scanner;
  for (const PlannedSample& s : plan.samples) {
    double density = 0;
    for (int id : s.measured_by) {
      const auto at = views.find(id);
      if (at == views.end()) continue;
      density += pointQuality(scanner, *at->second, s.sample.position, s.sample.normal).density;
    }
    sums[s.sample.face].first += density;
    ++sums[s.sample.face].second;
  }
  std::map<int, double> result;
  for (const auto& [face, sum] : sums) result[face] = sum.first / static_cast<double>(sum.second);
  return result;
}

json meshJson(const PlanScene& scene) {
  json mesh = detail::meshJson(scene.mesh);
  mesh["outlines"] = base64(floats(priorityOutlines(scene)));
  return mesh;
}

json facesJson(const Plan& plan, const PlanScene& scene, const Part& part,
               const std::vector<int>& fixture) {
  const std::map<int, double> densities = faceDensities(plan, scene);
  json faces = json::array();
  for (const FaceStatus& f : scene.faces) {
    const Face& face = part.faces[f.id - 1];
    const auto density = densities.find(f.id);
    // The share of its area measured, where the plan has it.
    const json area_share =
        static_cast<std::size_t>(f.id) <= plan.face_areas.size() &&
                plan.face_areas[f.id - 1].area > 0
            ? json(plan.face_areas[f.id - 1].measured / plan.face_areas[f.id - 1].area)
            : json(nullptr);
    faces.push_back(
        {{"id", f.id},
         {"type", toString(face.type)},
         {"name", face.name},
         {"area", face.area},
         {"samples", f.samples},
         {"measured", f.measured},
         {"not_coverable", f.not_coverable},
         {"coverage", toString(f.coverage)},
         {"priority", f.priority},
         {"fixture", std::binary_search(fixture.begin(), fixture.end(), f.id)},
         {"reason", f.reason == Uncoverable::None ? "" : toString(f.reason)},
         {"density", density == densities.end() ? json(nullptr) : json(density->second)},
         {"area_measured", area_share},
         {"loss", f.loss == Loss::Measured ? "" : toString(f.loss)}});
  }
  return faces;
}

json samplesJson(const Plan& plan) {
  std::vector<Vec3> positions;
  std::vector<std::uint8_t> state, task, role, reason;
  std::vector<std::int32_t> face;
  for (const PlannedSample& s : plan.samples) {
    positions.push_back(s.sample.position);
    state.push_back(static_cast<std::uint8_t>(sampleState(s)));
    task.push_back(static_cast<std::uint8_t>(s.sample.task));
    role.push_back(static_cast<std::uint8_t>(s.sample.role));
    reason.push_back(static_cast<std::uint8_t>(s.uncoverable));
    face.push_back(s.sample.face);
  }
  json tasks = json::array(), roles = json::array(), reasons = json::array();
  for (TaskType t : kTaskTypes) tasks.push_back(toString(t));
  for (Role r : {Role::Priority, Role::Normal, Role::Fixture}) roles.push_back(toString(r));
  for (Uncoverable u :
       {Uncoverable::None, Uncoverable::BelowWorkingPlane, Uncoverable::OccludedByPart,
        Uncoverable::NoValidPose, Uncoverable::Lost, Uncoverable::Unreachable})
    reasons.push_back(toString(u));
  return {{"count", plan.samples.size()},
          {"positions", base64(floats(positions))},
          {"state", base64(state)},
          {"task", base64(task)},
          {"role", base64(role)},
          {"reason", base64(reason)},
          {"face", base64(face)},
          {"tasks", tasks},
          {"roles", roles},
          {"reasons", reasons}};
}

json viewsJson(const PlanScene& scene, const Plan& plan, const std::vector<PointCloud>& clouds) {
  std::map<int, std::set<int>> faces_of_view;
  for (const PlannedSample& s : plan.samples)
    for (int id : s.measured_by) faces_of_view[id].insert(s.sample.face);
  json views = json::array();
  for (std::size_t i = 0; i < scene.views.size(); ++i) {
    const SceneView& v = scene.views[i];
    json corners = json::array();
    for (const Vec3& p : frustum(v.view, scene.scanner)) corners.push_back(vec(p));
    json matrix = json::array();
    for (int r = 0; r < 4; ++r)
      matrix.push_back({v.view.camera_to_world(r, 0), v.view.camera_to_world(r, 1),
                        v.view.camera_to_world(r, 2), v.view.camera_to_world(r, 3)});
    json entry = {{"id", v.view.id},
                  {"order", v.order},
                  {"state", toString(v.state)},
                  {"orientation", v.orientation},
                  {"task", v.view.task},
                  {"target", vec(v.view.target)},
                  {"frustum", corners},
                  {"camera_to_world", matrix},
                  {"measured", v.measured},
                  {"faces", faces_of_view[v.view.id]}};
    if (plan.registration && i < plan.registration->views.size()) {
      const ViewRegistration& r = plan.registration->views[i];
      entry["registration"] = {{"method", toString(r.method)}, {"to", r.to}};
    }
    if (i < clouds.size() && !clouds[i].points.empty()) {
      std::vector<std::uint8_t> incidence;
      for (float a : clouds[i].incidence)
        incidence.push_back(static_cast<std::uint8_t>(std::clamp(std::lround(a), 0L, 90L)));
      entry["cloud"] = {{"points", clouds[i].points.size()},
                        {"positions", base64(floats(clouds[i].points))},
                        {"incidence", base64(incidence)}};
    }
    views.push_back(entry);
  }
  return views;
}

// The clusters (planning/evidence.h) as the page draws them: each map scaled to 0..255.
json clustersJson(const std::vector<ClusterMap>& clusters) {
  json list = json::array();
  for (const ClusterMap& cluster : clusters) {
    const VisibilityMap& map = cluster.map;
    std::vector<std::uint8_t> cells(map.counts.size());
    const double top = std::max<std::uint32_t>(map.max(), 1);
    for (std::size_t i = 0; i < cells.size(); ++i)
      cells[i] = static_cast<std::uint8_t>(std::lround(255.0 * map.counts[i] / top));
    const std::vector<std::uint32_t> indices(cluster.members.begin(), cluster.members.end());
    list.push_back({{"id", cluster.id},
                    {"samples", cluster.members.size()},
                    {"position", vec(cluster.position)},
                    {"normal", vec(cluster.normal)},
                    {"members", base64(indices)},
                    {"azimuths", map.azimuths},
                    {"elevations", map.elevations},
                    {"step", map.step},
                    {"max", map.max()},
                    {"cvm", base64(cells)}});
  }
  return list;
}

}  // namespace

void writeReport(const Plan& plan, const Part& part, const Spec& spec, const std::string& path,
                 const ReportOptions& options, const Progress& progress) {
  writeReport(plan, part, resolveSpec(part, spec), path, options, progress);
}

void writeReport(const Plan& plan, const Part& part, const ResolvedSpec& resolved,
                 const std::string& path, const ReportOptions& options, const Progress& progress) {
  writeReport(plan, part, resolved, reportEvidence(plan, part, resolved, options, progress), path);
}

void writeReport(const Plan& plan, const Part& part, const ResolvedSpec& resolved,
                 const ReportEvidence& evidence, const std::string& path) {
  const Spec& spec = resolved.spec;
  const PlanScene scene = planScene(plan, part, resolved);
  Box part_box;
  for (const Vec3& v : scene.mesh.vertices) part_box.add(v);
  json plan_json = planJson(plan);
  plan_json.erase("samples");
  json data = {{"title", std::filesystem::path(plan.part_file).filename().string()},
               {"plan", plan_json},
               {"mesh", meshJson(scene)},
               {"faces", facesJson(plan, scene, part, resolved.targets.fixture)},
               {"fixtures", detail::meshJson(scene.fixtures)},
               {"samples", samplesJson(plan)},
               {"views", viewsJson(scene, plan, evidence.clouds)},
               {"path", scene.path},
               {"markers", base64(floats(scene.markers))},
               {"proposed_markers", base64(floats(scene.proposed_markers))},
               {"header", detail::headerJson(plan.part_file, spec.source)},
               {"working_plane", spec.working_plane},
               {"bounds", {{"min", vec(scene.bounds.min)}, {"max", vec(scene.bounds.max)}}},
               {"part_bounds", {{"min", vec(part_box.min)}, {"max", vec(part_box.max)}}},
               {"clusters", clustersJson(evidence.clusters)}};
  json palette = json::object();
  for (FaceCoverage c : {FaceCoverage::NotTarget, FaceCoverage::Measured, FaceCoverage::Partly,
                         FaceCoverage::NotMeasured})
    palette[std::string(toString(c))] = colour(c);
  for (ViewState s :
       {ViewState::Registered, ViewState::Bridge, ViewState::Unregistrable, ViewState::Unchecked})
    palette[std::string(toString(s))] = colour(s);
  palette["fixture"] = kFixtureColour;
  palette["path"] = kPathColour;
  palette["markers"] = kMarkerColour;
  palette["proposed markers"] = kProposedMarkerColour;
  data["palette"] = palette;
  if (evidence.inspection) data["inspection"] = inspectionJson(*evidence.inspection, plan);

  detail::writePage(assets::report_html, assets::viewer_js, data, path);
}

}  // namespace scanplan
