// Task-driven sampling: samples on their faces with outward normals, counts per
// direction, holes, borders, decimation, user points, the spec's tasks and its errors.

#include "support.h"

#include "cad/brep_model.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/points_csv.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning/planner.h>
#include <scanplan/sampling/sampling.h>
#include <scanplan/spec/spec.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColgp_Array2OfPnt.hxx>

#include <map>
#include <set>

namespace scanplan {
namespace {

// The 100 x 60 x 40 mm box with a radius 10 mm hole through it along z at (50, 30).
Part boxWithHole(const test::TempDir& dir) {
  TopoDS_Shape box = BRepPrimAPI_MakeBox(100, 60, 40).Shape();
  TopoDS_Shape hole =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(50, 30, -1), gp::DZ()), 10, 42).Shape();
  const std::string path = dir.file("box_hole.brep");
  BRepTools::Write(BRepAlgoAPI_Cut(box, hole).Shape(), path.c_str());
  return importPart(path);
}

int faceWhere(const Part& part, SurfaceType type, const std::function<bool(const Box&)>& where) {
  for (const Face& face : part.faces)
    if (face.type == type && where(face.bounds)) return face.id;
  return 0;
}

int topFace(const Part& part) {
  return faceWhere(part, SurfaceType::Plane, [](const Box& b) { return b.min.z() > 39.9; });
}

std::vector<int> allFaces(const Part& part) {
  std::vector<int> ids;
  for (const Face& f : part.faces) ids.push_back(f.id);
  return ids;
}

// Checks every `stride`-th sample against OCCT directly: its distance to the trimmed face
// (on the surface and inside the trims), and its normal against the triangle of the
// face's (outward, tested) mesh nearest to it.
void expectOnFacesAndOutward(const Part& part, const std::vector<Sample>& samples,
                             std::size_t stride) {
  const double size = part.bounds().diagonal();
  for (std::size_t i = 0; i < samples.size(); i += stride) {
    const Sample& s = samples[i];
    const TopoDS_Face face = part.brep->outwardFace(s.face);
    const gp_Pnt p(s.position.x(), s.position.y(), s.position.z());
    BRepExtrema_DistShapeShape distance(BRepBuilderAPI_MakeVertex(p).Vertex(), face);
    ASSERT_TRUE(distance.IsDone());
    EXPECT_LT(distance.Value(), 1e-6 * size) << "sample " << i << " off face " << s.face;
    const Face& f = part.face(s.face);
    double best = 1e300;
    Vec3 normal = Vec3::Zero();
    for (int t = f.first_triangle; t < f.first_triangle + f.triangle_count; ++t) {
      const Vec3i& tri = part.mesh.triangles[t];
      const Vec3 q = closestPointOnTriangle(s.position, part.mesh.vertices[tri[0]],
                                            part.mesh.vertices[tri[1]], part.mesh.vertices[tri[2]]);
      if ((q - s.position).squaredNorm() < best && !part.mesh.normal(t).isZero()) {
        best = (q - s.position).squaredNorm();
        normal = part.mesh.normal(t);
      }
    }
    EXPECT_GT(s.normal.dot(normal), 0)
        << "sample " << i << " on face " << s.face << " points inward";
    EXPECT_NEAR(s.normal.norm(), 1, 1e-9);
  }
}

std::size_t distinct(const std::vector<Sample>& samples, int face, int coordinate) {
  std::set<long> values;
  for (const Sample& s : samples)
    if (s.face == face) values.insert(std::lround(s.uv[coordinate] * 1e6));
  return values.size();
}

// Each NIST part on its own (the example, those in tests/data, the rest from the shared
// data): almost every face sampled, every sample on its face with an outward normal.
class NistSampling : public testing::TestWithParam<std::string> {};

