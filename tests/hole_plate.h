#pragma once
// A plate with a hole and its GD&T, a plate with two bores, and views tilted into a bore,
// shared by the tests of the inspection, of the capability model and of the planner's aim.

#include "support.h"

#include <scanplan/cad/gdt.h>
#include <scanplan/cad/import.h>
#include <scanplan/core/view.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepTools.hxx>
#include <gp_Ax2.hxx>

#include <vector>

namespace scanplan::test {

// A 200 x 100 x `thickness` mm plate with a through hole of 20 mm at (100, 50); datum A its top,
// B its side x = 0, C its side y = 0; the hole's position to A, B, C (0.5), the top's
// flatness (0.1) and the hole's diameter (20 +-0.1).
struct HolePlate {
  Part part;
  int top = 0, side_x = 0, side_y = 0;
  std::vector<int> hole;
  std::vector<Characteristic> characteristics;
};

inline HolePlate holePlate(const test::TempDir& dir, double thickness = 20) {
  const TopoDS_Shape plate = BRepPrimAPI_MakeBox(200, 100, thickness).Shape();
  const TopoDS_Shape drill =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(100, 50, -1), gp_Dir(0, 0, 1)), 10, thickness + 2)
          .Shape();
  BRepTools::Write(BRepAlgoAPI_Cut(plate, drill).Shape(), dir.file("plate.brep").c_str());
  HolePlate p;
  p.part = importPart(dir.file("plate.brep"));
  for (const Face& f : p.part.faces) {
    if (f.type == SurfaceType::Cylinder) p.hole.push_back(f.id);
    if (f.type != SurfaceType::Plane) continue;
    if (f.bounds.min.z() > thickness - 0.01) p.top = f.id;
    if (f.bounds.max.x() < 0.01) p.side_x = f.id;
    if (f.bounds.max.y() < 0.01) p.side_y = f.id;
  }
  p.part.gdt.datums = {{"A", {p.top}}, {"B", {p.side_x}}, {"C", {p.side_y}}};
  Characteristic position{1, "position", false, 0.5, 0, 0.5, {"A", "B", "C"}, p.hole};
  Characteristic flatness{2, "flatness", false, 0.1, 0, 0.1, {}, {p.top}};
  Characteristic diameter{3, "diameter", true, 20, 19.9, 20.1, {}, p.hole};
  p.characteristics = {position, flatness, diameter};
  return p;
}

// A view of id `id` at `standoff` from `target`, looking down at it from 50° off the
// vertical, from the side at `azimuth` (radians, from +x about z).
inline View tiltedView(int id, const Vec3& target, double standoff, double azimuth) {
  const double tilt = radians(50);
  const Vec3 towards(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth),
                     std::cos(tilt));
  const Vec3 z = -towards, x = z.cross(Vec3::UnitZ()).normalized(), y = z.cross(x);
  View view;
  view.id = id;
  view.target = target;
  view.camera_to_world.linear() << x, y, z;
  view.camera_to_world.translation() = target + standoff * towards;
  return view;
}

// A `length` x 100 x 20 mm plate with Ø20 through bores at (x, 50) for each of `xs`.
inline Part boredPlate(const test::TempDir& dir, double length, const std::vector<double>& xs) {
  TopoDS_Shape plate = BRepPrimAPI_MakeBox(length, 100, 20).Shape();
  for (const double x : xs)
    plate =
        BRepAlgoAPI_Cut(
            plate,
            BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, 50, -1), gp_Dir(0, 0, 1)), 10, 22).Shape())
            .Shape();
  BRepTools::Write(plate, dir.file("bored.brep").c_str());
  return importPart(dir.file("bored.brep"));
}

// A 700 x 100 x 20 mm plate with two Ø20 through bores 500 mm apart, at (100, 50) and
// (600, 50): datum A its top, B the first bore; the second bore's position to A and B
// (0.5).
struct TwoBorePlate {
  Part part;
  int top = 0;
  std::vector<int> first, second;  // the bores' faces
  Characteristic position;
};

inline TwoBorePlate twoBorePlate(const test::TempDir& dir) {
  TwoBorePlate p;
  p.part = boredPlate(dir, 700, {100, 600});
  for (const Face& f : p.part.faces) {
    if (f.type == SurfaceType::Cylinder)
      (f.bounds.max.x() < 350 ? p.first : p.second).push_back(f.id);
    if (f.type == SurfaceType::Plane && f.bounds.min.z() > 19.99) p.top = f.id;
  }
  p.part.gdt.datums = {{"A", {p.top}}, {"B", p.first}};
  p.position = {1, "position", false, 0.5, 0, 0.5, {"A", "B"}, p.second};
  return p;
}

}  // namespace scanplan::test
