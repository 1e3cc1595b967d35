#include "door_panel.h"

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace scanplan::bench {
namespace {

// The skin's height over (x, y): crowned across both directions, with a character line (a
// soft step) two thirds of the way up.
double skinZ(const DoorOptions& o, double x, double y) {
  const double crown = 45 * std::sin(M_PI * x / o.width) * std::sin(M_PI * y / o.height);
  const double line = 6 * std::tanh((y - 0.6 * o.height) / 12);
  return crown + line;
}

Handle(Geom_BSplineSurface) skinSurface(const DoorOptions& o) {
  constexpr int kU = 41, kV = 41;
  TColgp_Array2OfPnt grid(1, kU, 1, kV);
  for (int i = 1; i <= kU; ++i)
    for (int j = 1; j <= kV; ++j) {
      const double x = o.width * (i - 1) / (kU - 1), y = o.height * (j - 1) / (kV - 1);
      grid.SetValue(i, j, gp_Pnt(x, y, skinZ(o, x, y)));
    }
  return GeomAPI_PointsToBSplineSurface(grid, 3, 8, GeomAbs_C2, 0.01).Surface();
}

// The window opening: the faces whose centre falls in it are left out.
bool inWindow(double s, double t) { return s > 0.12 && s < 0.88 && t > 0.68 && t < 0.94; }

void writeStep(const TopoDS_Shape& shape, const std::string& path) {
  STEPControl_Controller::Init();
  Interface_Static::SetCVal("write.step.unit", "MM");
  STEPControl_Writer writer;
  if (writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone ||
      writer.Write(path.c_str()) != IFSelect_RetDone)
    throw std::runtime_error("cannot write " + path);
}

TopoDS_Shape box(double x0, double y0, double z0, double x1, double y1, double z1) {
  return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape();
}

TopoDS_Shape markerFrame(const DoorOptions& o) {
  const double in = o.frame_gap, out = o.frame_gap + o.frame_bar;
  return BRepAlgoAPI_Cut(box(-out, -out, -40, o.width + out, o.height + out, -2),
                         box(-in, -in, -41, o.width + in, o.height + in, -1))
      .Shape();
}

// Control points on the skin: faces drawn at random (seeded), a point drawn in each.
std::string controlPoints(const DoorOptions& o, const Handle(Geom_BSplineSurface) & skin,
                          const std::vector<std::pair<int, int>>& cells) {
  std::mt19937 random(7);
  std::uniform_int_distribution<std::size_t> pick(0, cells.size() - 1);
  std::uniform_real_distribution<double> within(0.1, 0.9);
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  skin->Bounds(u0, u1, v0, v1);
  std::ostringstream csv;
  csv.precision(9);
  for (int k = 0; k < o.points; ++k) {
    const auto [i, j] = cells[pick(random)];
    const double u = u0 + (u1 - u0) * (i + within(random)) / o.columns;
    const double v = v0 + (v1 - v0) * (j + within(random)) / o.rows;
    gp_Pnt p;
    gp_Vec du, dv;
    skin->D1(u, v, p, du, dv);
    gp_Vec n = du.Crossed(dv).Normalized();
    if (n.Z() < 0) n.Reverse();
    csv << p.X() << ',' << p.Y() << ',' << p.Z() << ',' << n.X() << ',' << n.Y() << ',' << n.Z()
        << '\n';
  }
  return csv.str();
}

}  // namespace

DoorCase writeDoorCase(const std::string& folder, const DoorOptions& o) {
  const Handle(Geom_BSplineSurface) skin = skinSurface(o);
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  skin->Bounds(u0, u1, v0, v1);
  BRepBuilderAPI_Sewing sewing(1e-3);
  std::vector<std::pair<int, int>> cells;
  for (int i = 0; i < o.columns; ++i)
    for (int j = 0; j < o.rows; ++j) {
      if (inWindow((i + 0.5) / o.columns, (j + 0.5) / o.rows)) continue;
      const double a = u0 + (u1 - u0) * i / o.columns, b = u0 + (u1 - u0) * (i + 1) / o.columns;
      const double c = v0 + (v1 - v0) * j / o.rows, d = v0 + (v1 - v0) * (j + 1) / o.rows;
      // Each face on its own piece of the skin, as a CAD system writes them.
      const Handle(Geom_BSplineSurface) piece = Handle(Geom_BSplineSurface)::DownCast(skin->Copy());
      piece->Segment(a, b, c, d);
      sewing.Add(BRepBuilderAPI_MakeFace(piece, 1e-6).Face());
      cells.emplace_back(i, j);
    }
  sewing.Perform();
  DoorCase written;
  written.faces = static_cast<int>(cells.size());
  written.part = folder + "/door.step";
  written.frame = folder + "/frame.step";
  written.points = folder + "/points.csv";
  written.spec = folder + "/spec.yaml";
  writeStep(sewing.SewedShape(), written.part);
  writeStep(markerFrame(o), written.frame);
  std::ofstream(written.points) << controlPoints(o, skin, cells);
  std::ofstream(written.spec) << (o.scanner.empty() ? "" : "scanner: " + o.scanner + "\n")
                              << "part: {file: door.step}\n"
                              << "fixtures: [{file: frame.step}]\n"
                              << "markers: {grid: " << o.marker_step << ", on: fixture}\n"
                              << "cell: {working_plane: false}\n"
                              << "tasks: [{type: points, file: points.csv}]\n";
  return written;
}

}  // namespace scanplan::bench