TEST_P(NistSampling, SamplesLieOnTheFacesWithOutwardNormals) {
  const std::string& name = GetParam();
  std::string path =
      name == "nist_ctc_01_asme1_ap242-e1.stp" ? test::example("parts/" + name)
      : name == "nist_ftc_11_asme1_ap242-e1.stp" || name == "nist_ctc_03_asme1_ap242-e2.stp"
          ? test::testData(name)
          : std::string(SCANPLAN_SHARED_DATA) + "/nist/" + name;
  SHARED_FILE_OR_SKIP(path);
  const Part& part = test::importedOnce(path);
  std::vector<Sample> samples = sampleSurface(part, allFaces(part), Role::Priority, TaskType::Gdt);
  std::set<int> sampled;
  for (const Sample& s : samples) sampled.insert(s.face);
  EXPECT_GE(sampled.size(), part.faces.size() * 95 / 100) << "faces without samples";
  expectOnFacesAndOutward(part, samples, std::max<std::size_t>(1, samples.size() / 400));
}

INSTANTIATE_TEST_SUITE_P(
    Nist, NistSampling,
    testing::Values("nist_ctc_01_asme1_ap242-e1.stp", "nist_ftc_11_asme1_ap242-e1.stp",
                    "nist_ctc_03_asme1_ap242-e2.stp", "nist_ctc_02_asme1_ap242-e2.stp",
                    "nist_ctc_04_asme1_ap242-e1.stp", "nist_ftc_06_asme1_ap242-e1.stp",
                    "nist_ftc_07_asme1_ap242-e2.stp", "nist_ftc_08_asme1_ap242-e1.stp"),
    [](const testing::TestParamInfo<std::string>& param) { return param.param.substr(0, 11); });

TEST(SurfaceSampling, PlaneCylinderAndBSplineGetSixPerDirection) {
  test::TempDir dir;
  Part part = boxWithHole(dir);
  std::vector<Sample> samples = sampleSurface(part, allFaces(part), Role::Priority, TaskType::Gdt);
  const int top = topFace(part);
  const int bore = faceWhere(part, SurfaceType::Cylinder, [](const Box&) { return true; });
  ASSERT_GT(top, 0);
  ASSERT_GT(bore, 0);
  for (int face : {top, bore}) {
    EXPECT_GE(distinct(samples, face, 0), 6u) << "face " << face;
    EXPECT_GE(distinct(samples, face, 1), 6u) << "face " << face;
  }
  // A wavy B-spline patch 80 x 60 mm.
  TColgp_Array2OfPnt grid(1, 6, 1, 5);
  for (int i = 1; i <= 6; ++i)
    for (int j = 1; j <= 5; ++j)
      grid(i, j) = gp_Pnt(16.0 * (i - 1), 15.0 * (j - 1), 5 * std::sin(i) * std::cos(j));
  Handle(Geom_Surface) surface(GeomAPI_PointsToBSplineSurface(grid).Surface());
  TopoDS_Face patch = BRepBuilderAPI_MakeFace(surface, 1e-6);
  BRepTools::Write(patch, dir.file("patch.brep").c_str());
  Part spline = importPart(dir.file("patch.brep"));
  ASSERT_EQ(spline.faces[0].type, SurfaceType::BSpline);
  std::vector<Sample> spline_samples =
      sampleSurface(spline, {1}, Role::Priority, TaskType::Surface);
  EXPECT_GE(distinct(spline_samples, 1, 0), 6u);
  EXPECT_GE(distinct(spline_samples, 1, 1), 6u);
  expectOnFacesAndOutward(spline, spline_samples, 1);
}

TEST(SurfaceSampling, NoSampleInsideTheHole) {
  test::TempDir dir;
  Part part = boxWithHole(dir);
  const int top = topFace(part);
  std::vector<Sample> samples = sampleSurface(part, {top}, Role::Priority, TaskType::Gdt);
  ASSERT_GT(samples.size(), 30u);
  for (const Sample& s : samples) {
    EXPECT_GE((s.position.head<2>() - Eigen::Vector2d(50, 30)).norm(), 10 - 1e-9);
    EXPECT_NEAR(s.position.z(), 40, 1e-9);
    EXPECT_TRUE(s.normal.isApprox(Vec3::UnitZ(), 1e-12));
  }
  double weight = 0;
  for (const Sample& s : samples) weight += s.weight;
  EXPECT_NEAR(weight, part.face(top).area, 1e-6 * part.face(top).area);
}

