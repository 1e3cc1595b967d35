#include <scanplan/errors.h>
#include <scanplan/io/atomic_file.h>
#include <scanplan/io/plan_json.h>

#include <map>

namespace scanplan {
namespace {

using nlohmann::json;

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

json matrix(const Pose& pose) {
  json rows = json::array();
  const Eigen::Matrix4d m = pose.matrix();
  for (int r = 0; r < 4; ++r) rows.push_back(json::array({m(r, 0), m(r, 1), m(r, 2), m(r, 3)}));
  return rows;
}

}  // namespace

json planJson(const Plan& plan) {
  const Scanner& s = plan.scanner;
  json views = json::array(), sequence = json::array(), samples = json::array();
  for (const View& view : plan.views) {
    views.push_back({{"id", view.id},
                     {"camera_to_world", matrix(view.camera_to_world)},
                     {"target", vec(view.target)},
                     {"task", view.task},
                     {"registration", nullptr}});
    sequence.push_back(view.id);
  }
  std::map<std::string, std::size_t> reasons;
  for (const PlannedSample& p : plan.samples) {
    json entry = {{"position", vec(p.sample.position)},
                  {"normal", vec(p.sample.normal)},
                  {"face", p.sample.face},
                  {"role", toString(p.sample.role)},
                  {"task", toString(p.sample.task)},
                  {"measured_by", p.measured_by}};
    if (p.uncoverable != Uncoverable::None) {
      entry["not_coverable"] = toString(p.uncoverable);
      if (p.uncoverable == Uncoverable::Lost) entry["loss"] = toString(p.last_loss);
      ++reasons[std::string(toString(p.uncoverable))];
    }
    samples.push_back(entry);
  }
  json times = json::object();
  for (const StageTime& t : plan.times) times[t.stage] = t.seconds;
  json result = {
      {"format", "scanplan.plan"},
      {"version", 1},
      {"units", "mm"},
      {"part",
       {{"file", plan.part_file},
        {"faces", plan.part_faces},
        {"part_to_world", matrix(plan.part_to_world)}}},
      {"scanner",
       {{"name", s.name},
        {"standoff", s.standoff},
        {"depth_of_field", s.depth_of_field},
        {"fov_width", s.fov_width},
        {"fov_height", s.fov_height},
        {"triangulation_angle", s.triangulation_angle},
        {"max_camera_angle", s.max_camera_angle},
        {"max_projector_angle", s.max_projector_angle},
        {"reflection_cone", s.reflection_cone},
        {"point_spacing", s.point_spacing}}},
      {"views", views},
      {"sequence", sequence},
      {"samples", samples},
      {"summary",
       {{"samples", plan.samples.size()},
        {"measured", plan.measuredCount()},
        {"not_coverable", plan.notCoverableCount()},
        {"not_coverable_by_reason", reasons},
        {"views", plan.views.size()},
        {"registrable_views", nullptr},
        {"seconds", plan.seconds},
        {"stage_seconds", times}}},
  };
  if (plan.bound) {
    const PlanBound& b = *plan.bound;
    result["summary"]["bound"] = {
        {"candidates", b.candidates},
        {"ilp_views", b.ilp_views},
        {"lower_bound", b.lower_bound},
        {"optimal", b.optimal},
        {"views_over_ilp",
         b.ilp_views ? static_cast<double>(plan.views.size()) / static_cast<double>(b.ilp_views)
                     : 0.0},
        {"seconds", b.seconds}};
  }
  return result;
}

void writePlan(const Plan& plan, const std::string& path) {
  writeFileAtomically(path, [&](std::ostream& out) { out << planJson(plan).dump(1) << '\n'; });
}

}  // namespace scanplan
