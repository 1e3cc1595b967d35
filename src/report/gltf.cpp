// The plan's scene as glTF 2.0 binary (tinygltf): one buffer, a node per kind of thing and
// per view. glTF is metres and Y up; the scene is written in mm, Z up, under a root node
// that scales by 0.001 and turns Z up into Y up, so that viewers show it upright and to
// size.

#include <scanplan/core/atomic_file.h>
#include <scanplan/report/exports.h>

#include <fmt/format.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <tuple>

namespace scanplan {
namespace {

class GlbBuilder {
 public:
  // Appends float VEC3 positions (and optional unsigned-byte normalized colours) as a
  // primitive of `mode` with its own material.
  void addMesh(const std::string& name, const std::vector<Vec3>& positions,
               const std::vector<Rgb>& colours, int mode, const Rgb& base, bool lit) {
    if (positions.empty()) return;
    tinygltf::Node node;
    node.name = name;
    node.mesh = mesh(name, positions, colours, mode, material(name, base, lit));
    model_.nodes.push_back(node);
    children_.push_back(static_cast<int>(model_.nodes.size() - 1));
  }

  // A view's node: at the camera, turned so that the node's -Z looks along the view and its
  // +Y is the image's up (glTF's camera convention), holding the view's glTF camera and its
  // frustum drawn as lines in `colour`.
  void addViewNode(const std::string& name, const View& view, const Scanner& scanner,
                   ViewState state) {
    // From the scanner frame S (x right, y down, z ahead) to glTF's camera frame.
    const Eigen::Matrix3d flip = Eigen::Vector3d(1, -1, -1).asDiagonal();
    const Pose to_local =
        Pose(view.camera_to_world.linear() * flip).inverse() * Eigen::Translation3d(-view.camera());
    const std::array<Vec3, 5> f = frustum(view, scanner);
    std::vector<Vec3> lines;
    for (int k = 1; k <= 4; ++k)
      for (const Vec3& p : {f[0], f[k], f[k], f[k % 4 + 1]}) lines.push_back(to_local * p);
    tinygltf::Camera camera;
    camera.type = "perspective";
    camera.name = name;
    camera.perspective.yfov = 2 * std::atan(scanner.fov_height / 2 / scanner.standoff);
    camera.perspective.aspectRatio = scanner.fov_width / scanner.fov_height;
    camera.perspective.znear = (scanner.standoff - scanner.depth_of_field / 2) / 1000;  // m
    camera.perspective.zfar = (scanner.standoff + scanner.depth_of_field / 2) / 1000;
    model_.cameras.push_back(camera);
    tinygltf::Node node;
    node.name = name;
    node.camera = static_cast<int>(model_.cameras.size() - 1);
    node.mesh = mesh(name, lines, {}, TINYGLTF_MODE_LINE,
                     material("view, " + std::string(toString(state)), colour(state), false));
    const Vec3 at = view.camera();
    node.translation = {at.x(), at.y(), at.z()};
    const Eigen::Quaterniond q(view.camera_to_world.linear() * flip);
    node.rotation = {q.x(), q.y(), q.z(), q.w()};
    model_.nodes.push_back(node);
    children_.push_back(static_cast<int>(model_.nodes.size() - 1));
  }

  void write(const std::string& path) {
    tinygltf::Node root;
    root.name = "scanplan plan (mm, Z up)";
    root.scale = {0.001, 0.001, 0.001};
    root.rotation = {-0.7071067811865476, 0, 0, 0.7071067811865476};  // Z up to Y up
    root.children = children_;
    model_.nodes.push_back(root);
    tinygltf::Scene scene;
    scene.nodes = {static_cast<int>(model_.nodes.size() - 1)};
    model_.scenes.push_back(scene);
    model_.defaultScene = 0;
    model_.asset.version = "2.0";
    model_.asset.generator = "scanplan";
    model_.buffers.push_back(buffer_);
    writeFileAtomically(path, [&](std::ostream& out) {
      tinygltf::TinyGLTF writer;
      if (!writer.WriteGltfSceneToStream(&model_, out, false, true))
        throw std::runtime_error("tinygltf could not write the scene");
    });
  }

 private:
  int mesh(const std::string& name, const std::vector<Vec3>& positions,
           const std::vector<Rgb>& colours, int mode, int material) {
    tinygltf::Primitive primitive;
    primitive.mode = mode;
    primitive.attributes["POSITION"] = addPositions(positions);
    if (!colours.empty()) primitive.attributes["COLOR_0"] = addColours(colours);
    primitive.material = material;
    tinygltf::Mesh mesh;
    mesh.name = name;
    mesh.primitives.push_back(primitive);
    model_.meshes.push_back(mesh);
    return static_cast<int>(model_.meshes.size() - 1);
  }

