// Seeing a plan: the scene against what the plan of a cube must show, the frustum against
// the scanner's numbers, PLY and CSV round trips through the project's readers, the glTF's
// structure, the picture's colours, and the report page's inlined data.

#include "plan_support.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/cloud_ply.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/io/views_csv.h>
#include <scanplan/planning.h>
#include <scanplan/planning/evidence.h>
#include <scanplan/report/report.h>

#include <tiny_gltf.h>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepTools.hxx>
#include <nlohmann/json.hpp>

#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace scanplan {
namespace {

using nlohmann::json;

// A 100 mm cube standing on the working plane and its plan of one global task: every face
// but the one it stands on is measurable.
struct CubePlan {
  test::TempDir dir;
  Part part;
  Plan plan;
  CubePlan() {
    BRepTools::Write(BRepPrimAPI_MakeBox(100, 100, 100).Shape(), dir.file("cube.brep").c_str());
    part = importPart(dir.file("cube.brep"));
    plan = planViews(part, defaultSpec());
  }
};

const CubePlan& cubePlan() {
  static const CubePlan cube;
  return cube;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// The face whose vertices all lie on the working plane in the scene.
int bottomFace(const PlanScene& scene) {
  for (const FaceStatus& f : scene.faces) {
    bool low = true;
    for (std::size_t t = 0; t < scene.mesh.triangles.size(); ++t)
      if (scene.mesh.triangle_faces[t] == f.id)
        for (int k = 0; k < 3; ++k)
          low = low && std::abs(scene.mesh.vertices[scene.mesh.triangles[t][k]].z()) < 1e-6;
    if (low) return f.id;
  }
  return 0;
}

// A face without samples (a fixture's face; every other face of a scan of the whole part
// has one) is not a target, whatever its measured area.
TEST(Report, FacesWithoutSamplesAreNotTargetsWhateverTheirMeasuredArea) {
  Plan plan = cubePlan().plan;
  ASSERT_EQ(plan.face_areas.size(), 6u);
  std::erase_if(plan.samples, [](const PlannedSample& s) { return s.sample.face <= 3; });
  for (PlannedSample& s : plan.samples) s.sample.task = TaskType::Global;
  for (int f = 0; f < 3; ++f) plan.face_areas[f] = {f + 1, 100, 50.0 * f};
  const PlanScene scene = planScene(plan, cubePlan().part);
  for (int f = 0; f < 3; ++f) EXPECT_EQ(scene.faces[f].coverage, FaceCoverage::NotTarget) << f;
  for (int f = 3; f < 6; ++f) EXPECT_NE(scene.faces[f].coverage, FaceCoverage::NotTarget) << f;
}

TEST(Report, SceneOfACubeShowsTheBottomFaceUnmeasuredAndEveryOtherMeasured) {
  const Plan& plan = cubePlan().plan;
  const PlanScene scene = planScene(plan, cubePlan().part);
  ASSERT_EQ(scene.faces.size(), 6u);
  const int bottom = bottomFace(scene);
  ASSERT_NE(bottom, 0);
  for (const FaceStatus& f : scene.faces) {
    EXPECT_GT(f.samples, 0u) << f.id;
    if (f.id == bottom) {
      EXPECT_EQ(f.coverage, FaceCoverage::NotMeasured);
      EXPECT_EQ(f.reason, Uncoverable::BelowWorkingPlane);
      EXPECT_EQ(f.not_coverable, f.samples);
    } else {
      EXPECT_EQ(f.coverage, FaceCoverage::Measured) << f.id;
      EXPECT_EQ(f.measured, f.samples) << f.id;
    }
  }
  // Every view once in the path, numbered 1..n in sequence order, and registered or not
  // as the plan's registration says.
  ASSERT_TRUE(plan.sequence && plan.registration);
  ASSERT_EQ(scene.views.size(), plan.views.size());
  ASSERT_EQ(scene.path.size(), plan.sequence->views.size());
  for (std::size_t k = 0; k < scene.path.size(); ++k) {
    const SceneView& v = scene.views[scene.path[k]];
    EXPECT_EQ(v.order, static_cast<int>(k + 1));
    EXPECT_EQ(v.view.id, plan.sequence->views[k]);
  }
  std::size_t measured = 0;
  for (std::size_t i = 0; i < scene.views.size(); ++i) {
    const bool registered = plan.registration->views[i].method != RegistrationMethod::None;
    EXPECT_EQ(scene.views[i].state != ViewState::Unregistrable, registered);
    measured += scene.views[i].measured;
  }
  std::size_t measurements = 0;
  for (const PlannedSample& s : plan.samples) measurements += s.measured_by.size();
  EXPECT_EQ(measured, measurements);
}

TEST(Report, FrustumEndsAtTheFarLimitOfTheDepthOfField) {
  Scanner scanner;  // 400 mm standoff, 200 mm depth of field, 300 x 225 mm field of view
  View view;        // camera at the origin looking along +Z
  const std::array<Vec3, 5> f = frustum(view, scanner);
  EXPECT_TRUE(f[0].isZero());
  const double far = 500, scale = far / 400;
  for (int k = 1; k <= 4; ++k) {
    EXPECT_NEAR(f[k].z(), far, 1e-9);
    EXPECT_NEAR(std::abs(f[k].x()), 150 * scale, 1e-9);
    EXPECT_NEAR(std::abs(f[k].y()), 112.5 * scale, 1e-9);
  }
}

TEST(Report, SamplesPlyRoundTripsWithTheirCoverage) {
  const Plan& plan = cubePlan().plan;
  test::TempDir dir;
  writePly(samplesPly(plan, Frame::World), dir.file("samples.ply"));
  const PlyData data = readPly(dir.file("samples.ply"));
  const std::string path = dir.file("samples.ply");
  const std::vector<double>& x = plyColumn(data, "vertex", "x", path);
  const std::vector<double>& z = plyColumn(data, "vertex", "z", path);
  const std::vector<double>& state = plyColumn(data, "vertex", "scalar_state", path);
  const std::vector<double>& views = plyColumn(data, "vertex", "scalar_views", path);
  const std::vector<double>& face = plyColumn(data, "vertex", "scalar_face", path);
  const std::vector<double>& green = plyColumn(data, "vertex", "green", path);
  ASSERT_EQ(x.size(), plan.samples.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const PlannedSample& s = plan.samples[i];
    EXPECT_NEAR(x[i], s.sample.position.x(), 1e-4);
    EXPECT_NEAR(z[i], s.sample.position.z(), 1e-4);
    EXPECT_EQ(face[i], s.sample.face);
    EXPECT_EQ(views[i], static_cast<double>(s.measured_by.size()));
    EXPECT_EQ(state[i], s.measured_by.empty() ? 2 : 0) << i;  // the cube: measured or not coverable
    EXPECT_EQ(green[i], colour(s.measured_by.empty() ? FaceCoverage::NotMeasured
                                                     : FaceCoverage::Measured)[1]);
  }
  EXPECT_THROW(plyColumn(data, "vertex", "no such", path), InputError);
}

TEST(Report, CloudPlyRoundTripsThroughTheReader) {
  const CubePlan& cube = cubePlan();
  test::TempDir dir;
  const std::vector<PointCloud> clouds =
      viewClouds(cube.plan, cube.part, resolveSpec(cube.part, defaultSpec()), 5);
  ASSERT_EQ(clouds.size(), cube.plan.views.size());
  ASSERT_FALSE(clouds.front().points.empty());
  writePly(clouds.front(), dir.file("one.ply"));
  const PointCloud back = readCloudPly(dir.file("one.ply"));
  ASSERT_EQ(back.points.size(), clouds.front().points.size());
  for (std::size_t i = 0; i < back.points.size(); ++i) {
    EXPECT_LT((back.points[i] - clouds.front().points[i]).norm(), 1e-4);
    EXPECT_EQ(back.faces[i], clouds.front().faces[i]);
    EXPECT_FLOAT_EQ(back.incidence[i], clouds.front().incidence[i]);
  }
  // All clouds in one file, written view by view: the same points, each tagged with its view.
  writeCloudsPly(cube.plan, cube.part, defaultSpec(), 5, Frame::World, dir.file("all.ply"));
  const std::string path = dir.file("all.ply");
  const PlyData all = readPly(path);
  const std::vector<double>& view = plyColumn(all, "vertex", "scalar_view", path);
  const std::vector<double>& x = plyColumn(all, "vertex", "x", path);
  const std::vector<double>& incidence = plyColumn(all, "vertex", "scalar_incidence", path);
  std::size_t at = 0;
  for (std::size_t v = 0; v < clouds.size(); ++v)
    for (std::size_t i = 0; i < clouds[v].points.size(); ++i, ++at) {
      ASSERT_LT(at, view.size());
      EXPECT_EQ(view[at], cube.plan.views[v].id);
      EXPECT_NEAR(x[at], clouds[v].points[i].x(), 1e-4);
      EXPECT_FLOAT_EQ(static_cast<float>(incidence[at]), clouds[v].incidence[i]);
    }
  EXPECT_EQ(at, view.size());
}

TEST(Report, ViewsCsvRoundTripsAndNamesTheBadLine) {
  const Plan& plan = cubePlan().plan;
  test::TempDir dir;
  writeViewsCsv({plan.views, {}, "world", plan.scanner.standoff}, dir.file("views.csv"));
  const std::vector<View> back = readViewsCsv(dir.file("views.csv"));
  ASSERT_EQ(back.size(), plan.views.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].id, plan.views[i].id);
    EXPECT_TRUE(
        back[i].camera_to_world.matrix().isApprox(plan.views[i].camera_to_world.matrix(), 1e-15));
    EXPECT_LT((back[i].target - plan.views[i].target).norm(), 1e-12);
    EXPECT_EQ(back[i].task, plan.views[i].task);
  }
  std::string text = readFile(dir.file("views.csv"));
  text.replace(text.find('\n', text.find('\n') + 1) + 1, 2, "x,");  // the second view's id
  test::writeText(dir.file("bad.csv"), text);
  const std::string bad =
      test::inputError(dir.file("bad.csv"), [&] { readViewsCsv(dir.file("bad.csv")); });
  EXPECT_NE(bad.find("line 3"), std::string::npos) << bad;
  // The setup counts from 1.
  text = readFile(dir.file("views.csv"));
  const std::size_t setup_at = text.find(",1,world,");
  ASSERT_LT(setup_at, text.find('\n', text.find('\n') + 1));  // on the first view's line
  text.replace(setup_at + 1, 1, "0");
  test::writeText(dir.file("setup.csv"), text);
  const std::string setup =
      test::inputError(dir.file("setup.csv"), [&] { readViewsCsv(dir.file("setup.csv")); });
  EXPECT_NE(setup.find("line 2: the setup '0'"), std::string::npos) << setup;
  test::writeText(dir.file("header.csv"), "sequence,id,m00\n1,2,3\n");
  const std::string header =
      test::inputError(dir.file("header.csv"), [&] { readViewsCsv(dir.file("header.csv")); });
  EXPECT_NE(header.find("no column 'task'"), std::string::npos) << header;
  EXPECT_THROW(readViewsCsv(dir.file("missing.csv")), InputError);
}

