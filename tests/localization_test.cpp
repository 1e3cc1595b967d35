// Rest orientations against what a person would list.

#include "support.h"

#include <scanplan/cad/import.h>
#include <scanplan/cad/localization.h>
#include <scanplan/core/errors.h>

#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepTools.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>

namespace scanplan {
namespace {

Part brepPart(const TopoDS_Shape& shape, const test::TempDir& dir, const std::string& name) {
  BRepTools::Write(shape, dir.file(name).c_str());
  return importPart(dir.file(name));
}

void expectOnThePlane(const Part& part, const RestOrientation& rest) {
  double lowest = 1e300;
  for (const Vec3& v : part.mesh.vertices) lowest = std::min(lowest, (rest.part_to_world * v).z());
  EXPECT_NEAR(lowest, 0, 1e-6);
  EXPECT_TRUE((rest.part_to_world.linear() * rest.down).isApprox(-Vec3::UnitZ(), 1e-9));
  const Vec3 centre = rest.part_to_world * centreOfMass(part);
  EXPECT_NEAR(centre.head<2>().norm(), 0, 1e-6);  // above the origin
  EXPECT_NEAR(centre.z(), rest.height, 1e-6);
}

TEST(RestOrientations, CubeHasSixEqualOnes) {
  test::TempDir dir;
  Part part = brepPart(BRepPrimAPI_MakeBox(50, 50, 50).Shape(), dir, "cube.brep");
  const auto rests = restOrientations(part);
  ASSERT_EQ(rests.size(), 6u);
  for (const RestOrientation& r : rests) {
    EXPECT_NEAR(r.margin, 1.0, 1e-9);  // 25 mm to the edge over 25 mm of height
    EXPECT_NEAR(r.contact_area, 2500, 1e-6);
    expectOnThePlane(part, r);
  }
}

TEST(RestOrientations, LongBoxLiesOnItsLargestFacesFirst) {
  test::TempDir dir;
  Part part = brepPart(BRepPrimAPI_MakeBox(200, 50, 20).Shape(), dir, "box.brep");
  const auto rests = restOrientations(part);
  ASSERT_EQ(rests.size(), 6u);
  const double expected[6] = {25.0 / 10, 25.0 / 10, 10.0 / 25, 10.0 / 25, 10.0 / 100, 10.0 / 100};
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(rests[k].margin, expected[k], 1e-9) << k;
  EXPECT_NEAR(std::abs(rests[0].down.z()), 1, 1e-9);
  EXPECT_NEAR(std::abs(rests[2].down.y()), 1, 1e-9);
  EXPECT_NEAR(std::abs(rests[4].down.x()), 1, 1e-9);
}

TEST(RestOrientations, LShapedSolid) {
  // A base 100 x 40 x 20 with a column 20 x 40 x 100 at x = 0: it lies on either side
  // (the L flat), on its bottom, on its back, or tipped onto the diagonal hull face;
  // not on the column's top nor on the base's end, over which it would fall.
  test::TempDir dir;
  TopoDS_Shape l = BRepAlgoAPI_Fuse(BRepPrimAPI_MakeBox(100, 40, 20).Shape(),
                                    BRepPrimAPI_MakeBox(20, 40, 100).Shape())
                       .Shape();
  Part part = brepPart(l, dir, "l.brep");
  const Vec3 centre = centreOfMass(part);
  EXPECT_TRUE(centre.isApprox(Vec3(4640000.0 / 144000, 20, 4640000.0 / 144000), 1e-9))
      << centre.transpose();
  const auto rests = restOrientations(part);
  ASSERT_EQ(rests.size(), 5u);
  EXPECT_NEAR(std::abs(rests[0].down.y()), 1, 1e-9);  // the two sides, margin 32.2 / 20
  EXPECT_NEAR(std::abs(rests[1].down.y()), 1, 1e-9);
  EXPECT_NEAR(rests[0].margin, centre.x() / 20, 1e-9);
  std::vector<Vec3> middle = {rests[2].down, rests[3].down};  // bottom and back, margin 20 / 32.2
  EXPECT_TRUE(std::any_of(middle.begin(), middle.end(),
                          [](const Vec3& d) { return d.isApprox(-Vec3::UnitZ(), 1e-9); }));
  EXPECT_TRUE(std::any_of(middle.begin(), middle.end(),
                          [](const Vec3& d) { return d.isApprox(-Vec3::UnitX(), 1e-9); }));
  EXPECT_NEAR(rests[2].margin, 20 / centre.z(), 1e-9);
  EXPECT_TRUE(rests[4].down.isApprox(Vec3(1, 0, 1).normalized(), 1e-9));  // the diagonal
  for (const RestOrientation& r : rests) expectOnThePlane(part, r);
}

TEST(RestOrientations, OnAGivenFace) {
  test::TempDir dir;
  TopoDS_Shape l = BRepAlgoAPI_Fuse(BRepPrimAPI_MakeBox(100, 40, 20).Shape(),
                                    BRepPrimAPI_MakeBox(20, 40, 100).Shape())
                       .Shape();
  ShapeUpgrade_UnifySameDomain unify(l);  // one face per plane
  unify.Build();
  Part part = brepPart(unify.Shape(), dir, "l.brep");
  // Flat faces by where they are: the bottom, a side, the column's top, the base's top.
  auto faceAt = [&](const Vec3& lo, const Vec3& hi) {
    for (const Face& face : part.faces)
      if (face.bounds.min.isApprox(lo, 1e-6) && face.bounds.max.isApprox(hi, 1e-6)) return face.id;
    ADD_FAILURE() << "no face spanning " << lo.transpose() << " .. " << hi.transpose();
    return 0;
  };
  const int bottom = faceAt(Vec3(0, 0, 0), Vec3(100, 40, 0));
  const int side = faceAt(Vec3(0, 0, 0), Vec3(100, 0, 100));
  const int column_top = faceAt(Vec3(0, 0, 100), Vec3(20, 40, 100));
  const int base_top = faceAt(Vec3(20, 0, 20), Vec3(100, 40, 20));

  const RestOrientation on_bottom = restOnFace(part, bottom, "spec.yaml");
  EXPECT_TRUE(on_bottom.down.isApprox(-Vec3::UnitZ(), 1e-9));
  expectOnThePlane(part, on_bottom);
  EXPECT_TRUE(restOnFace(part, side, "spec.yaml").down.isApprox(-Vec3::UnitY(), 1e-9));

  auto error = [&](int face) {
    try {
      restOnFace(part, face, "spec.yaml");
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("spec.yaml"), std::string::npos);
      return std::string(e.what());
    }
    ADD_FAILURE() << "face " << face << " accepted";
    return std::string();
  };
  EXPECT_NE(error(column_top).find("not a stable rest face"), std::string::npos);  // tips over
  EXPECT_NE(error(base_top).find("not a stable rest face"), std::string::npos);    // not on hull
  EXPECT_THROW(restOnFace(part, 999, "spec.yaml"), InputError);

  const Part cylinder = brepPart(BRepPrimAPI_MakeCylinder(20, 50).Shape(), dir, "c.brep");
  for (const Face& face : cylinder.faces)
    if (face.type == SurfaceType::Cylinder) {
      EXPECT_THROW(
          {
            try {
              restOnFace(cylinder, face.id, "spec.yaml");
            } catch (const InputError& e) {
              EXPECT_NE(std::string(e.what()).find("not flat"), std::string::npos) << e.what();
              throw;
            }
          },
          InputError);
    }
}

TEST(RestOrientations, MeshPartUsesItsClosedMesh) {
  test::TempDir dir;
  TriangleMesh mesh;
  test::addCube(mesh, Vec3(10, 10, 10), 30, 1);
  Part part = test::meshPart(mesh);
  EXPECT_TRUE(centreOfMass(part).isApprox(Vec3(25, 25, 25), 1e-12));
  EXPECT_EQ(restOrientations(part).size(), 6u);
}

}  // namespace
}  // namespace scanplan
