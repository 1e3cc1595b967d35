#pragma once
// The scene a plan makes (docs/report.md): the part coloured by coverage, the views as
// frusta in sequence and coloured by registration state, the path, the markers; what the
// report, the glTF file and the picture draw.

#include <scanplan/cad/part.h>
#include <scanplan/plan/plan.h>
#include <scanplan/spec/spec.h>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace scanplan {

// How much of a face the plan measures.
enum class FaceCoverage : std::uint8_t {
  NotTarget,    // no sample on it
  Measured,     // every sample measured
  Partly,       // some samples measured
  NotMeasured,  // samples on it, none measured
};
std::string_view toString(FaceCoverage coverage);

enum class ViewState : std::uint8_t {
  Registered,     // registers to the reference through the graph
  Bridge,         // added to join the registration graph
  Unregistrable,  // registers to no other view
  Unchecked,      // the plan has no registration
};
std::string_view toString(ViewState state);

using Rgb = std::array<std::uint8_t, 3>;  // sRGB
Rgb colour(FaceCoverage coverage);
Rgb colour(ViewState state);
inline constexpr Rgb kFixtureColour{96, 122, 168};         // fixture models and fixture faces
inline constexpr Rgb kPathColour{240, 228, 66};            // the path (Okabe-Ito yellow)
inline constexpr Rgb kMarkerColour{60, 60, 60};            // markers in the cell
inline constexpr Rgb kProposedMarkerColour{86, 180, 233};  // markers proposed (sky blue)

struct FaceStatus {
  int id = 0;
  std::size_t samples = 0, measured = 0, not_coverable = 0;
  FaceCoverage coverage = FaceCoverage::NotTarget;
  bool priority = false;                   // toleranced or datum face (GD&T)
  Uncoverable reason = Uncoverable::None;  // the commonest reason of its not coverable samples
  Loss loss = Loss::Measured;  // of those lost in simulation, the commonest test that lost them
};

struct SceneView {
  View view;      // in the scene frame
  int order = 0;  // 1-based position in the sequence; 0: not in it
  ViewState state = ViewState::Unchecked;
  int orientation = 0;       // 1-based index into Plan::orientations; 0 for one placement
  std::size_t measured = 0;  // samples it measures
};

// The plan in one frame, the world of its first placement (Plan::part_to_world): views
// of other rest orientations are carried into it with the part.
struct PlanScene {
  TriangleMesh mesh;                   // the part's mesh placed in the scene, mm
  std::vector<FaceStatus> faces;       // per face, faces[i].id == i + 1
  std::vector<SceneView> views;        // in plan order
  std::vector<int> path;               // indices into views, in sequence order
  std::vector<Vec3> markers;           // in the scene frame
  std::vector<Vec3> proposed_markers;  // the plan's proposal, one orientation only
  TriangleMesh fixtures;               // the spec's fixture models (face id 0), or none
  Scanner scanner;
  Box bounds;  // of the mesh, the cameras and the markers
};

// \throw InputError when the part does not match the plan (face count).
PlanScene planScene(const Plan& plan, const Part& part);
// The same with the fixture models of `spec` (resolved against `part`) in the scene.
PlanScene planScene(const Plan& plan, const Part& part, const ResolvedSpec& spec);

// The frames a scene and the exports are given in (docs/report.md, "Frames"): the part's
// CAD model's own, or the world of the plan's first setup, where the cell stands (the
// scene frame).
enum class Frame { Cad, World };
std::string_view toString(Frame frame);  // "cad", "world"
// The pose of the scene frame in `frame`: the inverse of the first placement for the CAD
// frame.
Pose sceneTo(const Plan& plan, Frame frame);
// The scene carried by `to`: its part, fixtures, views, path, markers and bounds.
void moveScene(PlanScene& scene, const Pose& to);

// The colour of face `face` of the scene: its coverage, the fixtures' for face 0 (the
// fixture models), not a target for an id the part does not have.
Rgb faceColour(const PlanScene& scene, int face);

// A sample's state: 0 measured, 1 not measured, 2 not coverable.
int sampleState(const PlannedSample& sample);

// The measuring frustum of a view: the camera, then the four corners of the field of view
// at the far end of the depth of field (scanner frame S: x right, y down, z ahead).
std::array<Vec3, 5> frustum(const View& view, const Scanner& scanner);

// The outlines of the priority faces: the edges of their triangles that no other
// triangle of the same face shares, as pairs of points (line segments).
std::vector<Vec3> priorityOutlines(const PlanScene& scene);

}  // namespace scanplan