// The TCP columns against the camera pose they come from, rebuilt by Eigen's own rotations:
// A, B, C as Rz(A) Ry(B) Rx(C) and the quaternion give the camera's rotation, and the TCP
// lies the standoff along the camera's axis.
TEST(Report, ViewsCsvTcpAnglesAndQuaternionRebuildTheCameraPose) {
  const Plan& plan = cubePlan().plan;
  test::TempDir dir;
  std::vector<View> views = plan.views;
  View turned = views.front();  // B near 90 degrees, where A and C share one turn
  turned.camera_to_world.linear() =
      Eigen::AngleAxisd(radians(89.9999), Vec3::UnitY()).toRotationMatrix();
  views.push_back(turned);
  writeViewsCsv({views, {}, "cad", 400}, dir.file("views.csv"));
  std::ifstream in(dir.file("views.csv"));
  std::string line;
  std::getline(in, line);
  std::map<std::string, std::size_t> column;
  std::istringstream names(line);
  for (std::string name; std::getline(names, name, ',');) column.emplace(name, column.size());
  for (const View& view : views) {
    ASSERT_TRUE(std::getline(in, line));
    std::vector<std::string> fields;
    std::istringstream row(line);
    for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
    auto at = [&](const char* name) { return std::stod(fields.at(column.at(name))); };
    EXPECT_EQ(fields.at(column.at("frame")), "cad");
    const Eigen::Matrix3d abc = (Eigen::AngleAxisd(radians(at("tcp_a")), Vec3::UnitZ()) *
                                 Eigen::AngleAxisd(radians(at("tcp_b")), Vec3::UnitY()) *
                                 Eigen::AngleAxisd(radians(at("tcp_c")), Vec3::UnitX()))
                                    .toRotationMatrix();
    const Eigen::Quaterniond q(at("tcp_qw"), at("tcp_qx"), at("tcp_qy"), at("tcp_qz"));
    const Eigen::Matrix3d& r = view.camera_to_world.linear();
    EXPECT_LT((abc - r).norm(), 1e-9);
    EXPECT_NEAR(q.norm(), 1, 1e-12);
    EXPECT_GE(q.w(), 0);
    EXPECT_LT((q.toRotationMatrix() - r).norm(), 1e-12);
    const Vec3 tcp(at("tcp_x"), at("tcp_y"), at("tcp_z"));
    EXPECT_LT((tcp - (view.camera() + 400 * r.col(2))).norm(), 1e-9);
  }
}