TEST(SurfaceSampling, LargeFacesAreSplitIntoPortionsThatFit) {
  // A 1000 x 600 plate: portions of at most 225 mm, so samples are spread over it and the
  // gaps between neighbouring samples stay well under a portion.
  test::TempDir dir;
  BRepTools::Write(BRepPrimAPI_MakeBox(1000, 600, 10).Shape(), dir.file("plate.brep").c_str());
  Part part = importPart(dir.file("plate.brep"));
  const int top = faceWhere(part, SurfaceType::Plane, [](const Box& b) { return b.min.z() > 9.9; });
  SamplingOptions options;
  std::vector<Sample> samples = sampleSurface(part, {top}, Role::Priority, TaskType::Gdt, options);
  // At least 8 x 8 per portion, and at least (1000/225) x (600/225) portions.
  EXPECT_GE(samples.size(), 64u * 5 * 3);
  for (double x = 20; x < 1000; x += 50)
    for (double y = 20; y < 600; y += 50) {
      double nearest = 1e300;
      for (const Sample& s : samples)
        nearest = std::min(nearest, (s.position.head<2>() - Eigen::Vector2d(x, y)).norm());
      ASSERT_LT(nearest, options.portion_size / options.min_per_direction) << x << ", " << y;
    }
}

TEST(BorderSampling, HoleBorderIsAtTheRadius) {
  test::TempDir dir;
  Part part = boxWithHole(dir);
  const int top = topFace(part);
  SamplingOptions options;
  std::vector<Sample> samples = sampleBorders(part, {top}, Role::Priority, TaskType::Trim, options);
  int on_hole = 0, on_outside = 0;
  for (const Sample& s : samples) {
    const double r = (s.position.head<2>() - Eigen::Vector2d(50, 30)).norm();
    EXPECT_NEAR(s.position.z(), 40, 1e-9);
    EXPECT_TRUE(s.normal.isApprox(Vec3::UnitZ(), 1e-9));
    EXPECT_NEAR(s.tangent.norm(), 1, 1e-9);
    EXPECT_NEAR(s.tangent.z(), 0, 1e-9);
    EXPECT_LE(s.weight, options.border_step + 1e-9);
    if (r < 20) {
      EXPECT_NEAR(r, 10, 1e-6);
      // The tangent of a circle is perpendicular to its radius.
      EXPECT_NEAR(s.tangent.head<2>().dot((s.position.head<2>() - Eigen::Vector2d(50, 30)) / r), 0,
                  1e-6);
      ++on_hole;
    } else {
      const bool on_rectangle =
          std::abs(s.position.x()) < 1e-9 || std::abs(s.position.x() - 100) < 1e-9 ||
          std::abs(s.position.y()) < 1e-9 || std::abs(s.position.y() - 60) < 1e-9;
      EXPECT_TRUE(on_rectangle) << s.position.transpose();
      ++on_outside;
    }
  }
  // Circumference 62.8 mm and perimeter 320 mm at steps of at most 5 mm.
  EXPECT_GE(on_hole, 13);
  EXPECT_GE(on_outside, 64);
}

