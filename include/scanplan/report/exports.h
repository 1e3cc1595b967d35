#pragma once
// Files written from a plan's scene beside the report (docs/report.md): PLY of the samples
// and of the simulated clouds, glTF 2.0 binary, and a PNG picture.

#include <scanplan/cad/part.h>
#include <scanplan/cad/ply.h>
#include <scanplan/core/progress.h>
#include <scanplan/report/scene.h>
#include <scanplan/spec/spec.h>

#include <cstdint>
#include <string>
#include <vector>

namespace scanplan {

// The samples as PLY in `frame`: x y z (double) nx ny nz; scalar_face, scalar_task,
// scalar_role, scalar_views (views measuring it), scalar_state (0 measured, 1 not measured,
// 2 not coverable) and scalar_reason (Uncoverable), named so that CloudCompare reads them
// as scalar fields; quality (MeshLab's), the views again; red green blue by state.
PlyData samplesPly(const Plan& plan, Frame frame = Frame::Cad);

// Writes every view's simulated cloud (forEachViewCloud, planning/evidence.h) in `frame`
// into one binary PLY, one view at a time so that memory stays that of one cloud: x y z
// nx ny nz, scalar_face, scalar_incidence (degrees), scalar_view (id), quality (the
// incidence again), red green blue by incidence.
// \throw OutputError when it cannot be written.
void writeCloudsPly(const Plan& plan, const Part& part, const Spec& spec, double spacing,
                    Frame frame, const std::string& path, const Progress& progress = {});

// The scene as glTF 2.0 binary (.glb), in the scene's own frame: the part with vertex
// colours by face coverage, the priority faces' outlines, the path and the markers, each a
// node of its own, and a node per view (named by its place in the sequence) holding its
// frustum and a glTF camera with the scanner's field of view, looking along the view.
// \throw OutputError when it cannot be written.
void writeGlb(const PlanScene& scene, const std::string& path);

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // row-major from the top, 3 bytes a pixel
};

// A picture of the scene from above and in front (Embree primary rays, Lambert shading
// with a head light): the part coloured by coverage, the frusta, path and markers drawn
// over it.
Image renderScene(const PlanScene& scene, int width = 1280, int height = 960);
// \throw OutputError when it cannot be written.
void writePng(const Image& image, const std::string& path);
// \throw InputError naming the file when it cannot be read.
Image readPng(const std::string& path);

}  // namespace scanplan
