#include <scanplan/cad/localization.h>
#include <scanplan/core/errors.h>

#include "cad/brep_model.h"

#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
#include <cmath>
#include <numeric>

namespace scanplan {

Vec3 centreOfMass(const Part& part) {
  if (part.brep && !part.solids.empty()) {
    GProp_GProps props;
    BRepGProp::VolumeProperties(part.brep->shape, props);
    if (std::abs(props.Mass()) > 0) {
      const gp_Pnt c = props.CentreOfMass();
      return Vec3(c.X(), c.Y(), c.Z());
    }
  }
  // The closed mesh: sum of the signed tetrahedra from the origin.
  double volume = 0;
  Vec3 moment = Vec3::Zero();
  for (const Vec3i& t : part.mesh.triangles) {
    const Vec3 &a = part.mesh.vertices[t[0]], &b = part.mesh.vertices[t[1]],
               &c = part.mesh.vertices[t[2]];
    const double v = a.dot(b.cross(c)) / 6;
    volume += v;
    moment += v * (a + b + c) / 4;
  }
  if (!(std::abs(volume) > 0))
    throw InputError(part.file, "the part encloses no volume: it has no centre of mass");
  return moment / volume;
}

namespace {

// A face of the convex hull: outward unit normal, offset (n.x + offset = 0 on it), and
// its polygon's corners.
struct HullFace {
  Vec3 normal;
  double offset;
  std::vector<Vec3> corners;
};

std::vector<HullFace> convexHull(const std::vector<Vec3>& points, const std::string& file) {
  std::vector<coordT> coordinates;
  coordinates.reserve(points.size() * 3);
  for (const Vec3& p : points) coordinates.insert(coordinates.end(), {p.x(), p.y(), p.z()});
  qhT context;
  qhT* qh = &context;
  QHULL_LIB_CHECK
  qh_zero(qh, nullptr);
  // Qt is off: coplanar facets are merged into polygons (Qhull's default pre-merge).
  char options[] = "qhull Pp";
  const int status = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coordinates.data(), False,
                                  options, nullptr, nullptr);
  std::vector<HullFace> faces;
  if (status == 0) {
    facetT* facet;
    FORALLfacets {
      HullFace face;
      face.normal = Vec3(facet->normal[0], facet->normal[1], facet->normal[2]);
      face.offset = facet->offset;
      vertexT *vertex, **vertexp;
      FOREACHvertex_(facet->vertices)
          face.corners.emplace_back(vertex->point[0], vertex->point[1], vertex->point[2]);
      faces.push_back(std::move(face));
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int current_long = 0, total_long = 0;
  qh_memfreeshort(qh, &current_long, &total_long);
  if (status != 0)
    throw InputError(file,
                     "the convex hull of the part could not be computed (flat or degenerate)");
  return faces;
}

}  // namespace

std::vector<RestOrientation> restOrientations(const Part& part) {
  const Vec3 centre = centreOfMass(part);
  std::vector<RestOrientation> result;
  std::vector<std::size_t> order;
  for (const HullFace& face : convexHull(part.mesh.vertices, part.file)) {
    const Vec3& n = face.normal;
    const double height = -(n.dot(centre) + face.offset);  // inside the hull: positive
    if (!(height > 0)) continue;
    const Vec3 foot = centre + height * n;  // projection onto the face's plane
    // The polygon in the plane's 2D frame, corners ordered by angle about their mean.
    const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
    Vec3 mean = Vec3::Zero();
    for (const Vec3& c : face.corners) mean += c;
    mean /= static_cast<double>(face.corners.size());
    std::vector<Eigen::Vector2d> polygon;
    for (const Vec3& c : face.corners) polygon.emplace_back((c - mean).dot(u), (c - mean).dot(v));
    std::sort(polygon.begin(), polygon.end(),
              [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
                return std::atan2(a.y(), a.x()) < std::atan2(b.y(), b.x());
              });
    const Eigen::Vector2d p((foot - mean).dot(u), (foot - mean).dot(v));
    bool inside = true;
    double boundary = std::numeric_limits<double>::infinity(), area = 0;
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      const Eigen::Vector2d& a = polygon[k];
      const Eigen::Vector2d& b = polygon[(k + 1) % polygon.size()];
      const Eigen::Vector2d edge = b - a;
      const double cross = edge.x() * (p - a).y() - edge.y() * (p - a).x();
      if (cross < 0) inside = false;  // counter-clockwise polygon: inside is on the left
      const double t = std::clamp((p - a).dot(edge) / edge.squaredNorm(), 0.0, 1.0);
      boundary = std::min(boundary, (p - (a + t * edge)).norm());
      area += 0.5 * (a.x() * b.y() - b.x() * a.y());
    }
    if (!inside || polygon.size() < 3) continue;
    RestOrientation rest;
    rest.down = n;
    rest.margin = boundary / height;
    rest.contact_area = area;
    rest.height = height;
    const Eigen::Quaterniond turn = Eigen::Quaterniond::FromTwoVectors(n, -Vec3::UnitZ());
    rest.part_to_world = Pose::Identity();
    rest.part_to_world.linear() = turn.toRotationMatrix();
    rest.part_to_world.translation() = -(rest.part_to_world.linear() * foot);
    result.push_back(rest);
  }
  std::stable_sort(result.begin(), result.end(),
                   [](const RestOrientation& a, const RestOrientation& b) {
                     if (std::abs(a.margin - b.margin) > 1e-9 * std::max(1.0, a.margin))
                       return a.margin > b.margin;
                     return a.contact_area > b.contact_area + 1e-9;
                   });
  return result;
}

RestOrientation restOnFace(const Part& part, int face_id, const std::string& source,
                           const std::string& key) {
  const Face& face = part.face(face_id);
  const std::string name = key + ": face " + std::to_string(face_id);
  Vec3 normal = Vec3::Zero();
  for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
    const Vec3 n = part.mesh.normal(t);
    if (n.isZero()) continue;
    if (!normal.isZero() && n.dot(normal.normalized()) < std::cos(1e-3))
      throw InputError(source, name + " is not flat: the part cannot rest on it");
    normal += part.mesh.area(t) * n;
  }
  if (normal.isZero()) throw InputError(source, name + " has no area to rest on");
  normal.normalize();
  const double tolerance = 1e-6 * part.bounds().diagonal() + 1e-6;
  for (const RestOrientation& rest : restOrientations(part)) {
    if (rest.down.dot(normal) < std::cos(1e-6)) continue;
    bool on_plane = true;  // the face lies in the hull face the part stands on
    for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count && on_plane;
         ++t)
      for (int corner : part.mesh.triangles[t])
        on_plane = on_plane && std::abs((rest.part_to_world * part.mesh.vertices[corner]).z()) <
                                   std::max(tolerance, part.linear_deflection);
    if (on_plane) return rest;
  }
  throw InputError(source,
                   name +
                       " is not a stable rest face: it is not on the part's convex hull, "
                       "or the part would tip over resting on it (see scanplan info --rest)");
}

}  // namespace scanplan