TEST(GlobalSampling, BoxFacesGetFewSpreadSamples) {
  test::TempDir dir;
  BRepTools::Write(BRepPrimAPI_MakeBox(100, 60, 40).Shape(), dir.file("box.brep").c_str());
  Part part = importPart(dir.file("box.brep"));
  SamplingOptions options;
  options.decimation_radius = 20;
  std::vector<Sample> dense =
      sampleSurface(part, allFaces(part), Role::Normal, TaskType::Global, options);
  std::vector<Sample> samples = sampleGlobal(part, {}, options);
  EXPECT_LT(samples.size(), dense.size() / 4);
  std::map<int, int> per_face;
  for (const Sample& s : samples) ++per_face[s.face];
  for (const Face& face : part.faces) {
    // Points at least r apart in an a x b rectangle: at most (a/r + 1)(b/r + 1).
    const Vec3 size = face.bounds.size();
    std::vector<double> sides;
    for (int k = 0; k < 3; ++k)
      if (size[k] > 1e-6) sides.push_back(size[k]);
    const double bound =
        (sides[0] / options.decimation_radius + 1) * (sides[1] / options.decimation_radius + 1);
    EXPECT_GT(per_face[face.id], 0);
    EXPECT_LE(per_face[face.id], bound) << "face " << face.id;
  }
  for (std::size_t a = 0; a < samples.size(); ++a)
    for (std::size_t b = a + 1; b < samples.size(); ++b)
      if (samples[a].normal.dot(samples[b].normal) > std::cos(radians(options.decimation_angle))) {
        EXPECT_GE((samples[a].position - samples[b].position).norm(), options.decimation_radius);
      }
}

TEST(GlobalSampling, EveryFaceKeepsASampleHoweverSmall) {
  // A 100 x 60 x 40 mm box with two shallow grooves along x in its top: each groove's
  // floor (3 mm wide, 1 mm down) lies within the decimation radius of the top's samples
  // with the same normal, and each groove's 1 mm walls near the other's.
  test::TempDir dir;
  TopoDS_Shape block = BRepPrimAPI_MakeBox(100, 60, 40).Shape();
  for (const double y : {20.0, 37.0})
    block = BRepAlgoAPI_Cut(block, BRepPrimAPI_MakeBox(gp_Pnt(-1, y, 39), 102, 3, 2).Shape());
  BRepTools::Write(block, dir.file("grooves.brep").c_str());
  const Part part = importPart(dir.file("grooves.brep"));
  SamplingOptions options;
  options.decimation_radius = 20;
  const std::vector<Sample> samples = sampleGlobal(part, {}, options);
  std::set<int> sampled;
  for (const Sample& s : samples) sampled.insert(s.face);
  for (const Face& face : part.faces) EXPECT_TRUE(sampled.count(face.id)) << "face " << face.id;
  EXPECT_EQ(part.faces.size(), 6u + 2 + 3 * 2);  // the box's, one more on top, the grooves'
}

TEST(GlobalSampling, EveryFaceOfTheDieCastPartIsSampled) {
  // 232 faces, many of them fillets and ribs narrower than the decimation radius.
  SHARED_DATA_OR_SKIP(path, "mech/asi_repatch-hpdc.stp");
  const Part part = importPart(path);
  std::set<int> sampled;
  for (const Sample& s : sampleGlobal(part, {})) sampled.insert(s.face);
  for (const Face& face : part.faces) EXPECT_TRUE(sampled.count(face.id)) << "face " << face.id;
}

TEST(GlobalSampling, CurvedFacesKeepMoreSamplesThanFlatOnes) {
  test::TempDir dir;
  Part part = boxWithHole(dir);
  std::vector<Sample> samples = sampleGlobal(part, {});
  const int bore = faceWhere(part, SurfaceType::Cylinder, [](const Box&) { return true; });
  const int top = topFace(part);
  double bore_density = 0, top_density = 0;
  for (const Sample& s : samples) {
    if (s.face == bore) bore_density += 1 / part.face(bore).area;
    if (s.face == top) top_density += 1 / part.face(top).area;
  }
  EXPECT_GT(bore_density, 2 * top_density);
}

