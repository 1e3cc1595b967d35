// Import of parts with known geometry, made with OCCT in the test: exact counts, areas and
// volumes; unit conversion; repair of inward and inconsistently oriented shells.

#include "occt_support.h"
#include "support.h"

#include <scanplan/cad/elementary.h>
#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <GeomConvert.hxx>
#include <GeomLProp_SLProps.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_ConicalSurface.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_SphericalSurface.hxx>
#include <Geom_ToroidalSurface.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Controller.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>

#include <fstream>
#include <iterator>
#include <random>
#include <regex>

namespace scanplan {
namespace {

using test::writeBrep;
using test::writeStep;

// A 100 x 60 x 40 mm box with a through hole of radius 10 mm along z.
constexpr double kA = 100, kB = 60, kC = 40, kR = 10;
const double kArea = 2 * (kA * kB + kB * kC + kA * kC) - 2 * M_PI * kR * kR + 2 * M_PI * kR * kC;
const double kVolume = kA * kB * kC - M_PI * kR * kR * kC;

TopoDS_Shape boxWithHole() {
  TopoDS_Shape box = BRepPrimAPI_MakeBox(kA, kB, kC).Shape();
  TopoDS_Shape hole =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(kA / 2, kB / 2, -1), gp::DZ()), kR, kC + 2).Shape();
  return BRepAlgoAPI_Cut(box, hole).Shape();
}

void expectBoxWithHole(const Part& part) {
  ASSERT_EQ(part.faces.size(), 7u);
  EXPECT_NEAR(part.area(), kArea, 1e-6 * kArea);
  EXPECT_NEAR(part.volume(), kVolume, 1e-6 * kVolume);
  int planes = 0, cylinders = 0;
  for (const Face& face : part.faces) {
    planes += face.type == SurfaceType::Plane;
    cylinders += face.type == SurfaceType::Cylinder;
  }
  EXPECT_EQ(planes, 6);
  EXPECT_EQ(cylinders, 1);
  EXPECT_TRUE(part.bounds().size().isApprox(Vec3(kA, kB, kC), 1e-3));
  EdgeReport edges = edgeReport(part.mesh, 1e-6);
  EXPECT_EQ(edges.boundary + edges.non_manifold + edges.misoriented, 0u);
  // The mesh's volume is within the chordal error of the exact one: the hole's polygon
  // is inscribed, so the mesh volume is slightly larger.
  double mesh_volume = signedVolume(part.mesh);
  EXPECT_GT(mesh_volume, kVolume);
  EXPECT_LT(mesh_volume, kVolume + 2 * M_PI * kR * kC * part.linear_deflection);
}

// A cylinder, a cone, a sphere and a torus, each as ours and as OCCT's, about one axis.
struct SurfaceCase {
  ElementarySurface ours;
  Handle(Geom_Surface) occt;
  double v_from, v_to;  // the surface's v range searched (u goes round)
};
const Vec3 kCaseOrigin(10, -5, 3);

// OCCT's surface of `c` over the range its tests search.
Handle(Geom_Surface) trimmed(const SurfaceCase& c) {
  return new Geom_RectangularTrimmedSurface(c.occt, 0, 2 * M_PI, c.v_from, c.v_to);
}

// Points scattered about each case's surface (40 mm about its origin, `seed`), each with
// its case.
std::vector<std::pair<const SurfaceCase*, Vec3>> scatteredAbout(
    const std::vector<SurfaceCase>& cases, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> within(-40, 40);
  std::vector<std::pair<const SurfaceCase*, Vec3>> points;
  for (const SurfaceCase& c : cases)
    for (int k = 0; k < 50; ++k)
      points.push_back({&c, kCaseOrigin + Vec3(within(random), within(random), within(random))});
  return points;
}

