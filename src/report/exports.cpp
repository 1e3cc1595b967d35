// Point exports of a plan: its samples with their coverage, and the simulated clouds of
// its views, as PLY that MeshLab and CloudCompare colour by the red, green, blue columns.

#include <scanplan/core/atomic_file.h>
#include <scanplan/io/cloud_ply.h>
#include <scanplan/planning/evidence.h>
#include <scanplan/report/exports.h>

#include <fmt/format.h>

#include <algorithm>

namespace scanplan {
namespace {

// Fills the red, green, blue columns of `element` from one colour per item.
void addColours(PlyElement& element, const std::vector<Rgb>& colours) {
  const char* names[3] = {"red", "green", "blue"};
  for (int k = 0; k < 3; ++k) {
    std::vector<double> values(colours.size());
    for (std::size_t i = 0; i < colours.size(); ++i) values[i] = colours[i][k];
    element.add(names[k], PlyType::UInt8, std::move(values));
  }
}

template <typename Get>
std::vector<double> column(std::size_t n, Get get) {
  std::vector<double> values(n);
  for (std::size_t i = 0; i < n; ++i) values[i] = static_cast<double>(get(i));
  return values;
}

// Incidence colours: blue at normal incidence through green to red at 90 degrees.
Rgb incidenceColour(double degrees) {
  const double t = std::clamp(degrees / 90.0, 0.0, 1.0);
  const double r = std::clamp(2 * t, 0.0, 1.0), b = std::clamp(2 - 2 * t, 0.0, 1.0);
  const double g = 1 - std::abs(2 * t - 1);
  return {static_cast<std::uint8_t>(255 * r), static_cast<std::uint8_t>(200 * g),
          static_cast<std::uint8_t>(255 * b)};
}

// The frame as the files' comments say it.
std::string frameText(Frame frame) {
  return frame == Frame::Cad ? "the part's CAD frame"
                             : "world frame of the plan's first setup (the cell's)";
}

}  // namespace

PlyData samplesPly(const Plan& plan, Frame frame) {
  const std::vector<PlannedSample>& samples = plan.samples;
  const std::size_t n = samples.size();
  const Pose to = sceneTo(plan, frame);
  std::vector<Vec3> positions(n), normals(n);
  for (std::size_t i = 0; i < n; ++i) {
    positions[i] = to * samples[i].sample.position;
    normals[i] = to.linear() * samples[i].sample.normal;
  }
  PlyElement vertex{"vertex", n, {}};
  const char* axes[3] = {"x", "y", "z"};
  const char* normal_axes[3] = {"nx", "ny", "nz"};
  for (int k = 0; k < 3; ++k)
    vertex.add(axes[k], PlyType::Float64,
               column(n, [&](std::size_t i) { return positions[i][k]; }));
  for (int k = 0; k < 3; ++k)
    vertex.add(normal_axes[k], PlyType::Float32,
               column(n, [&](std::size_t i) { return normals[i][k]; }));
  vertex.add("scalar_face", PlyType::Int32,
             column(n, [&](std::size_t i) { return samples[i].sample.face; }));
  vertex.add("scalar_task", PlyType::UInt8,
             column(n, [&](std::size_t i) { return static_cast<int>(samples[i].sample.task); }));
  vertex.add("scalar_role", PlyType::UInt8,
             column(n, [&](std::size_t i) { return static_cast<int>(samples[i].sample.role); }));
  auto views = [&](std::size_t i) { return samples[i].measured_by.size(); };
  vertex.add("scalar_views", PlyType::UInt16, column(n, views));
  auto state = [&](std::size_t i) { return sampleState(samples[i]); };
  vertex.add("scalar_state", PlyType::UInt8, column(n, state));
  vertex.add("scalar_reason", PlyType::UInt8,
             column(n, [&](std::size_t i) { return static_cast<int>(samples[i].uncoverable); }));
  vertex.add("quality", PlyType::Float32, column(n, views));
  std::vector<Rgb> colours(n);
  for (std::size_t i = 0; i < n; ++i)
    colours[i] = colour(state(i) == 0   ? FaceCoverage::Measured
                        : state(i) == 1 ? FaceCoverage::Partly
                                        : FaceCoverage::NotMeasured);
  addColours(vertex, colours);
  return {{fmt::format("scanplan samples, mm, {}", frameText(frame)),
           "task: 0 gdt, 1 trim, 2 surface, 3 global, 4 points; role: 0 priority, 1 normal, "
           "2 fixture; quality: views",
           "state: 0 measured, 1 not measured, 2 not coverable; reason: 0 none, 1 below the "
           "working plane, 2 occluded by the part, 3 no valid pose, 4 lost"},
          {std::move(vertex)}};
}

void writeCloudsPly(const Plan& plan, const Part& part, const Spec& spec, double spacing,
                    Frame frame, const std::string& path, const Progress& progress) {
  const ResolvedSpec resolved = resolveSpec(part, spec);
  const Pose to = sceneTo(plan, frame);
  writeFileAtomically(path, [&](std::ostream& out) {
    // The point count is known at the end: written into a fixed-width field then.
    out << "ply\nformat binary_little_endian 1.0\n"
        << "comment scanplan simulated clouds of every view, mm, " << frameText(frame) << "\n"
        << "comment scalar_view: view id; quality: incidence; colour by incidence (blue 0, red "
           "90 degrees)\n"
        << "element vertex ";
    const std::streampos count_at = out.tellp();
    out << "000000000000\n"
        << "property float x\nproperty float y\nproperty float z\n"
        << "property float nx\nproperty float ny\nproperty float nz\n"
        << "property int scalar_face\nproperty float scalar_incidence\nproperty int scalar_view\n"
        << "property float quality\nproperty uchar red\nproperty uchar green\nproperty uchar "
           "blue\nend_header\n";
    std::size_t count = 0;
    forEachViewCloud(plan, part, resolved, spacing, progress, [&](std::size_t v, PointCloud&& c) {
      const std::int32_t view = plan.views[v].id;
      std::string buffer;
      auto put = [&](const auto& value) {
        buffer.append(reinterpret_cast<const char*>(&value), sizeof value);
      };
      for (std::size_t i = 0; i < c.points.size(); ++i) {
        const Vec3 p = to * c.points[i], normal = to.linear() * c.normals[i];
        for (int k = 0; k < 3; ++k) put(static_cast<float>(p[k]));
        for (int k = 0; k < 3; ++k) put(static_cast<float>(normal[k]));
        put(static_cast<std::int32_t>(c.faces[i]));
        put(c.incidence[i]);
        put(view);
        put(c.incidence[i]);
        put(incidenceColour(c.incidence[i]));
      }
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      count += c.points.size();
    });
    out.seekp(count_at);
    out << fmt::format("{:012d}", count);
  });
}

}  // namespace scanplan
