// A still picture of a plan's scene: one Embree primary ray per pixel for the part, Lambert
// shading under a head light, then the frusta, the path and the markers drawn over it with
// a depth test against the part, and the views' sequence numbers (stb_easy_font).

#include <scanplan/cad/raycast.h>
#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/core/input_file.h>
#include <scanplan/report/exports.h>

#include <stb_easy_font.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

namespace scanplan {
namespace {

class Canvas {
 public:
  // Looks from the front-right and above at `points`, near enough that all of them fill
  // the 40° view with a margin.
  Canvas(const std::vector<Vec3>& points, int width, int height) : image_{width, height, {}} {
    image_.rgb.assign(static_cast<std::size_t>(width) * height * 3, 0);
    depth_.assign(static_cast<std::size_t>(width) * height,
                  std::numeric_limits<double>::infinity());
    forward_ = Vec3(-0.55, 0.75, -0.55).normalized();
    right_ = forward_.cross(Vec3::UnitZ()).normalized();
    up_ = right_.cross(forward_);
    const double half_fov = radians(20);
    focal_ = std::min(width, height) / 2.0 / std::tan(half_fov);
    const double tan_x = 0.92 * width / 2.0 / focal_, tan_y = 0.92 * height / 2.0 / focal_;
    Box box;
    for (const Vec3& p : points) box.add(p);
    const Vec3 centre = box.center();
    double distance = 1;
    for (const Vec3& p : points) {
      const Vec3 d = p - centre;
      const double z = d.dot(forward_);
      distance = std::max(
          {distance, std::abs(d.dot(right_)) / tan_x - z, std::abs(d.dot(up_)) / tan_y - z});
    }
    eye_ = centre - forward_ * distance;
  }

  void box(int x0, int y0, int size, const Rgb& c) {
    for (int y = y0; y < y0 + size && y < image_.height; ++y)
      for (int x = x0; x < x0 + size && x < image_.width; ++x)
        set(static_cast<std::size_t>(y) * image_.width + x, c);
  }

  Ray ray(int x, int y) const {
    const Vec3 d = forward_ + (x + 0.5 - image_.width / 2.0) / focal_ * right_ -
                   (y + 0.5 - image_.height / 2.0) / focal_ * up_;
    return {eye_, d.normalized(), 0, std::numeric_limits<double>::infinity()};
  }

  // The part and the fixtures, shaded; the background a light grey gradient.
  void drawPart(const PlanScene& scene) {
    std::vector<Ray> rays;
    rays.reserve(depth_.size());
    for (int y = 0; y < image_.height; ++y)
      for (int x = 0; x < image_.width; ++x) rays.push_back(ray(x, y));
    TriangleMesh mesh = scene.mesh;
    mesh.append(scene.fixtures, 0);
    std::vector<std::optional<RayHit>> hits;
    if (!mesh.empty()) hits = RayCaster(mesh).intersect(rays);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const int y = static_cast<int>(i) / image_.width;
      if (hits.empty() || !hits[i]) {
        const auto shade = static_cast<std::uint8_t>(245 - 25.0 * y / image_.height);
        set(i, {shade, shade, shade});
        continue;
      }
      const RayHit& hit = *hits[i];
      depth_[i] = hit.t;
      const Rgb colour_of_face = faceColour(scene, hit.face);
      const double light = 0.35 + 0.65 * std::abs(hit.normal.dot(rays[i].direction));
      set(i, {static_cast<std::uint8_t>(colour_of_face[0] * light),
              static_cast<std::uint8_t>(colour_of_face[1] * light),
              static_cast<std::uint8_t>(colour_of_face[2] * light)});
    }
  }

  // A segment, hidden where the part is in front of it.
  void line(const Vec3& a, const Vec3& b, const Rgb& c, int thickness = 1) {
    Eigen::Vector2d pa, pb;
    if (!project(a, pa) || !project(b, pb)) return;
    const int steps = std::max(1, static_cast<int>(2 * (pb - pa).norm()));
    for (int s = 0; s <= steps; ++s) {
      const double t = static_cast<double>(s) / steps;
      dot(a + t * (b - a), c, thickness);
    }
  }

  void dot(const Vec3& p, const Rgb& c, int radius) {
    Eigen::Vector2d q;
    if (!project(p, q)) return;
    const double distance = (p - eye_).norm();
    for (int dy = -radius / 2; dy <= radius / 2; ++dy)
      for (int dx = -radius / 2; dx <= radius / 2; ++dx) {
        const int x = static_cast<int>(q.x()) + dx, y = static_cast<int>(q.y()) + dy;
        if (x < 0 || y < 0 || x >= image_.width || y >= image_.height) continue;
        const std::size_t i = static_cast<std::size_t>(y) * image_.width + x;
        if (distance <= depth_[i] * 1.001) set(i, c);
      }
  }

  // Text with its top left corner at the projection of `p` (stb_easy_font's quads).
  void text(const Vec3& p, const std::string& s, const Rgb& c) {
    Eigen::Vector2d q;
    if (!project(p, q)) return;
    text(static_cast<int>(q.x()) + 4, static_cast<int>(q.y()) - 10, s, c, 1);
  }