std::vector<SurfaceCase> surfaceCases() {
  const gp_Ax3 frame(gp_Pnt(10, -5, 3), gp_Dir(1, 2, 2));
  const Vec3 origin = kCaseOrigin, axis = Vec3(1, 2, 2).normalized();
  return {
      {{SurfaceType::Cylinder, origin, axis, 12},
       new Geom_CylindricalSurface(frame, 12),
       -100,
       100},
      {{SurfaceType::Cone, origin, axis, 12, 0, radians(20)},
       new Geom_ConicalSurface(frame, radians(20), 12),
       -200,
       200},
      {{SurfaceType::Sphere, origin, axis, 12},
       new Geom_SphericalSurface(frame, 12),
       -M_PI / 2,
       M_PI / 2},
      {{SurfaceType::Torus, origin, axis, 30, 8},
       new Geom_ToroidalSurface(frame, 30, 8),
       0,
       2 * M_PI},
      // A spindle torus (minor radius past the major, as a dome's), whose tube crosses its
      // axis: the nearest point may lie on the tube about the far side of the ring.
      {{SurfaceType::Torus, origin, axis, 6, 10},
       new Geom_ToroidalSurface(frame, 6, 10),
       0,
       2 * M_PI},
  };
}

// The point of a cylinder, cone (both nappes), sphere and tori nearest points scattered about them
// lies as far as OCCT's projection onto the same surface finds, on the surface (OCCT's distance
// from it 0), and off it along its normal there.
TEST(ElementarySurface, TheNearestPointIsOcctsProjection) {
  const std::vector<SurfaceCase> cases = surfaceCases();
  for (const auto& [c, p] : scatteredAbout(cases, 5)) {
    const auto [q, normal] = nearestOn(c->ours, p);
    GeomAPI_ProjectPointOnSurf projected(gp_Pnt(p.x(), p.y(), p.z()), trimmed(*c));
    ASSERT_GT(projected.NbPoints(), 0) << int(c->ours.type) << " " << p.transpose();
    EXPECT_NEAR((p - q).norm(), projected.LowerDistance(), 1e-6) << int(c->ours.type);
    GeomAPI_ProjectPointOnSurf back(gp_Pnt(q.x(), q.y(), q.z()), trimmed(*c));
    ASSERT_GT(back.NbPoints(), 0);
    EXPECT_NEAR(back.LowerDistance(), 0, 1e-6);
    EXPECT_NEAR((p - q).cross(normal).norm(), 0, 1e-6);
    EXPECT_NEAR(normal.norm(), 1, 1e-12);
  }
}

// At the point of each surface nearest points scattered about it, the sum of its principal
// curvatures is twice OCCT's mean curvature there, signed for our normal: positive where the
// surface bends away from it. OCCT's mean curvature is negative where the surface bends away
// from its own normal (a sphere with its normal outward).
TEST(ElementarySurface, ItsCurvatureSumIsTwiceOcctsMeanCurvature) {
  const std::vector<SurfaceCase> cases = surfaceCases();
  for (const auto& [c, p] : scatteredAbout(cases, 6)) {
    const auto [q, normal] = nearestOn(c->ours, p);
    const Handle(Geom_Surface) surface = trimmed(*c);
    GeomAPI_ProjectPointOnSurf on(gp_Pnt(q.x(), q.y(), q.z()), surface);
    ASSERT_GT(on.NbPoints(), 0);
    double u = 0, v = 0;
    on.LowerDistanceParameters(u, v);
    GeomLProp_SLProps props(surface, u, v, 2, 1e-9);
    if (!props.IsCurvatureDefined()) continue;  // a cone's apex
    const gp_Dir n = props.Normal();
    const double same_way = Vec3(n.X(), n.Y(), n.Z()).dot(normal) > 0 ? 1 : -1;
    EXPECT_NEAR(curvatureSum(c->ours, p), -2 * props.MeanCurvature() * same_way, 1e-9)
        << int(c->ours.type) << " " << p.transpose();
  }
  const ElementarySurface plane{SurfaceType::Plane, kCaseOrigin, Vec3::UnitZ()};
  EXPECT_EQ(curvatureSum(plane, Vec3(1, 2, 3)), 0);
}

TEST(GeneratedPart, BoxWithHoleFromBrep) {
  test::TempDir dir;
  Part part = importPart(writeBrep(boxWithHole(), dir.file("box.brep")));
  EXPECT_EQ(part.format, "BREP");
  expectBoxWithHole(part);
  for (const Face& face : part.faces) EXPECT_FALSE(face.reoriented);
}

TEST(GeneratedPart, BoxWithHoleFromStep) {
  test::TempDir dir;
  Part part = importPart(writeStep(boxWithHole(), dir.file("box.step"), "MM"));
  EXPECT_EQ(part.format, "STEP");
  expectBoxWithHole(part);
}