TEST(PointSampling, PointsTakeTheirFaceAndNormal) {
  test::TempDir dir;
  Part part = boxWithHole(dir);
  test::writeText(dir.file("points.csv"), "x,y,z\n10,10,40\n# a comment\n50,40,20,0,1,0\n");
  std::vector<Sample> samples =
      samplePoints(part, readPointsCsv(dir.file("points.csv")), dir.file("points.csv"));
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_EQ(samples[0].face, topFace(part));
  EXPECT_TRUE(samples[0].normal.isApprox(Vec3::UnitZ(), 1e-9));
  // On the bore at (50, 40, 20): the bore's outward normal (out of the material) is -y there.
  EXPECT_EQ(part.face(samples[1].face).type, SurfaceType::Cylinder);
  EXPECT_TRUE(samples[1].normal.isApprox(Vec3::UnitY(), 1e-9));  // the CSV's normal wins
  test::writeText(dir.file("one.csv"), "50,40,20\n");
  std::vector<Sample> bore =
      samplePoints(part, readPointsCsv(dir.file("one.csv")), dir.file("one.csv"));
  EXPECT_TRUE(bore[0].normal.isApprox(-Vec3::UnitY(), 1e-6)) << bore[0].normal.transpose();
}

// A point off the part within the tolerance becomes the point on the exact face: on the
// bore (radius 10 about x = 50, y = 30), not on its facets, and on the top plane.
TEST(PointSampling, PointsAreProjectedOntoTheExactFace) {
  test::TempDir dir;
  Part part = boxWithHole(dir);
  test::writeText(dir.file("near.csv"), "50,39.6,20\n58.2,34.1,31\n10,10,40.3\n");
  const std::vector<Sample> samples =
      samplePoints(part, readPointsCsv(dir.file("near.csv")), dir.file("near.csv"));
  ASSERT_EQ(samples.size(), 3u);
  for (int i : {0, 1}) {
    const Sample& s = samples[i];
    EXPECT_EQ(part.face(s.face).type, SurfaceType::Cylinder);
    EXPECT_NEAR(std::hypot(s.position.x() - 50, s.position.y() - 30), 10, 1e-7);
    // Along the radius through the given point.
    EXPECT_NEAR(std::atan2(s.position.y() - 30, s.position.x() - 50),
                std::atan2(i == 0 ? 9.6 : 4.1, i == 0 ? 0.0 : 8.2), 1e-9);
  }
  EXPECT_TRUE(samples[2].position.isApprox(Vec3(10, 10, 40), 1e-12));
}

