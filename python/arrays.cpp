#include "arrays.h"

#include <scanplan/core/errors.h>

#include <cmath>

namespace scanplan::python {

using namespace py::literals;

namespace {

// A read-only array over `data` (shape and strides in bytes), owned by `owner`.
template <typename T>
py::array view(const T* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides,
               const py::object& owner) {
  py::array_t<T> array(std::move(shape), std::move(strides), data, owner);
  array.attr("setflags")("write"_a = false);
  return array;
}

py::ssize_t count(std::size_t n) { return static_cast<py::ssize_t>(n); }

template <typename T, typename Get>
py::array_t<T> column(std::size_t n, Get get) {
  py::array_t<T> array(static_cast<py::ssize_t>(n));
  auto out = array.template mutable_unchecked<1>();
  for (std::size_t i = 0; i < n; ++i) out(static_cast<py::ssize_t>(i)) = get(i);
  return array;
}

}  // namespace

py::array_t<double> rows(const std::vector<Vec3>& points) {
  py::array_t<double> array({points.size(), std::size_t{3}});
  auto out = array.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int c = 0; c < 3; ++c) out(static_cast<py::ssize_t>(i), c) = points[i][c];
  return array;
}

py::array meshVertices(const py::object& self) {
  const TriangleMesh& mesh = self.cast<const Part&>().mesh;
  return view(mesh.vertices.data()->data(), {count(mesh.vertices.size()), 3},
              {sizeof(Vec3), sizeof(double)}, self);
}

py::array meshTriangles(const py::object& self) {
  const TriangleMesh& mesh = self.cast<const Part&>().mesh;
  return view(mesh.triangles.data()->data(), {count(mesh.triangles.size()), 3},
              {sizeof(Vec3i), sizeof(int)}, self);
}

py::array meshTriangleFaces(const py::object& self) {
  const TriangleMesh& mesh = self.cast<const Part&>().mesh;
  return view(mesh.triangle_faces.data(), {count(mesh.triangle_faces.size())}, {sizeof(int)}, self);
}

py::array_t<double> viewPoses(const Plan& plan) {
  py::array_t<double> array({plan.views.size(), std::size_t{4}, std::size_t{4}});
  auto out = array.mutable_unchecked<3>();
  for (std::size_t v = 0; v < plan.views.size(); ++v)
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        out(static_cast<py::ssize_t>(v), r, c) = plan.views[v].camera_to_world.matrix()(r, c);
  return array;
}

std::vector<int> viewIds(const Plan& plan) {
  std::vector<int> ids;
  for (const View& view : plan.views) ids.push_back(view.id);
  return ids;
}

py::array_t<double> viewTargets(const Plan& plan) {
  std::vector<Vec3> targets;
  for (const View& view : plan.views) targets.push_back(view.target);
  return rows(targets);
}

std::vector<View> viewsFrom(const py::object& poses, double standoff) {
  const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(poses);
  if (!array || array.ndim() != 3 || array.shape(1) != 4 || array.shape(2) != 4)
    throw InputError("views", "expected an (n, 4, 4) array of camera-to-world matrices");
  const auto in = array.unchecked<3>();
  std::vector<View> views;
  for (py::ssize_t v = 0; v < array.shape(0); ++v) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = in(v, r, c);
    const Eigen::Matrix3d rotation = m.topLeftCorner<3, 3>();
    if (!m.allFinite() || !(rotation.transpose() * rotation).isIdentity(1e-6) ||
        !(rotation.determinant() > 0) || !m.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)))
      throw InputError("views", "matrix " + std::to_string(v) + " is not a rigid motion");
    View view;
    view.id = static_cast<int>(v) + 1;
    view.camera_to_world = Pose(m);
    view.target = view.camera() + standoff * view.axis();
    views.push_back(view);
  }
  return views;
}

py::array_t<double> samplePositions(const Plan& plan) {
  std::vector<Vec3> points;
  for (const PlannedSample& s : plan.samples) points.push_back(s.sample.position);
  return rows(points);
}

py::array_t<double> sampleNormals(const Plan& plan) {
  std::vector<Vec3> normals;
  for (const PlannedSample& s : plan.samples) normals.push_back(s.sample.normal);
  return rows(normals);
}

py::array_t<int> sampleFaces(const Plan& plan) {
  return column<int>(plan.samples.size(),
                     [&](std::size_t i) { return plan.samples[i].sample.face; });
}

py::array_t<bool> sampleMeasured(const Plan& plan) {
  return column<bool>(plan.samples.size(),
                      [&](std::size_t i) { return !plan.samples[i].measured_by.empty(); });
}

}  // namespace scanplan::python