// The GLB container and its JSON: every index and byte range within bounds (glTF 2.0,
// section "GLB File Format Specification" and the accessor rules).
TEST(Report, GlbIsStructurallyValid) {
  const CubePlan& cube = cubePlan();
  const PlanScene scene = planScene(cube.plan, cube.part);
  test::TempDir dir;
  writeGlb(scene, dir.file("plan.glb"));
  const std::string bytes = readFile(dir.file("plan.glb"));
  auto u32 = [&](std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  ASSERT_GE(bytes.size(), 28u);
  EXPECT_EQ(u32(0), 0x46546C67u);  // "glTF"
  EXPECT_EQ(u32(4), 2u);
  EXPECT_EQ(u32(8), bytes.size());
  const std::uint32_t json_length = u32(12);
  EXPECT_EQ(u32(16), 0x4E4F534Au);  // "JSON"
  EXPECT_EQ(json_length % 4, 0u);
  const json gltf = json::parse(bytes.substr(20, json_length));
  const std::size_t bin_at = 20 + json_length;
  ASSERT_GE(bytes.size(), bin_at + 8);
  const std::uint32_t bin_length = u32(bin_at);
  EXPECT_EQ(u32(bin_at + 4), 0x004E4942u);  // "BIN\0"
  EXPECT_EQ(bin_at + 8 + bin_length, bytes.size());

  ASSERT_EQ(gltf["buffers"].size(), 1u);
  EXPECT_LE(gltf["buffers"][0]["byteLength"].get<std::size_t>(), bin_length);
  const json& views = gltf["bufferViews"];
  for (const json& v : views)
    EXPECT_LE(v.value("byteOffset", 0u) + v["byteLength"].get<std::size_t>(),
              gltf["buffers"][0]["byteLength"].get<std::size_t>());
  auto component_size = [](int type) {
    return type == 5126 || type == 5125 ? 4 : type == 5121 ? 1 : 2;
  };
  auto components = [](const std::string& type) {
    return type == "VEC3" ? 3 : type == "VEC4" ? 4 : 1;
  };
  for (const json& a : gltf["accessors"]) {
    const std::size_t view = a["bufferView"];
    ASSERT_LT(view, views.size());
    const std::size_t size =
        a["count"].get<std::size_t>() * component_size(a["componentType"]) * components(a["type"]);
    EXPECT_LE(a.value("byteOffset", 0u) + size, views[view]["byteLength"].get<std::size_t>());
  }
  std::size_t part_vertices = 0;
  for (const json& mesh : gltf["meshes"])
    for (const json& primitive : mesh["primitives"]) {
      for (const auto& [name, accessor] : primitive["attributes"].items())
        ASSERT_LT(accessor.get<std::size_t>(), gltf["accessors"].size()) << name;
      const json& position =
          gltf["accessors"][primitive["attributes"]["POSITION"].get<std::size_t>()];
      EXPECT_TRUE(position.contains("min") && position.contains("max"));
      ASSERT_LT(primitive["material"].get<std::size_t>(), gltf["materials"].size());
      if (mesh["name"] == "part, coloured by coverage") part_vertices = position["count"];
    }
  EXPECT_EQ(part_vertices, 3 * cube.part.mesh.triangles.size());
  for (const json& node : gltf["nodes"]) {
    if (node.contains("mesh")) {
      EXPECT_LT(node["mesh"].get<std::size_t>(), gltf["meshes"].size());
    }
    for (const json& child : node.value("children", json::array()))
      EXPECT_LT(child.get<std::size_t>(), gltf["nodes"].size());
  }
  // And tinygltf's own loader reads it without an error.
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, dir.file("plan.glb"))) << error;
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_EQ(model.meshes.size(), gltf["meshes"].size());
}

