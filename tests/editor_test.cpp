// The spec editor's page: its data checked against the part it was written for (the exact
// surfaces the page snaps points onto, the rest orientations, the characteristics) and
// against the spec it starts from. tests/editor_browser_test.sh drives the page itself.

#include "support.h"

#include <scanplan/cad/import.h>
#include <scanplan/cad/localization.h>
#include <scanplan/core/errors.h>
#include <scanplan/editor/editor.h>
#include <scanplan/report/report.h>

#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepTools.hxx>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace scanplan {
namespace {

using json = nlohmann::ordered_json;  // to see the order the page keeps

// The data the page carries, read back from the written file.
json pageData(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string page = text.str();
  const std::string open = R"(<script type="application/json" id="scanplan-data">)";
  const std::size_t begin = page.find(open) + open.size();
  std::string data = page.substr(begin, page.find("</script>", begin) - begin);
  for (std::size_t at = data.find("<\\/"); at != std::string::npos; at = data.find("<\\/", at))
    data.erase(at + 1, 1);
  return json::parse(data);
}

Vec3 vec(const json& v) { return Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>()); }

// How far `p` lies off the elementary surface `s` as the page describes it, mm.
double offSurface(const json& s, const Vec3& p) {
  const Vec3 o = vec(s["origin"]), v = p - o;
  const std::string type = s["type"];
  const double r = s.value("radius", 0.0);  // planes have none
  if (type == "plane") return std::abs(v.dot(vec(s["axis"])));
  if (type == "sphere") return std::abs(v.norm() - r);
  const Vec3 axis = vec(s["axis"]);
  const double h = v.dot(axis), across = (v - h * axis).norm();
  if (type == "cylinder") return std::abs(across - r);
  if (type == "cone")
    return std::abs(across - (r + h * std::tan(s["semi_angle"].get<double>()))) *
           std::cos(s["semi_angle"].get<double>());
  if (type == "torus") return std::abs(std::hypot(across - r, h) - s["minor_radius"].get<double>());
  ADD_FAILURE() << "unknown surface " << type;
  return 0;
}

// Every vertex of the mesh lies on its face's exact surface, so each face's description
// must hold all the vertices of its triangles.
TEST(SpecEditor, EachFacesSurfaceHoldsItsVertices) {
  const Part part = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  test::TempDir dir;
  writeSpecEditor(part, "", dir.file("editor.html"));
  const json data = pageData(dir.file("editor.html"));
  ASSERT_EQ(data["faces"].size(), part.faces.size());
  std::set<std::string> types;
  for (const Face& face : part.faces) {
    const json& surface = data["faces"][face.id - 1]["surface"];
    const bool elementary = face.type == SurfaceType::Plane || face.type == SurfaceType::Cylinder ||
                            face.type == SurfaceType::Cone || face.type == SurfaceType::Sphere ||
                            face.type == SurfaceType::Torus;
    ASSERT_EQ(surface.is_object(), elementary) << "face " << face.id;
    if (!elementary) continue;
    types.insert(surface["type"]);
    double worst = 0;
    for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t)
      for (int k = 0; k < 3; ++k)
        worst = std::max(worst, offSurface(surface, part.mesh.vertices[part.mesh.triangles[t][k]]));
    EXPECT_LT(worst, 1e-5) << "face " << face.id << " (" << surface["type"] << ")";
    if (surface["type"] == "plane") {  // outward, as the mesh's triangles
      EXPECT_GT(vec(surface["axis"]).dot(part.mesh.normal(face.first_triangle)), 0.999);
    }
  }
  EXPECT_TRUE(types.count("plane") && types.count("cylinder")) << types.size();
  EXPECT_EQ(data["characteristics"].size(), characteristics(part.gdt).size());
}