// A B-spline face's area comes from its triangulation: within the chordal tolerance's
// share of the exact area. A quarter cylinder of radius 50 and height 80 as a B-spline.
TEST(GeneratedPart, BSplineFaceAreaFromItsTriangulation) {
  test::TempDir dir;
  const Handle(Geom_Surface) quarter = new Geom_RectangularTrimmedSurface(
      new Geom_CylindricalSurface(gp_Ax3(gp::XOY()), 50), 0.0, M_PI / 2, 0.0, 80.0);
  const TopoDS_Face face =
      BRepBuilderAPI_MakeFace(Handle(Geom_Surface)(GeomConvert::SurfaceToBSplineSurface(quarter)),
                              1e-7)
          .Face();
  const Part part = importPart(writeBrep(face, dir.file("quarter.brep")));
  ASSERT_EQ(part.faces.size(), 1u);
  EXPECT_EQ(part.faces[0].type, SurfaceType::BSpline);
  const double exact = 50 * M_PI / 2 * 80;
  // A chord of sagitta d on radius R is short of its arc by about 2d / (3R).
  const double bound = 2 * part.linear_deflection / (3 * 50);
  EXPECT_NEAR(part.faces[0].area, exact, bound * exact);
  EXPECT_LT(part.faces[0].area, exact);
}

TEST(GeneratedPart, InchStepIsConvertedToMillimetres) {
  test::TempDir dir;
  Part part = importPart(writeStep(boxWithHole(), dir.file("box_inch.step"), "INCH"));
  EXPECT_EQ(part.file_unit, "inch");
  EXPECT_DOUBLE_EQ(part.unit_scale, 25.4);
  expectBoxWithHole(part);
}

// A file whose inch is a conversion-based unit with its factor written as a plain
// MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4), mm), as NIST CTC 05 writes it, where OCCT's
// writer writes LENGTH_MEASURE_WITH_UNIT: the unit is still named, and the box has its size
// in millimetres.
TEST(GeneratedPart, InchWithAPlainConversionFactorIsNamed) {
  test::TempDir dir;
  const std::string path = writeStep(boxWithHole(), dir.file("box_inch.step"), "INCH");
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::regex factor(R"(LENGTH_MEASURE_WITH_UNIT\(25\.4,)");
  ASSERT_TRUE(std::regex_search(text, factor));
  text = std::regex_replace(text, factor, "MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),");
  test::writeText(dir.file("plain.step"), text);
  Part part = importPart(dir.file("plain.step"));
  EXPECT_EQ(part.file_unit, "inch");
  EXPECT_DOUBLE_EQ(part.unit_scale, 25.4);
  expectBoxWithHole(part);
}

TEST(GeneratedPart, BoxWithHoleFromIges) {
  test::TempDir dir;
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 1);  // B-Rep mode
  writer.AddShape(boxWithHole());
  writer.ComputeModel();
  std::string path = dir.file("box.igs");
  ASSERT_TRUE(writer.Write(path.c_str()));
  // OCCT's IGES reader prints its statistics through its default messenger; importPart
  // silences it, so that a program using the library prints nothing it did not ask for.
  testing::internal::CaptureStdout();
  Part part = importPart(path);
  EXPECT_EQ(testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(part.format, "IGES");
  EXPECT_EQ(part.faces.size(), 7u);
  EXPECT_NEAR(part.area(), kArea, 1e-6 * kArea);
}

TEST(GeneratedPart, ChosenDeflectionIsUsed) {
  test::TempDir dir;
  std::string path = writeBrep(boxWithHole(), dir.file("box.brep"));
  ImportOptions coarse, fine;
  coarse.linear_deflection = 1.0;
  fine.linear_deflection = 0.01;
  Part a = importPart(path, coarse), b = importPart(path, fine);
  EXPECT_DOUBLE_EQ(a.linear_deflection, 1.0);
  EXPECT_LT(a.mesh.triangles.size(), b.mesh.triangles.size());
  // The automatic tolerance follows the part size.
  Part automatic = importPart(path);
  EXPECT_NEAR(automatic.linear_deflection,
              ImportOptions{}.relative_deflection * std::sqrt(kA * kA + kB * kB + kC * kC), 0.01);
}

