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

// The samples as PLY (scene frame): x y z nx ny nz, face, task, role, views measuring it,
// state (0 measured, 1 not measured, 2 not coverable), reason (Uncoverable), red green
// blue by state.
PlyData samplesPly(const Plan& plan);

// Writes every view's simulated cloud (forEachViewCloud, planning/evidence.h) into one
// binary PLY, one view at a time so that memory stays that of one cloud: x y z nx ny nz,
// face, incidence (degrees), view (id), red green blue by incidence.
// \throw OutputError when it cannot be written.
void writeCloudsPly(const Plan& plan, const Part& part, const Spec& spec, double spacing,
                    const std::string& path, const Progress& progress = {});

// The scene as glTF 2.0 binary (.glb): the part with vertex colours by face coverage, the
// priority faces' outlines, the frusta, the path and the markers, each a node of its own.
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