  void text(int x0, int y0, const std::string& s, const Rgb& c, int scale) {
    std::vector<float> quads(static_cast<std::size_t>(s.size()) * 270 + 16);
    std::string copy = s;
    unsigned char rgba[4] = {c[0], c[1], c[2], 255};
    const int n = stb_easy_font_print(0, 0, copy.data(), rgba, quads.data(),
                                      static_cast<int>(quads.size() * sizeof(float)));
    for (int q = 0; q < n; ++q) {
      const float* v = &quads[static_cast<std::size_t>(q) * 16];  // 4 vertices x y z colour
      const int x1 = x0 + scale * static_cast<int>(v[0]), y1 = y0 + scale * static_cast<int>(v[1]);
      const int x2 = x0 + scale * static_cast<int>(v[8]), y2 = y0 + scale * static_cast<int>(v[9]);
      for (int y = y1; y < y2; ++y)
        for (int x = x1; x < x2; ++x)
          if (x >= 0 && y >= 0 && x < image_.width && y < image_.height)
            set(static_cast<std::size_t>(y) * image_.width + x, c);
    }
  }

  Image take() { return std::move(image_); }

 private:
  bool project(const Vec3& p, Eigen::Vector2d& q) const {
    const Vec3 d = p - eye_;
    const double z = d.dot(forward_);
    if (z <= 1e-9) return false;
    q = {image_.width / 2.0 + focal_ * d.dot(right_) / z,
         image_.height / 2.0 - focal_ * d.dot(up_) / z};
    return true;
  }

  void set(std::size_t i, const Rgb& c) { std::copy(c.begin(), c.end(), &image_.rgb[3 * i]); }

  Image image_;
  std::vector<double> depth_;  // distance from the eye to the part per pixel
  Vec3 eye_, forward_, right_, up_;
  double focal_ = 1;
};

}  // namespace

Image renderScene(const PlanScene& scene, int width, int height) {
  // Views are drawn as small pyramids (a quarter of the frustum), so that the part stays
  // visible under many of them.
  auto cone = [&](const View& view) {
    std::array<Vec3, 5> f = frustum(view, scene.scanner);
    for (int k = 1; k <= 4; ++k) f[k] = f[0] + 0.25 * (f[k] - f[0]);
    return f;
  };
  // Framed on the part (its fixtures with it): views far from it fall outside the picture
  // rather than leave the part small among them.
  std::vector<Vec3> points = scene.mesh.vertices;
  points.insert(points.end(), scene.fixtures.vertices.begin(), scene.fixtures.vertices.end());
  Canvas canvas(points, width, height);
  canvas.drawPart(scene);
  const std::vector<Vec3> outlines = priorityOutlines(scene);
  for (std::size_t i = 0; i + 1 < outlines.size(); i += 2)
    canvas.line(outlines[i], outlines[i + 1], {20, 20, 20});
  for (std::size_t k = 1; k < scene.path.size(); ++k)
    canvas.line(scene.views[scene.path[k - 1]].view.camera(),
                scene.views[scene.path[k]].view.camera(), kPathColour, 2);
  for (const SceneView& v : scene.views) {
    const std::array<Vec3, 5> f = cone(v.view);
    for (int k = 1; k <= 4; ++k) {
      canvas.line(f[0], f[k], colour(v.state));
      canvas.line(f[k], f[k % 4 + 1], colour(v.state));
    }
  }
  for (const SceneView& v : scene.views)
    canvas.text(v.view.camera(), std::to_string(v.order > 0 ? v.order : v.view.id), {0, 0, 0});
  for (const Vec3& m : scene.markers) canvas.dot(m, kMarkerColour, 3);
  const int row = 22;
  int y = 12;
  auto legend = [&](const Rgb& c, const std::string& label) {
    canvas.box(12, y + 1, 12, c);
    canvas.text(32, y, label, {30, 30, 30}, 2);
    y += row;
  };
  for (FaceCoverage c : {FaceCoverage::Measured, FaceCoverage::Partly, FaceCoverage::NotMeasured,
                         FaceCoverage::NotTarget})
    legend(colour(c), "face " + std::string(toString(c)));
  if (!scene.fixtures.empty()) legend(kFixtureColour, "fixture");
  for (ViewState s : {ViewState::Registered, ViewState::Bridge, ViewState::Unregistrable})
    legend(colour(s), "view " + std::string(toString(s)));
  legend(kPathColour, "path");
  if (!scene.markers.empty()) legend(kMarkerColour, "markers");
  return canvas.take();
}

void writePng(const Image& image, const std::string& path) {
  std::string bytes;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.rgb.data(),
                              image.width * 3))
    throw OutputError(path, "cannot encode the PNG image");
  writeFileAtomically(path, [&](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

Image readPng(const std::string& path) {
  requireInputFile(path);
  int width = 0, height = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
  if (data == nullptr)
    throw InputError(path, std::string("not a readable image: ") + stbi_failure_reason());
  Image image{width, height,
              std::vector<std::uint8_t>(data, data + static_cast<std::size_t>(width) * height * 3)};
  stbi_image_free(data);
  return image;
}

}  // namespace scanplan
