#pragma once
// The scanner model (docs/design.md §4): a camera and a projector (or laser) on a rigid
// baseline, with its measuring volume, glancing limits and noise; a fringe head may have a
// second camera on the projector's other side.
//
// Scanner frame S: origin at the (first) camera's optical centre, +Z the optical axis
// (towards the part), +X from the camera towards the projector, +Y = Z x X. A view is the
// pose of S in the world, camera_to_world.

#include <scanplan/core/geometry.h>

#include <array>
#include <string>
#include <vector>

namespace scanplan {

struct Scanner {
  std::string name = "custom";
  double standoff = 400;            // camera centre to measuring-volume centre along +Z, mm
  double depth_of_field = 200;      // length of the measuring volume along +Z, mm
  double fov_width = 300;           // measured width at the standoff, along X, mm
  double fov_height = 225;          // measured height at the standoff, along Y, mm
  double triangulation_angle = 25;  // camera axis to projector axis, degrees
  double max_camera_angle = 60;     // largest angle normal / direction to camera, degrees
  double max_projector_angle = 60;  // the same for the projector, degrees
  double reflection_cone = 10;      // specular loss cone around the mirror direction, degrees
  double point_spacing = 0.2;       // lateral sampling distance at the standoff, mm
  double noise_sigma = 0.01;        // depth noise at the standoff and normal incidence, mm
  // 1, or 2: a second camera as far beyond the projector as the first is before it,
  // aimed at the measuring volume's centre. A point is measured where the projector lights
  // it and either camera sees it, as a two-camera fringe head measures.
  double cameras = 1;
  // The scanner body, which must stay clear of the part, fixtures and working plane: a box
  // around camera and projector grown by body_margin, reaching body_depth behind the camera.
  double body_margin = 60;  // mm
  double body_depth = 200;  // mm
  // The acquisition at each view (docs/cycle.md): a fringe head projects `patterns`
  // patterns, each exposed for `exposure` seconds; a laser line (sweep_speed > 0, mm/s)
  // sweeps its stroke, fov_height, at that speed.
  double patterns = 10;
  double exposure = 0.05;  // s
  double sweep_speed = 0;  // mm/s; 0: a fringe head
  // Acceptance figures after VDI/VDE 2634 part 2, as a data sheet states them (maximum
  // permissible errors, mm; 0: not stated): probing error of form (PF) and of size (PS) on
  // a sphere, the sphere-spacing error (SD) and the flatness measurement error (F). The
  // error budget adds them to the noise (docs/capability.md, "Error budget").
  double probing_form = 0;
  double probing_size = 0;
  double sphere_spacing = 0;
  double flatness_error = 0;

  // Distance from camera to projector: standoff * tan(triangulation_angle), mm.
  double baseline() const;
  // Radius of the sphere around the view's target that holds the whole measuring volume.
  double reach() const;
  // Projector centre in S: (baseline, 0, 0).
  Vec3 projectorInScanner() const;
  // The cameras' centres in S: (0, 0, 0), and with a second camera (2 baseline, 0, 0).
  std::vector<Vec3> camerasInScanner() const;
  // The scanner body in S: the box around camera and projector grown by body_margin,
  // reaching body_depth behind the camera.
  Box body() const;
  // Seconds from the trigger to the end of one view's capture.
  double acquisitionSeconds() const;
};

// The scanner's numeric parameters by the names spec, preset and plan files give them.
struct ScannerParameter {
  const char* name;
  double Scanner::*value;
};
const std::array<ScannerParameter, 20>& scannerParameters();

// \throw InputError naming `source` and the parameter when a value is out of range:
//        the cameras 1 or 2, sizes positive, angles within (0, 90) degrees (the reflection cone
//        within [0, 90)), and the depth of field shorter than twice the standoff; the
//        patterns a whole number within [1, 1000], the exposure within (0, 10] s, the
//        sweep speed 0 or within [1, 10000] mm/s, the acceptance figures 0 or positive
//        and less than the depth of field.
void validate(const Scanner& scanner, const std::string& source);

// The scanner presets' names, sorted: those compiled into the library (data/scanners/ of
// the source) and those in $SCANPLAN_DATA/scanners/<name>.yaml, which may add presets or
// replace one by name.
std::vector<std::string> scannerPresetNames();

// The preset `name`, validated: $SCANPLAN_DATA/scanners/<name>.yaml if there is one, else
// the library's own.
// \throw InputError for an unknown preset (listing the known ones) or a bad preset file.
Scanner scannerPreset(const std::string& name);

// The scanner `name` names: a scanner file (YAML: a path ending in .yaml or .yml, or an
// existing file) read by loadScanner, else a preset.
Scanner scannerNamed(const std::string& name);

// A scanner from a YAML file: either a scanner file (a mapping of the parameters above,
// optionally `preset: NAME` to start from) or a spec with a `scanner:` key holding a
// preset name or such a mapping. Unknown keys are errors.
// \throw InputError naming the file and the problem.
Scanner loadScanner(const std::string& path);

}  // namespace scanplan