// Each view is a node with a glTF camera (glTF 2.0, "Cameras": the camera looks along the
// node's -Z with +Y up) that looks along the view, with the scanner's field of view.
TEST(Report, GlbHasACameraPerViewLookingAlongIt) {
  const CubePlan& cube = cubePlan();
  const PlanScene scene = planScene(cube.plan, cube.part);
  test::TempDir dir;
  writeGlb(scene, dir.file("plan.glb"));
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, dir.file("plan.glb"))) << error;
  ASSERT_EQ(model.cameras.size(), scene.views.size());
  std::size_t seen = 0;
  for (const tinygltf::Node& node : model.nodes) {
    if (node.camera < 0) continue;
    const SceneView& v = scene.views.at(seen++);
    const Eigen::Quaterniond q(node.rotation[3], node.rotation[0], node.rotation[1],
                               node.rotation[2]);
    const Eigen::Matrix3d& r = v.view.camera_to_world.linear();
    EXPECT_LT((q * Vec3(0, 0, -1) - r.col(2)).norm(), 1e-9);  // looks along the view
    EXPECT_LT((q * Vec3(0, 1, 0) + r.col(1)).norm(), 1e-9);   // up is the image's -y
    EXPECT_LT(
        (Vec3(node.translation[0], node.translation[1], node.translation[2]) - v.view.camera())
            .norm(),
        1e-9);
    const tinygltf::PerspectiveCamera& lens = model.cameras[node.camera].perspective;
    EXPECT_NEAR(std::tan(lens.yfov / 2) * cube.plan.scanner.standoff,
                cube.plan.scanner.fov_height / 2, 1e-9);
    EXPECT_NEAR(lens.aspectRatio * std::tan(lens.yfov / 2) * cube.plan.scanner.standoff,
                cube.plan.scanner.fov_width / 2, 1e-9);
    EXPECT_GE(node.mesh, 0);  // and its frustum
  }
  EXPECT_EQ(seen, scene.views.size());
}

