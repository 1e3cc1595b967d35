#pragma once
// Where the part stands on the working plane (docs/localization.md): its stable
// rest orientations, from the faces of its convex hull.

#include <scanplan/cad/part.h>
#include <scanplan/core/view.h>

#include <string>
#include <vector>

namespace scanplan {

struct RestOrientation {
  Vec3 down = -Vec3::UnitZ();             // outward normal of the hull face it rests on, part frame
  Pose part_to_world = Pose::Identity();  // turns `down` to -Z, puts the hull face on z = 0
                                          // and the centre of mass above the origin
  double margin = 0;                      // distance from the centre of mass's projection to the
                                          // hull face's boundary, divided by the centre of mass's
                                          // height above it (dimensionless, larger is steadier)
  double contact_area = 0;                // area of the hull face, mm²
  double height = 0;                      // centre of mass above the plane, mm
};

// The part's centre of mass, uniform density: OCCT's mass properties of its solids, or of
// the closed mesh for mesh parts. \throw InputError for a part with no volume.
Vec3 centreOfMass(const Part& part);

// Rest orientations: the faces of the convex hull (Qhull, coplanar facets merged) on
// which the centre of mass projects inside, sorted by decreasing margin (ties by larger
// contact area, then hull order). \throw InputError for a part with no volume.
std::vector<RestOrientation> restOrientations(const Part& part);

// The rest orientation in which the part stands on face `face` (a flat face lying in the
// hull face it rests on). \throw InputError naming `source` and `key`, where the face was
// given, for an unknown, curved or unstable face.
RestOrientation restOnFace(const Part& part, int face, const std::string& source,
                           const std::string& key = "part.rest");

}  // namespace scanplan
