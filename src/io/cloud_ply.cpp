#include <scanplan/io/cloud_ply.h>

namespace scanplan {

PlyData cloudPly(const PointCloud& cloud) {
  PlyElement vertex{"vertex", cloud.points.size(), {}};
  const char* axes[3] = {"x", "y", "z"};
  const char* normal_axes[3] = {"nx", "ny", "nz"};
  auto column = [&](auto value) {
    std::vector<double> values(cloud.points.size());
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = value(i);
    return values;
  };
  for (int k = 0; k < 3; ++k)
    vertex.add(axes[k], PlyType::Float32,
               column([&](std::size_t i) { return cloud.points[i][k]; }));
  for (int k = 0; k < 3; ++k)
    vertex.add(normal_axes[k], PlyType::Float32,
               column([&](std::size_t i) { return cloud.normals[i][k]; }));
  vertex.add("face", PlyType::Int32, column([&](std::size_t i) { return cloud.faces[i]; }));
  vertex.add("incidence", PlyType::Float32,
             column([&](std::size_t i) { return cloud.incidence[i]; }));
  return {{"scanplan simulated cloud, mm"}, {std::move(vertex)}};
}

void writePly(const PointCloud& cloud, const std::string& path) { writePly(cloudPly(cloud), path); }

PointCloud readCloudPly(const std::string& path) {
  const PlyData data = readPly(path);
  auto column = [&](const char* name) -> const std::vector<double>& {
    return plyColumn(data, "vertex", name, path);
  };
  const std::vector<double>&x = column("x"), &y = column("y"), &z = column("z");
  const std::vector<double>&nx = column("nx"), &ny = column("ny"), &nz = column("nz");
  const std::vector<double>&face = column("face"), &incidence = column("incidence");
  PointCloud cloud;
  for (std::size_t i = 0; i < x.size(); ++i) {
    cloud.points.emplace_back(x[i], y[i], z[i]);
    cloud.normals.emplace_back(nx[i], ny[i], nz[i]);
    cloud.faces.push_back(static_cast<int>(face[i]));
    cloud.incidence.push_back(static_cast<float>(incidence[i]));
  }
  return cloud;
}

}  // namespace scanplan