TEST(Report, PictureShowsThePartInItsCoverageColours) {
  const CubePlan& cube = cubePlan();
  const Image image = renderScene(planScene(cube.plan, cube.part), 320, 240);
  ASSERT_EQ(image.rgb.size(), 320u * 240 * 3);
  // Shades of the measured green (its channels in the same ratio) and of the background.
  const Rgb green = colour(FaceCoverage::Measured);
  std::size_t measured = 0, background = 0;
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) {
    const double r = image.rgb[i], g = image.rgb[i + 1], b = image.rgb[i + 2];
    if (g > 40 && std::abs(r / g - green[0] / double(green[1])) < 0.03 &&
        std::abs(b / g - green[2] / double(green[1])) < 0.03)
      ++measured;
    if (r == g && g == b && r > 200) ++background;
  }
  const double pixels = 320.0 * 240;
  // Framed on the part, the cube's measured faces take 31 % of the picture; framed on the
  // part and every camera, as it was, they took 1.8 %.
  EXPECT_GT(static_cast<double>(measured) / pixels, 0.1);
  EXPECT_GT(static_cast<double>(background) / pixels, 0.3);
  test::TempDir dir;
  writePng(image, dir.file("plan.png"));
  const Image back = readPng(dir.file("plan.png"));
  EXPECT_EQ(back.width, 320);
  EXPECT_EQ(back.height, 240);
  EXPECT_EQ(back.rgb, image.rgb);
  EXPECT_THROW(readPng(dir.file("missing.png")), InputError);
}

TEST(Report, PageIsOneFileWithThePlansData) {
  const CubePlan& cube = cubePlan();
  test::TempDir dir;
  writeReport(cube.plan, cube.part, defaultSpec(), dir.file("report.html"));
  const std::string page = readFile(dir.file("report.html"));
  // Nothing fetched from elsewhere.
  for (const char* outside : {"src=\"http", "href=\"http", "<link", "src=\"//"})
    EXPECT_EQ(page.find(outside), std::string::npos) << outside;
  const std::string open = R"(<script type="application/json" id="scanplan-data">)";
  const std::size_t begin = page.find(open);
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = page.find("</script>", begin);
  const json data = json::parse(page.substr(begin + open.size(), end - begin - open.size()));
  EXPECT_EQ(data["views"].size(), cube.plan.views.size());
  EXPECT_EQ(data["plan"]["summary"]["views"], cube.plan.views.size());
  EXPECT_EQ(data["faces"].size(), 6u);
  EXPECT_EQ(data["samples"]["count"], cube.plan.samples.size());
  // Base64 of 3 floats per vertex.
  EXPECT_EQ(data["mesh"]["positions"].get<std::string>().size(),
            (cube.part.mesh.vertices.size() * 12 + 2) / 3 * 4);
  ASSERT_FALSE(data["clusters"].empty());
  for (const json& c : data["clusters"])
    EXPECT_EQ(c["cvm"].get<std::string>().size(),
              (c["azimuths"].get<std::size_t>() * c["elevations"].get<std::size_t>() + 2) / 3 * 4);
  for (const json& v : data["views"]) EXPECT_GT(v["cloud"]["points"].get<int>(), 0);
  // The viewer is inlined.
  EXPECT_NE(page.find("scanplan-data"), page.rfind("scanplan-data"));
  EXPECT_GT(page.size(), 400000u);
}

