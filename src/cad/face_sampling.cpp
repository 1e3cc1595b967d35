// The sampling kernels on a B-Rep's exact faces: Greville points by portions that fit the
// field of view, points along the faces' edges, and the nearest point of a face.

#include "cad/brep_model.h"

#include <scanplan/cad/face_sampling.h>

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <BSplCLib.hxx>
#include <GCPnts_QuasiUniformDeflection.hxx>
#include <Geom2d_Curve.hxx>
#include <GeomConvert.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_MapOfShape.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <cmath>

namespace scanplan {
namespace {

// Greville abscissae of one parameter direction, as fractions of the parameter range.
std::vector<double> grevilleFractions(const Handle(Geom_BSplineSurface) & surface,
                                      bool u_direction) {
  const int degree = u_direction ? surface->UDegree() : surface->VDegree();
  const int poles = u_direction ? surface->NbUPoles() : surface->NbVPoles();
  TColStd_Array1OfReal flat(1, poles + degree + 1);
  if (u_direction)
    surface->UKnotSequence(flat);
  else
    surface->VKnotSequence(flat);
  TColStd_Array1OfReal abscissae(1, poles);
  BSplCLib::BuildSchoenbergPoints(degree, flat, abscissae);
  const double first = flat(degree + 1), last = flat(poles + 1);
  std::vector<double> fractions;
  for (int i = 1; i <= poles; ++i) fractions.push_back((abscissae(i) - first) / (last - first));
  return fractions;
}

class FaceSampler {
 public:
  FaceSampler(const TopoDS_Face& face, const FaceSampling& options)
      : face_(face), surface_(face), classifier_(face, 1e-7), options_(options) {
    BRepTools::UVBounds(face, u0_, u1_, v0_, v1_);
    // Pcurves of a periodic face may wind over more than one period (a sphere face with u
    // in [-pi/2, 2pi]); the 2D classifier is unreliable there, so classify in 3D.
    wraps_ = (surface_.IsUPeriodic() && u1_ - u0_ > surface_.UPeriod() + 1e-9) ||
             (surface_.IsVPeriodic() && v1_ - v0_ > surface_.VPeriod() + 1e-9);
    // The NURBS form: the face's own B-spline, or OCCT's conversion of its trimmed surface.
    try {
      Handle(Geom_Surface) geometry = BRep_Tool::Surface(face);
      Handle(Geom_BSplineSurface) nurbs = GeomConvert::SurfaceToBSplineSurface(
          new Geom_RectangularTrimmedSurface(geometry, u0_, u1_, v0_, v1_));
      greville_u_ = grevilleFractions(nurbs, true);
      greville_v_ = grevilleFractions(nurbs, false);
    } catch (const Standard_Failure&) {
      // No NURBS form (rare surface kinds): uniform parameters only.
    }
  }

  // Point and outward normal at fractions (s, t) of the UV box; false where the normal
  // is undefined (a pole).
  bool evaluate(double s, double t, Vec3& point, Vec3& normal, Eigen::Vector2d& uv) const {
    uv = Eigen::Vector2d(u0_ + s * (u1_ - u0_), v0_ + t * (v1_ - v0_));
    gp_Pnt p;
    gp_Vec du, dv;
    surface_.D1(uv.x(), uv.y(), p, du, dv);
    gp_Vec n = du.Crossed(dv);
    if (n.Magnitude() < 1e-12) return false;
    if (face_.Orientation() == TopAbs_REVERSED) n.Reverse();
    n.Normalize();
    point = Vec3(p.X(), p.Y(), p.Z());
    normal = Vec3(n.X(), n.Y(), n.Z());
    return true;
  }

  bool inside(double s, double t) const {
    const double u = u0_ + s * (u1_ - u0_), v = v0_ + t * (v1_ - v0_);
    if (!wraps_) return classifier_.Perform(gp_Pnt2d(u, v)) == TopAbs_IN;
    BRepClass_FaceClassifier classifier(face_, surface_.Value(u, v), 1e-7);
    return classifier.State() == TopAbs_IN;
  }

