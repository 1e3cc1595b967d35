// Border sampling (trim task): the edges of the target faces.

#include "cad/brep_model.h"

#include <scanplan/sampling/sampling.h>

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRep_Tool.hxx>
#include <GCPnts_QuasiUniformDeflection.hxx>
#include <Geom2d_Curve.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_MapOfShape.hxx>
#include <TopoDS.hxx>

#include <cmath>
#include <map>

namespace scanplan {
namespace {

// Parameters along the edge: quasi-uniform under the chordal tolerance, then subdivided
// so that no step is longer than `step`; the end point is left to the next edge.
std::vector<double> edgeParameters(const BRepAdaptor_Curve& curve, const SamplingOptions& options) {
  std::vector<double> params;
  GCPnts_QuasiUniformDeflection deflection(curve, options.border_deflection);
  if (deflection.IsDone() && deflection.NbPoints() >= 2) {
    for (int i = 1; i <= deflection.NbPoints(); ++i) params.push_back(deflection.Parameter(i));
  } else {
    params = {curve.FirstParameter(), curve.LastParameter()};
  }
  std::vector<double> result;
  for (std::size_t i = 0; i + 1 < params.size(); ++i) {
    const double a = params[i], b = params[i + 1];
    const double length = curve.Value(a).Distance(curve.Value(b));
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / options.border_step)));
    for (int k = 0; k < pieces; ++k) result.push_back(a + (b - a) * k / pieces);
  }
  return result;
}

void sampleBrepBorders(const Part& part, int id, Role role, TaskType task,
                       const SamplingOptions& options, std::vector<Sample>& out) {
  const TopoDS_Face face = part.brep->outwardFace(id);
  BRepAdaptor_Surface surface(face);
  TopTools_MapOfShape done;
  for (TopExp_Explorer it(face, TopAbs_EDGE); it.More(); it.Next()) {
    const TopoDS_Edge edge = TopoDS::Edge(it.Current());
    if (BRep_Tool::Degenerated(edge) || BRep_Tool::IsClosed(edge, face) || !done.Add(edge))
      continue;
    double first = 0, last = 0;
    Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, face, first, last);
    if (pcurve.IsNull()) continue;
    BRepAdaptor_Curve curve(edge);
    const std::vector<double> params = edgeParameters(curve, options);
    for (std::size_t i = 0; i < params.size(); ++i) {
      const double t = params[i];
      gp_Pnt p;
      gp_Vec d1;
      curve.D1(t, p, d1);
      if (edge.Orientation() == TopAbs_REVERSED) d1.Reverse();
      const gp_Pnt2d uv = pcurve->Value(t);
      gp_Pnt on_surface;
      gp_Vec du, dv;
      surface.D1(uv.X(), uv.Y(), on_surface, du, dv);
      gp_Vec n = du.Crossed(dv);
      if (n.Magnitude() < 1e-12 || d1.Magnitude() < 1e-12) continue;
      if (face.Orientation() == TopAbs_REVERSED) n.Reverse();
      n.Normalize();
      d1.Normalize();
      Sample s;
      s.position = Vec3(p.X(), p.Y(), p.Z());
      s.normal = Vec3(n.X(), n.Y(), n.Z());
      s.tangent = Vec3(d1.X(), d1.Y(), d1.Z());
      s.face = id;
      s.uv = Eigen::Vector2d(t, 0);
      s.role = role;
      s.task = task;
      const double next = i + 1 < params.size() ? params[i + 1] : curve.LastParameter();
      s.weight = p.Distance(curve.Value(next));
      out.push_back(s);
    }
  }
}

// A mesh face's border: its triangle edges not shared with another triangle of the face.
void sampleMeshBorders(const Part& part, int id, Role role, TaskType task,
                       const SamplingOptions& options, std::vector<Sample>& out) {
  const Face& face = part.face(id);
  std::map<std::pair<int, int>, std::pair<int, int>> edges;  // (a, b) → (uses, triangle)
  for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t)
    for (int k = 0; k < 3; ++k) {
      int a = part.mesh.triangles[t][k], b = part.mesh.triangles[t][(k + 1) % 3];
      auto& entry = edges[{std::min(a, b), std::max(a, b)}];
      ++entry.first;
      entry.second = t;
    }
  for (const auto& [key, use] : edges) {
    if (use.first != 1) continue;
    const Vec3& a = part.mesh.vertices[key.first];
    const Vec3& b = part.mesh.vertices[key.second];
    const double length = (b - a).norm();
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / options.border_step)));
    for (int k = 0; k < pieces; ++k) {
      Sample s;
      s.position = a + (b - a) * (k + 0.5) / pieces;
      s.normal = part.mesh.normal(use.second);
      s.tangent = (b - a).normalized();
      s.face = id;
      s.role = role;
      s.task = task;
      s.weight = length / pieces;
      out.push_back(s);
    }
  }
}

}  // namespace

std::vector<Sample> sampleBorders(const Part& part, const std::vector<int>& faces, Role role,
                                  TaskType task, const SamplingOptions& options) {
  std::vector<Sample> samples;
  for (int id : faces) {
    part.face(id);  // throws for an unknown id
    if (part.brep)
      sampleBrepBorders(part, id, role, task, options, samples);
    else
      sampleMeshBorders(part, id, role, task, options, samples);
  }
  return samples;
}

}  // namespace scanplan