TEST(PointSampling, FarPointIsAnErrorNamingIt) {
  test::TempDir dir;
  Part part = boxWithHole(dir);
  test::writeText(dir.file("far.csv"), "10,10,40\n10,10,45\n");
  try {
    samplePoints(part, readPointsCsv(dir.file("far.csv")), dir.file("far.csv"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("5.000000 mm from the part"), std::string::npos)
        << e.what();
  }
}

TEST(SpecSampling, GdtFromFileSelectsExactlyThePmiFaces) {
  Part part = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"), "gdt: from-file\n");
  std::vector<Sample> samples = sampleTargets(
      part, resolveSpec(part, loadSpec(dir.file("spec.yaml"))).targets, SamplingOptions{});
  std::set<int> expected;
  for (const GeometricTolerance& t : part.gdt.tolerances)
    expected.insert(t.faces.begin(), t.faces.end());
  for (const Datum& d : part.gdt.datums) expected.insert(d.faces.begin(), d.faces.end());
  ASSERT_FALSE(expected.empty());
  std::set<int> sampled;
  for (const Sample& s : samples) {
    sampled.insert(s.face);
    EXPECT_EQ(s.task, TaskType::Gdt);
    EXPECT_EQ(s.role, Role::Priority);
  }
  EXPECT_EQ(sampled, expected);
}

// gdt: all targets the dimensioned faces too: every face of the file's tolerances,
// dimensions with a value and datums.
TEST(SpecSampling, GdtAllAddsTheDimensionedFaces) {
  Part part = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"), "gdt: all\n");
  std::set<int> expected;
  for (const GeometricTolerance& t : part.gdt.tolerances)
    expected.insert(t.faces.begin(), t.faces.end());
  for (const Dimension& d : part.gdt.dimensions)
    if (d.value > 0) expected.insert(d.faces.begin(), d.faces.end());
  for (const Datum& d : part.gdt.datums) expected.insert(d.faces.begin(), d.faces.end());
  std::set<int> sampled;
  for (const Sample& s : sampleTargets(
           part, resolveSpec(part, loadSpec(dir.file("spec.yaml"))).targets, SamplingOptions{}))
    sampled.insert(s.face);
  EXPECT_EQ(sampled, expected);
  EXPECT_GT(expected.size(), gdtFaces(part).size());  // the dimensions add faces
}

TEST(SpecSampling, TasksMergeAndFixturesAreNeverSampled) {
  test::TempDir dir;
  Part part = boxWithHole(dir);
  const int top = topFace(part);
  test::writeText(dir.file("points.csv"), "10,10,40\n");
  test::writeText(dir.file("spec.yaml"),
                  "roles:\n  fixture: [" + std::to_string(top) +
                      "]\ntasks:\n  - {type: global}\n  - {type: trim, faces: [1]}\n"
                      "  - {type: points, file: points.csv}\n");
  std::vector<Sample> samples = sampleTargets(
      part, resolveSpec(part, loadSpec(dir.file("spec.yaml"))).targets, SamplingOptions{});
  std::map<TaskType, int> tasks;
  for (const Sample& s : samples) {
    ++tasks[s.task];
    if (s.task != TaskType::Points) {
      EXPECT_NE(s.face, top);
    }
  }
  EXPECT_GT(tasks[TaskType::Global], 0);
  EXPECT_GT(tasks[TaskType::Trim], 0);
  EXPECT_EQ(tasks[TaskType::Points], 1);
}

// The spec resolved against its part once: roles and tasks as face ids, fixtures left out
// of every task, the GD&T faces both priority and gdt targets.
TEST(SpecSampling, ResolvedSpecHoldsFaceIds) {
  Part part = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  const std::vector<int> gdt = gdtFaces(part);
  ASSERT_GE(gdt.size(), 2u);
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"),
                  "gdt: from-file\nroles: {fixture: [" + std::to_string(gdt.front()) +
                      "], specular: [3, 1]}\ntasks:\n  - {type: gdt}\n  - {type: trim, faces: [" +
                      std::to_string(gdt.back()) + "]}\n");
  const ResolvedSpec resolved = resolveSpec(part, loadSpec(dir.file("spec.yaml")));
  EXPECT_EQ(resolved.gdt_faces, gdt);
  EXPECT_EQ(resolved.targets.priority, gdt);
  EXPECT_EQ(resolved.targets.fixture, std::vector<int>{gdt.front()});
  EXPECT_EQ(resolved.specular, (std::vector<int>{1, 3}));
  ASSERT_EQ(resolved.targets.tasks.size(), 2u);
  EXPECT_EQ(resolved.targets.tasks[0].faces, std::vector<int>(gdt.begin() + 1, gdt.end()));
  EXPECT_EQ(resolved.targets.tasks[1].faces, std::vector<int>{gdt.back()});
  EXPECT_EQ(simulationOptionsFor(resolved, part, Pose::Identity()).specular_faces,
            resolved.specular);
  // An unknown face in any role names the spec.
  test::writeText(dir.file("bad.yaml"), "roles: {specular: [9999]}\n");
  EXPECT_THROW(resolveSpec(part, loadSpec(dir.file("bad.yaml"))), InputError);
}

// A task given again targets nothing new: three thousand copies of two tasks resolve to the
// two, and sample as one copy of each does.
TEST(SpecSampling, ATaskGivenAgainIsSampledOnce) {
  Part part = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  test::TempDir dir;
  std::string copies = "tasks:\n";
  for (int k = 0; k < 3000; ++k) copies += "  - {type: global}\n  - {type: trim, faces: [2, 3]}\n";
  test::writeText(dir.file("copies.yaml"), copies);
  test::writeText(dir.file("once.yaml"),
                  "tasks:\n  - {type: global}\n  - {type: trim, faces: [3, 2]}\n");
  const ResolvedSpec many = resolveSpec(part, loadSpec(dir.file("copies.yaml")));
  const ResolvedSpec once = resolveSpec(part, loadSpec(dir.file("once.yaml")));
  ASSERT_EQ(many.targets.tasks.size(), 2u);
  const SamplingOptions options = samplingOptionsFor(many.spec.scanner);
  EXPECT_EQ(sampleTargets(part, many.targets, options).size(),
            sampleTargets(part, once.targets, options).size());
}