std::vector<std::uint32_t> decodeUInt32s(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes;
  unsigned bits = 0, count = 0;
  for (char c : text) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<unsigned>(alphabet.find(c));
    if ((count += 6) >= 8) bytes.push_back(static_cast<char>((bits >> (count -= 8)) & 0xff));
  }
  std::vector<std::uint32_t> values(bytes.size() / 4);
  std::memcpy(values.data(), bytes.data(), values.size() * 4);
  return values;
}

// The report's visibility maps are those of the planner's first round: its clusters hold
// exactly the samples the planner said it clustered then (the sweep of the plate's top
// took the others), each once.
TEST(Report, ClustersAreThoseOfThePlannersFirstRound) {
  test::TempDir dir;
  BRepTools::Write(BRepPrimAPI_MakeBox(1000, 600, 10).Shape(), dir.file("plate.brep").c_str());
  const Part part = importPart(dir.file("plate.brep"));
  const int top = test::topFace(part);
  test::writeText(dir.file("spec.yaml"),
                  "planner: {anchors: 50, selection_nodes: 20}\ntasks:\n"
                  "  - {type: gdt, faces: [" +
                      std::to_string(top) + "]}\n  - {type: global}\n");
  const Spec spec = loadSpec(dir.file("spec.yaml"));
  std::size_t first_round = 0;
  const Progress progress = [&](std::string_view stage, double) {
    const std::string_view round = "planning views, round 1 (";
    if (stage.starts_with(round)) first_round = std::stoul(std::string(stage.substr(round.size())));
  };
  const Plan plan = planViews(part, spec, PlanningOptions{.registration = false}, progress);
  ASSERT_FALSE(plan.sweeps.empty());
  ASSERT_GT(first_round, 0u);
  ASSERT_LT(first_round, plan.samples.size());
  ReportOptions options;
  options.clouds = false;
  writeReport(plan, part, spec, dir.file("report.html"), options);
  const std::string page = readFile(dir.file("report.html"));
  const std::string open = R"(<script type="application/json" id="scanplan-data">)";
  const std::size_t begin = page.find(open) + open.size();
  const json data = json::parse(page.substr(begin, page.find("</script>", begin) - begin));
  std::set<std::uint32_t> members;
  std::size_t total = 0;
  for (const json& c : data["clusters"]) {
    const auto mine = decodeUInt32s(c["members"].get<std::string>());
    EXPECT_EQ(mine.size(), c["samples"].get<std::size_t>());
    total += mine.size();
    members.insert(mine.begin(), mine.end());
  }
  EXPECT_EQ(total, first_round);
  EXPECT_EQ(members.size(), first_round);
  for (std::uint32_t i : members) {
    ASSERT_LT(i, plan.samples.size());
    for (int id : plan.samples[i].measured_by)
      for (const Sweep& sweep : plan.sweeps)
        EXPECT_EQ(std::count(sweep.views.begin(), sweep.views.end(), id), 0) << i;
  }
}

TEST(Report, PlanReadBackKeepsWhySamplesCannotBeCovered) {
  const Plan& plan = cubePlan().plan;
  test::TempDir dir;
  writePlan(plan, dir.file("plan.json"));
  const Plan back = readPlan(dir.file("plan.json"));
  ASSERT_EQ(back.samples.size(), plan.samples.size());
  EXPECT_GT(plan.notCoverableCount(), 0u);
  for (std::size_t i = 0; i < back.samples.size(); ++i)
    EXPECT_EQ(back.samples[i].uncoverable, plan.samples[i].uncoverable) << i;
  // And, for a sample lost in the simulation, the test that lost it.
  Plan lost = plan;
  lost.samples[0].uncoverable = Uncoverable::Lost;
  lost.samples[0].last_loss = Loss::ProjectorOccluded;
  writePlan(lost, dir.file("lost.json"));
  EXPECT_EQ(readPlan(dir.file("lost.json")).samples[0].last_loss, Loss::ProjectorOccluded);
}

}  // namespace
}  // namespace scanplan