// A box rests on each of its six faces; the page names the face of each orientation.
TEST(SpecEditor, ABoxRestsOnEachOfItsFaces) {
  test::TempDir dir;
  BRepTools::Write(BRepPrimAPI_MakeBox(100, 60, 40).Shape(), dir.file("box.brep").c_str());
  const Part part = importPart(dir.file("box.brep"));
  writeSpecEditor(part, "", dir.file("editor.html"));
  const json rests = pageData(dir.file("editor.html"))["rests"];
  ASSERT_EQ(rests.size(), 6u);
  std::set<int> faces;
  for (const json& r : rests) {
    const int face = r["face"];
    ASSERT_GT(face, 0);
    faces.insert(face);
    EXPECT_GT(part.mesh.normal(part.faces[face - 1].first_triangle).dot(vec(r["down"])), 0.999999);
    // part.rest: <face> gives this orientation back.
    EXPECT_GT(restOnFace(part, face, "spec").down.dot(vec(r["down"])), 1 - 1e-9);
  }
  EXPECT_EQ(faces.size(), 6u);
  // Steadiest first: standing on a 100 x 60 face.
  EXPECT_NEAR(rests[0]["contact_area"].get<double>(), 6000, 1e-6);
}

// A face name from the CAD file that closes the data's element or opens an HTML comment
// stays text: the page holds one data element, no '<' in it, and the name reads back.
TEST(SpecEditor, NamesFromTheFileCannotEndThePagesData) {
  test::TempDir dir;
  BRepTools::Write(BRepPrimAPI_MakeBox(100, 60, 40).Shape(), dir.file("box.brep").c_str());
  Part part = importPart(dir.file("box.brep"));
  const std::string name = "</script><!--<script>alert(1)</script>";
  part.faces[0].name = name;
  writeSpecEditor(part, "", dir.file("editor.html"));
  const std::string page = test::readText(dir.file("editor.html"));
  const std::string open = R"(<script type="application/json" id="scanplan-data">)";
  const std::size_t begin = page.find(open) + open.size();
  const std::string data = page.substr(begin, page.find("</script>", begin) - begin);
  EXPECT_EQ(data.find('<'), std::string::npos);
  EXPECT_EQ(page.find("<!--"), std::string::npos);
  EXPECT_NE(json::parse(data).dump().find(json(name).dump()), std::string::npos);
}

// The spec it starts from: its document as written (order, numbers, quoted strings), each
// task's and role's faces as ids, and its control points with their faces.
TEST(SpecEditor, StartsFromAGivenSpec) {
  test::TempDir dir;
  BRepTools::Write(BRepPrimAPI_MakeBox(100, 60, 40).Shape(), dir.file("box.brep").c_str());
  const Part part = importPart(dir.file("box.brep"));
  test::writeText(dir.file("points.csv"), "x,y,z\n10,10,40\n");
  test::writeText(dir.file("spec.yaml"),
                  "scanner: laser-line\nroles:\n  priority: [4, 2]\n"
                  "registration: {tolerance: 0.1, method: \"geometry\"}\n"
                  "tasks:\n  - {type: surface, faces: [3, 1]}\n"
                  "  - {type: points, file: points.csv}\n");
  writeSpecEditor(part, dir.file("spec.yaml"), dir.file("editor.html"));
  const json spec = pageData(dir.file("editor.html"))["spec"];
  EXPECT_EQ(spec["tasks"][0]["faces"], json({1, 3}));
  EXPECT_EQ(spec["priority"], json({2, 4}));
  EXPECT_EQ(spec["document"]["registration"].dump(), R"({"tolerance":0.1,"method":"geometry"})");
  ASSERT_EQ(spec["points"].size(), 1u);
  EXPECT_TRUE(vec(spec["points"][0]["position"]).isApprox(Vec3(10, 10, 40)));
  EXPECT_TRUE(vec(spec["points"][0]["normal"]).isApprox(Vec3::UnitZ()));
  EXPECT_EQ(part.faces[spec["points"][0]["face"].get<int>() - 1].bounds.min.z(), 40);
}

TEST(SpecEditor, ASpecNamingAFaceThePartLacksIsAnInputError) {
  test::TempDir dir;
  BRepTools::Write(BRepPrimAPI_MakeBox(100, 60, 40).Shape(), dir.file("box.brep").c_str());
  const Part part = importPart(dir.file("box.brep"));
  test::writeText(dir.file("spec.yaml"), "tasks:\n  - {type: trim, faces: [7]}\n");
  try {
    writeSpecEditor(part, dir.file("spec.yaml"), dir.file("editor.html"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("spec.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("unknown face id 7"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir.file("editor.html")));
}

}  // namespace
}  // namespace scanplan
