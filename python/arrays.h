#pragma once
// numpy arrays of the library's points, poses and meshes. The part's mesh is viewed in
// place (read-only, keeping the part alive); the rest is copied, its values being spread
// over structs rather than laid out as arrays.

#include <scanplan/cad/part.h>
#include <scanplan/planning.h>

#include <pybind11/numpy.h>

#include <vector>

namespace scanplan::python {

namespace py = pybind11;

// (n, 3) float64.
py::array_t<double> rows(const std::vector<Vec3>& points);

// The part's mesh, viewed: `self` is the Python Part.
py::array meshVertices(const py::object& self);
py::array meshTriangles(const py::object& self);
py::array meshTriangleFaces(const py::object& self);

// The plan's views: (n, 4, 4) camera-to-world, ids, (n, 3) targets.
py::array_t<double> viewPoses(const Plan& plan);
std::vector<int> viewIds(const Plan& plan);
py::array_t<double> viewTargets(const Plan& plan);
// Views from an (n, 4, 4) array of camera-to-world matrices: ids 1..n, each aimed along
// its axis. \throw InputError for another shape or a matrix that is not a rigid motion.
std::vector<View> viewsFrom(const py::object& poses, double standoff);

// The plan's samples: (m, 3) positions and normals, (m,) face ids, (m,) measured.
py::array_t<double> samplePositions(const Plan& plan);
py::array_t<double> sampleNormals(const Plan& plan);
py::array_t<int> sampleFaces(const Plan& plan);
py::array_t<bool> sampleMeasured(const Plan& plan);

}  // namespace scanplan::python