TEST(GeneratedPart, InwardSolidIsTurnedOutward) {
  test::TempDir dir;
  Part part = importPart(writeBrep(boxWithHole().Reversed(), dir.file("inward.brep")));
  expectBoxWithHole(part);
  for (const Face& face : part.faces) EXPECT_TRUE(face.reoriented) << face.id;
}

TEST(GeneratedPart, InconsistentShellIsRepaired) {
  // A box whose shell has one face turned the wrong way round.
  TopoDS_Shape box = BRepPrimAPI_MakeBox(kA, kB, kC).Shape();
  BRep_Builder builder;
  TopoDS_Shell shell;
  builder.MakeShell(shell);
  int index = 0;
  for (TopExp_Explorer it(box, TopAbs_FACE); it.More(); it.Next(), ++index)
    builder.Add(shell, index == 3 ? it.Current().Reversed() : it.Current());
  TopoDS_Solid solid;
  builder.MakeSolid(solid);
  builder.Add(solid, shell);
  test::TempDir dir;
  Part part = importPart(writeBrep(solid, dir.file("inconsistent.brep")));
  ASSERT_EQ(part.faces.size(), 6u);
  int reoriented = 0;
  for (const Face& face : part.faces) reoriented += face.reoriented;
  EXPECT_EQ(reoriented, 1);
  EdgeReport edges = edgeReport(part.mesh, 1e-6);
  EXPECT_EQ(edges.misoriented, 0u);
  EXPECT_NEAR(signedVolume(part.mesh), kA * kB * kC, 1e-6 * kA * kB * kC);
}

TEST(GeneratedPart, StepNamesAndColoursReachTheFaces) {
  // An XDE document: the part named HousingBody, its bore named BORE_A and red.
  Handle(TDocStd_Document) doc;
  XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
  Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
  Handle(XCAFDoc_ColorTool) colors = XCAFDoc_DocumentTool::ColorTool(doc->Main());
  TopoDS_Shape shape = boxWithHole();
  TDF_Label label = shapes->AddShape(shape, false);
  TDataStd_Name::Set(label, "HousingBody");
  TopoDS_Shape bore;
  for (TopExp_Explorer it(shape, TopAbs_FACE); it.More(); it.Next())
    if (BRepAdaptor_Surface(TopoDS::Face(it.Current())).GetType() == GeomAbs_Cylinder)
      bore = it.Current();
  TDF_Label bore_label = shapes->AddSubShape(label, bore);
  TDataStd_Name::Set(bore_label, "BORE_A");
  colors->SetColor(bore_label, Quantity_Color(1, 0, 0, Quantity_TOC_RGB), XCAFDoc_ColorSurf);

  test::TempDir dir;
  std::string path = dir.file("named.step");
  STEPCAFControl_Controller::Init();
  Interface_Static::SetIVal("write.stepcaf.subshapes.name", 1);
  STEPCAFControl_Writer writer;
  ASSERT_TRUE(writer.Transfer(doc, STEPControl_AsIs));
  ASSERT_EQ(writer.Write(path.c_str()), IFSelect_RetDone);
  Interface_Static::SetIVal("write.stepcaf.subshapes.name", 0);
  XCAFApp_Application::GetApplication()->Close(doc);

  Part part = importPart(path);
  ASSERT_EQ(part.faces.size(), 7u);
  ASSERT_EQ(part.solids.size(), 1u);
  EXPECT_EQ(part.solids[0].name, "HousingBody");
  int named = 0;
  for (const Face& face : part.faces) {
    if (face.type != SurfaceType::Cylinder) {
      EXPECT_TRUE(face.name.empty()) << face.name;
      EXPECT_FALSE(face.color && face.color->g == 0) << "face " << face.id << " is red";
      continue;
    }
    ++named;
    EXPECT_EQ(face.name, "BORE_A");
    ASSERT_TRUE(face.color);
    EXPECT_FLOAT_EQ(face.color->r, 1);
    EXPECT_FLOAT_EQ(face.color->g, 0);
  }
  EXPECT_EQ(named, 1);
}

TEST(GeneratedPart, FaceLookupRejectsUnknownIds) {
  test::TempDir dir;
  Part part = importPart(writeBrep(boxWithHole(), dir.file("box.brep")));
  EXPECT_EQ(part.face(7).id, 7);
  EXPECT_THROW(part.face(0), InputError);
  EXPECT_THROW(part.face(8), InputError);
}

}  // namespace
}  // namespace scanplan