TEST(SpecSampling, TasksWithoutTargetsCannotBePlanned) {
  test::TempDir dir;
  Part part = boxWithHole(dir);
  auto reason = [&](const std::string& spec_text) -> std::string {
    test::writeText(dir.file("spec.yaml"), spec_text);
    try {
      sampleTargets(part, resolveSpec(part, loadSpec(dir.file("spec.yaml"))).targets,
                    SamplingOptions{});
    } catch (const PlanningError& e) {
      EXPECT_EQ(e.exitCode(), kExitPlanning);
      return e.what();
    }
    ADD_FAILURE() << "no PlanningError for: " << spec_text;
    return {};
  };
  EXPECT_NE(reason("tasks:\n  - {type: trim}\n").find("task 1 (trim) has no target faces"),
            std::string::npos);
  EXPECT_NE(reason("roles: {fixture: [1, 2]}\ntasks:\n  - {type: global}\n  - {type: surface, "
                   "faces: [2, 1]}\n")
                .find("task 2 (surface) has no target faces: all of them are fixtures"),
            std::string::npos);
}

TEST(SpecSampling, SpecErrors) {
  test::TempDir dir;
  Part part = boxWithHole(dir);
  auto reason = [&](const std::string& spec_text) -> std::string {
    test::writeText(dir.file("spec.yaml"), spec_text);
    try {
      sampleTargets(part, resolveSpec(part, loadSpec(dir.file("spec.yaml"))).targets,
                    SamplingOptions{});
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(dir.file("")), std::string::npos) << e.what();
      return e.what();
    }
    ADD_FAILURE() << "no error for: " << spec_text;
    return {};
  };
  auto has = [](const std::string& text, const std::string& part_text) {
    return text.find(part_text) != std::string::npos;
  };
  EXPECT_TRUE(has(reason("tasks:\n  - {type: trim, faces: [99]}\n"), "unknown face id 99"));
  EXPECT_TRUE(
      has(reason("tasks:\n  - {type: gdt, faces: [{name: DATUM_Z}]}\n"), "named 'DATUM_Z'"));
  EXPECT_TRUE(has(reason("roles:\n  priority: [{color: '#ff0000'}]\n"), "colour"));
  EXPECT_TRUE(
      has(reason("tasks:\n  - {type: points, file: missing.csv}\n"), "missing.csv: no such file"));
  EXPECT_TRUE(has(reason("tasks: [{type: gdt}\n"), "not valid YAML"));
  EXPECT_TRUE(has(reason("tasks:\n  - {type: scan}\n"), "unknown task type 'scan'"));
  EXPECT_TRUE(has(reason("gdt: from-file\n"), "carries no GD&T"));
  EXPECT_TRUE(has(reason("planner: {tilt: [60, 30]}\n"), "planner.tilt"));
  EXPECT_TRUE(has(reason("planner: {sweep_overlap: 0.95}\n"), "planner.sweep_overlap"));
  EXPECT_TRUE(
      has(reason("planner: {evaluation_spacing: -1}\n"), "planner.evaluation_spacing must be"));
  EXPECT_TRUE(has(reason("part: {rest: 0}\n"), "face ids start at 1"));
  EXPECT_TRUE(has(reason("part: {rest: sideways}\n"), "expected auto, all, a face id"));
  test::writeText(dir.file("far.csv"), "10,10,80\n");
  EXPECT_TRUE(has(reason("tasks:\n  - {type: points, file: far.csv}\n"), "mm from the part"));
  test::writeText(dir.file("bad.csv"), "1,2\n");
  EXPECT_TRUE(has(reason("tasks:\n  - {type: points, file: bad.csv}\n"), "line 1: expected x,y,z"));
}

}  // namespace
}  // namespace scanplan