  struct Rect {
    double s0, s1, t0, t1;
  };
  static constexpr int kMaxDepth = 12;  // at most 4096 portions per face

  // Splits [0,1]² along isoparametric lines until each portion fits: no larger than the
  // field of view, normals within the spread. A portion is split across the direction in
  // which it is longer (too big) or turns more (too curved), judged on a 5 x 5 probe grid
  // so that closed faces (a full cylinder) split around, not along.
  void portions(const Rect& r, int depth, std::vector<Rect>& out) const {
    constexpr int kProbe = 5;
    Vec3 point[kProbe][kProbe], normal[kProbe][kProbe];
    bool valid[kProbe][kProbe];
    Box box;
    std::vector<Vec3> inside_normals;
    for (int i = 0; i < kProbe; ++i)
      for (int j = 0; j < kProbe; ++j) {
        const double s = r.s0 + (r.s1 - r.s0) * i / (kProbe - 1),
                     t = r.t0 + (r.t1 - r.t0) * j / (kProbe - 1);
        Eigen::Vector2d uv;
        valid[i][j] = evaluate(s, t, point[i][j], normal[i][j], uv);
        if (!valid[i][j] || !inside(s, t)) continue;
        box.add(point[i][j]);
        inside_normals.push_back(normal[i][j]);
      }
    double min_dot = 1;
    for (std::size_t a = 0; a < inside_normals.size(); ++a)
      for (std::size_t b = a + 1; b < inside_normals.size(); ++b)
        min_dot = std::min(min_dot, inside_normals[a].dot(inside_normals[b]));
    const bool too_big = !box.empty() && box.size().maxCoeff() > options_.portion_size;
    const bool too_curved = min_dot < std::cos(radians(options_.max_normal_spread));
    if (!(too_big || too_curved) || depth >= kMaxDepth) {
      out.push_back(r);
      return;
    }
    // Length and turning of the probe polylines along s and along t.
    double length_s = 0, length_t = 0, turn_s = 0, turn_t = 0;
    for (int i = 0; i + 1 < kProbe; ++i)
      for (int j = 0; j < kProbe; ++j) {
        if (valid[i][j] && valid[i + 1][j]) {
          length_s += (point[i + 1][j] - point[i][j]).norm();
          turn_s += std::acos(std::clamp(normal[i + 1][j].dot(normal[i][j]), -1.0, 1.0));
        }
        if (valid[j][i] && valid[j][i + 1]) {
          length_t += (point[j][i + 1] - point[j][i]).norm();
          turn_t += std::acos(std::clamp(normal[j][i + 1].dot(normal[j][i]), -1.0, 1.0));
        }
      }
    const bool split_s = too_curved && turn_s != turn_t ? turn_s > turn_t : length_s >= length_t;
    if (split_s) {
      const double mid = 0.5 * (r.s0 + r.s1);
      portions({r.s0, mid, r.t0, r.t1}, depth + 1, out);
      portions({mid, r.s1, r.t0, r.t1}, depth + 1, out);
    } else {
      const double mid = 0.5 * (r.t0 + r.t1);
      portions({r.s0, r.s1, r.t0, mid}, depth + 1, out);
      portions({r.s0, r.s1, mid, r.t1}, depth + 1, out);
    }
  }

  // Parameters of one direction of a portion [a, b] (grown by the overlap): the Greville
  // abscissae inside it, or evenly spread ones when those are too few or too many.
  std::vector<double> parameters(double a, double b, const std::vector<double>& greville) const {
    const double grow = options_.overlap * (b - a);
    a = std::max(0.0, a - grow);
    b = std::min(1.0, b + grow);
    std::vector<double> values;
    for (double g : greville)
      if (g > a && g < b) values.push_back(g);
    const int n = static_cast<int>(values.size());
    if (n >= options_.min_per_direction && n <= options_.max_per_direction) return values;
    const int count = std::clamp(n, options_.min_per_direction, options_.max_per_direction);
    values.clear();
    for (int i = 0; i < count; ++i) values.push_back(a + (b - a) * (i + 0.5) / count);
    return values;
  }

