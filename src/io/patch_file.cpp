// Interpolated patches written as STEP or BREP faces, each a rectangle of the B-spline
// surface's parameters.

#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/patch_file.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Precision.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopoDS_Compound.hxx>

#include <filesystem>

namespace scanplan {
namespace {

Handle(Geom_BSplineSurface) occtSurface(const BSplineSurface& s) {
  TColgp_Array2OfPnt poles(1, s.u_poles, 1, s.v_poles);
  TColStd_Array2OfReal weights(1, s.u_poles, 1, s.v_poles);
  for (int j = 0; j < s.v_poles; ++j)
    for (int i = 0; i < s.u_poles; ++i) {
      const std::size_t k = static_cast<std::size_t>(i + s.u_poles * j);
      poles(i + 1, j + 1) = gp_Pnt(s.poles[k].x(), s.poles[k].y(), s.poles[k].z());
      weights(i + 1, j + 1) = s.weights.empty() ? 1.0 : s.weights[k];
    }
  auto knots = [](const std::vector<double>& values, const std::vector<int>& multiplicities,
                  TColStd_Array1OfReal& k, TColStd_Array1OfInteger& m) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      k(static_cast<int>(i) + 1) = values[i];
      m(static_cast<int>(i) + 1) = multiplicities[i];
    }
  };
  const int nu = static_cast<int>(s.u_knots.size()), nv = static_cast<int>(s.v_knots.size());
  TColStd_Array1OfReal u_knots(1, nu), v_knots(1, nv);
  TColStd_Array1OfInteger u_mults(1, nu), v_mults(1, nv);
  knots(s.u_knots, s.u_multiplicities, u_knots, u_mults);
  knots(s.v_knots, s.v_multiplicities, v_knots, v_mults);
  if (s.weights.empty())
    return new Geom_BSplineSurface(poles, u_knots, v_knots, u_mults, v_mults, s.u_degree,
                                   s.v_degree);
  return new Geom_BSplineSurface(poles, weights, u_knots, v_knots, u_mults, v_mults, s.u_degree,
                                 s.v_degree);
}

}  // namespace

void writePatch(const PatchShape& patch, const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  const bool step = extension == ".step" || extension == ".stp";
  if (!step && extension != ".brep")
    throw OutputError(path, "a patch is written as .step, .stp or .brep");
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  try {
    const Handle(Geom_BSplineSurface) surface = occtSurface(patch.surface);
    for (const auto& [x0, x1, y0, y1] : patch.faces) {
      BRepBuilderAPI_MakeFace face(surface, x0, x1, y0, y1, Precision::Confusion());
      if (face.IsDone()) builder.Add(compound, face.Face());
    }
  } catch (const Standard_Failure&) {
    throw OutputError(path, "cannot make the faces of the interpolated patch");
  }
  writeFileAtomically(path, [&](const std::string& temporary) {
    bool written = false;
    try {
      if (step) {
        STEPControl_Writer writer;
        written = writer.Transfer(compound, STEPControl_AsIs) == IFSelect_RetDone &&
                  writer.Write(temporary.c_str()) == IFSelect_RetDone;
      } else {
        written = BRepTools::Write(compound, temporary.c_str());
      }
    } catch (const Standard_Failure&) {
      written = false;
    }
    if (!written) throw OutputError(path, "cannot write the interpolated patch");
  });
}

}  // namespace scanplan
