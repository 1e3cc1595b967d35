#pragma once
// Task-driven sampling (docs/design.md §2, §5): what is sampled, and how, follows the
// inspection task. All positions and normals are in the part frame, mm.

#include <scanplan/cad/part.h>
#include <scanplan/core/tasks.h>
#include <scanplan/scanner/sensor.h>
#include <scanplan/scanner/simulation.h>

#include <Eigen/Core>
#include <string_view>
#include <vector>

namespace scanplan {

struct Sample {
  Vec3 position = Vec3::Zero();                  // on the face, part frame, mm
  Vec3 normal = Vec3::UnitZ();                   // unit, outward
  Vec3 tangent = Vec3::Zero();                   // unit edge tangent for border samples, else zero
  int face = 0;                                  // 1-based face id
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // face parameters (border: edge parameter in x)
  Role role = Role::Normal;
  TaskType task = TaskType::Global;
  double weight = 0;  // surface: area it stands for, mm²; border: length, mm
  int cluster = -1;   // set by clustering, -1 before
};

struct SamplingOptions {
  double portion_size = 225;       // largest extent of a face portion, mm (the field of view)
  double max_normal_spread = 90;   // largest angle between normals in a portion, degrees
  double overlap = 0.1;            // portions overlap their neighbours by this fraction
  int min_per_direction = 8;       // samples per parameter direction of a portion, at least
  int max_per_direction = 40;      // and at most
  double border_deflection = 0.1;  // chordal tolerance of border sampling, mm
  double border_step = 5;          // largest step between border samples, mm
  double decimation_radius = 20;   // global: samples closer than this, mm ...
  double decimation_angle = 20;    // ... whose normals differ less than this (degrees) merge
  double point_tolerance = 1;      // user points farther than this from the part are errors, mm
};

// Options with the field-of-view-dependent sizes taken from the scanner.
SamplingOptions samplingOptionsFor(const Scanner& scanner);

// Surface sampling of B-Rep faces (gdt, surface): each face is split along isoparametric
// lines into portions no larger than `portion_size` whose normals spread at most
// `max_normal_spread`, overlapping; each portion is sampled at the Greville abscissae of
// the face's NURBS form (OCCT's conversion for analytic faces), at least
// `min_per_direction` per direction, keeping the points inside the trimmed face.
// Mesh parts: the centroids of the faces' triangles.
std::vector<Sample> sampleSurface(const Part& part, const std::vector<int>& faces, Role role,
                                  TaskType task, const SamplingOptions& options = {});

// Border sampling (trim): the edges of the faces' outer and inner wires under a chordal
// tolerance and a largest step, each with the face's normal and the edge's tangent.
// Seam and degenerate edges are skipped. Mesh parts: the faces' boundary edges.
std::vector<Sample> sampleBorders(const Part& part, const std::vector<int>& faces, Role role,
                                  TaskType task, const SamplingOptions& options = {});

// Global sampling: every face (but `excluded`) surface-sampled, then decimated by distance
// and normal angle, so flat areas keep few samples and curved ones more; every face keeps at
// least one, so that a scan of the whole part is aimed at its small faces too.
std::vector<Sample> sampleGlobal(const Part& part, const std::vector<int>& excluded,
                                 const SamplingOptions& options = {});

// User points projected onto the nearest face: the sample is the point on it (on the exact
// face of a B-Rep, else on its triangles), with its face id and, when the CSV gives none,
// its normal there. \throw InputError naming `source` and the point (line) farther than
// `point_tolerance` from the part.
std::vector<Sample> samplePoints(const Part& part, const std::vector<ControlPoint>& points,
                                 const std::string& source, const SamplingOptions& options = {});

// The samples as surface points; those of `members` (indices into `samples`) only.
std::vector<SurfacePoint> surfacePoints(const std::vector<Sample>& samples);
std::vector<SurfacePoint> surfacePoints(const std::vector<Sample>& samples,
                                        const std::vector<int>& members);

// Whether decimation may take away every sample of a face.
enum class FaceSamples { MayVanish, KeepOne };

// Greedy decimation: keeps a sample unless an earlier kept one lies within `radius`
// with a normal within `angle` degrees, which then stands for its weight too. With
// FaceSamples::KeepOne, a face's last sample stays however near it lies to another's.
// Deterministic (input order).
std::vector<Sample> decimate(const std::vector<Sample>& samples, double radius, double angle,
                             FaceSamples faces = FaceSamples::MayVanish);

// Every task's samples, merged, in task order (resolveSpec in spec.h makes the targets):
// gdt, surface and trim samples are priority; global samples of priority faces too;
// fixture faces are never sampled. \throw InputError for a bad control points file.
std::vector<Sample> sampleTargets(const Part& part, const Targets& targets,
                                  const SamplingOptions& options);

}  // namespace scanplan