  std::vector<FacePoint> sample() const {
    std::vector<Rect> rects;
    portions({0, 1, 0, 1}, 0, rects);
    std::vector<FacePoint> out;
    for (const Rect& r : rects)
      for (double s : parameters(r.s0, r.s1, greville_u_))
        for (double t : parameters(r.t0, r.t1, greville_v_)) {
          if (!inside(s, t)) continue;
          FacePoint point;
          if (!evaluate(s, t, point.position, point.normal, point.uv)) continue;
          out.push_back(point);
        }
    return out;
  }

 private:
  TopoDS_Face face_;
  BRepAdaptor_Surface surface_;
  BRepTopAdaptor_FClass2d classifier_;
  FaceSampling options_;
  double u0_ = 0, u1_ = 1, v0_ = 0, v1_ = 1;
  bool wraps_ = false;
  std::vector<double> greville_u_, greville_v_;
};

}  // namespace

std::vector<FacePoint> brepSurfacePoints(const Part& part, int face, const FaceSampling& sampling) {
  return FaceSampler(part.brep->outwardFace(face), sampling).sample();
}

namespace {

// Parameters along the edge: quasi-uniform under the chordal tolerance, then subdivided
// so that no step is longer than `step`; the end point is left to the next edge.
std::vector<double> edgeParameters(const BRepAdaptor_Curve& curve, double border_deflection,
                                   double border_step) {
  std::vector<double> params;
  GCPnts_QuasiUniformDeflection deflection(curve, border_deflection);
  if (deflection.IsDone() && deflection.NbPoints() >= 2) {
    for (int i = 1; i <= deflection.NbPoints(); ++i) params.push_back(deflection.Parameter(i));
  } else {
    params = {curve.FirstParameter(), curve.LastParameter()};
  }
  std::vector<double> result;
  for (std::size_t i = 0; i + 1 < params.size(); ++i) {
    const double a = params[i], b = params[i + 1];
    const double length = curve.Value(a).Distance(curve.Value(b));
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / border_step)));
    for (int k = 0; k < pieces; ++k) result.push_back(a + (b - a) * k / pieces);
  }
  return result;
}

}  // namespace

std::vector<FacePoint> brepBorderPoints(const Part& part, int id, double deflection, double step) {
  std::vector<FacePoint> out;
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
    const std::vector<double> params = edgeParameters(curve, deflection, step);
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
      FacePoint point;
      point.position = Vec3(p.X(), p.Y(), p.Z());
      point.normal = Vec3(n.X(), n.Y(), n.Z());
      point.tangent = Vec3(d1.X(), d1.Y(), d1.Z());
      point.uv = Eigen::Vector2d(t, 0);
      const double next = i + 1 < params.size() ? params[i + 1] : curve.LastParameter();
      point.length = p.Distance(curve.Value(next));
      out.push_back(point);
    }
  }
  return out;
}

std::optional<NearestOnFace> nearestOnBrepFace(const Part& part, int id, const Vec3& p) {
  const TopoDS_Face face = part.brep->outwardFace(id);
  BRepExtrema_DistShapeShape extrema(
      BRepBuilderAPI_MakeVertex(gp_Pnt(p.x(), p.y(), p.z())).Vertex(), face);
  if (!extrema.IsDone() || extrema.NbSolution() == 0) return std::nullopt;
  NearestOnFace nearest;
  nearest.distance = extrema.Value();
  const gp_Pnt on = extrema.PointOnShape2(1);
  nearest.position = Vec3(on.X(), on.Y(), on.Z());
  if (extrema.SupportTypeShape2(1) != BRepExtrema_IsInFace) return nearest;
  double u = 0, v = 0;
  extrema.ParOnFaceS2(1, u, v);
  nearest.uv = Eigen::Vector2d(u, v);
  BRepLProp_SLProps props(BRepAdaptor_Surface(face), u, v, 1, 1e-9);
  if (props.IsNormalDefined()) {
    gp_Dir n = props.Normal();
    if (face.Orientation() == TopAbs_REVERSED) n.Reverse();
    nearest.normal = Vec3(n.X(), n.Y(), n.Z());
  }
  return nearest;
}

}  // namespace scanplan