  int addView(const void* data, std::size_t bytes, int target) {
    while (buffer_.data.size() % 4 != 0) buffer_.data.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer_.data.size();
    view.byteLength = bytes;
    view.target = target;
    const auto* begin = static_cast<const unsigned char*>(data);
    buffer_.data.insert(buffer_.data.end(), begin, begin + bytes);
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size() - 1);
  }

  int addPositions(const std::vector<Vec3>& positions) {
    std::vector<float> values;
    values.reserve(positions.size() * 3);
    Box box;
    for (const Vec3& p : positions) {
      box.add(p.cast<float>().cast<double>());
      for (int k = 0; k < 3; ++k) values.push_back(static_cast<float>(p[k]));
    }
    tinygltf::Accessor accessor;
    accessor.bufferView =
        addView(values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    accessor.type = TINYGLTF_TYPE_VEC3;
    accessor.count = positions.size();
    accessor.minValues = {box.min.x(), box.min.y(), box.min.z()};
    accessor.maxValues = {box.max.x(), box.max.y(), box.max.z()};
    model_.accessors.push_back(accessor);
    return static_cast<int>(model_.accessors.size() - 1);
  }

  int addColours(const std::vector<Rgb>& colours) {
    std::vector<std::uint8_t> values;
    values.reserve(colours.size() * 4);
    for (const Rgb& c : colours) values.insert(values.end(), {c[0], c[1], c[2], 255});
    tinygltf::Accessor accessor;
    accessor.bufferView = addView(values.data(), values.size(), TINYGLTF_TARGET_ARRAY_BUFFER);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    accessor.normalized = true;
    accessor.type = TINYGLTF_TYPE_VEC4;
    accessor.count = colours.size();
    model_.accessors.push_back(accessor);
    return static_cast<int>(model_.accessors.size() - 1);
  }

  // The material of that colour and lighting, made once under the first name given.
  int material(const std::string& name, const Rgb& base, bool lit) {
    const auto [at, added] =
        materials_.try_emplace({base, lit}, static_cast<int>(model_.materials.size()));
    if (!added) return at->second;
    tinygltf::Material m;
    m.name = name;
    m.pbrMetallicRoughness.baseColorFactor = {base[0] / 255.0, base[1] / 255.0, base[2] / 255.0,
                                              1.0};
    m.pbrMetallicRoughness.metallicFactor = 0;
    m.pbrMetallicRoughness.roughnessFactor = 0.8;
    m.doubleSided = true;
    if (!lit) m.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
    model_.materials.push_back(m);
    if (!lit && std::find(model_.extensionsUsed.begin(), model_.extensionsUsed.end(),
                          "KHR_materials_unlit") == model_.extensionsUsed.end())
      model_.extensionsUsed.push_back("KHR_materials_unlit");
    return at->second;
  }

  tinygltf::Model model_;
  std::map<std::pair<Rgb, bool>, int> materials_;
  tinygltf::Buffer buffer_;
  std::vector<int> children_;
};

}  // namespace

void writeGlb(const PlanScene& scene, const std::string& path) {
  GlbBuilder glb;
  std::vector<Vec3> triangles;
  std::vector<Rgb> colours;
  const TriangleMesh& mesh = scene.mesh;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Rgb c = faceColour(scene, mesh.triangle_faces[t]);
    for (int k = 0; k < 3; ++k) {
      triangles.push_back(mesh.vertices[mesh.triangles[t][k]]);
      colours.push_back(c);
    }
  }
  glb.addMesh("part, coloured by coverage", triangles, colours, TINYGLTF_MODE_TRIANGLES,
              {255, 255, 255}, true);
  glb.addMesh("priority faces", priorityOutlines(scene), {}, TINYGLTF_MODE_LINE, {0, 0, 0}, false);
  std::vector<Vec3> fixtures;  // none: addMesh adds nothing
  for (const Vec3i& t : scene.fixtures.triangles)
    for (int k = 0; k < 3; ++k) fixtures.push_back(scene.fixtures.vertices[t[k]]);
  glb.addMesh("fixtures", fixtures, {}, TINYGLTF_MODE_TRIANGLES, kFixtureColour, true);

  for (const SceneView& v : scene.views)
    glb.addViewNode(v.order > 0 ? fmt::format("view {} (id {})", v.order, v.view.id)
                                : fmt::format("view id {}", v.view.id),
                    v.view, scene.scanner, v.state);
  std::vector<Vec3> route;
  for (int i : scene.path) route.push_back(scene.views[i].view.camera());
  glb.addMesh("path", route, {}, TINYGLTF_MODE_LINE_STRIP, kPathColour, false);
  glb.addMesh("markers", scene.markers, {}, TINYGLTF_MODE_POINTS, kMarkerColour, false);
  glb.write(path);
}

}  // namespace scanplan
