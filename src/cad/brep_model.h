#pragma once
// The B-Rep behind a Part, kept for the stages that need exact geometry (sampling on
// NURBS, trims). OCCT types stay in src/: this header is private to the library.

#include <scanplan/cad/part.h>
#include <scanplan/core/progress.h>

#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <vector>

namespace scanplan::detail {

struct BRepModel {
  TopoDS_Shape shape;                // the whole part in millimetres
  TopTools_IndexedMapOfShape faces;  // index i is face id i (1-based), MapShapes order
  std::vector<bool> reversed;        // per face id - 1: outward is opposite to faces(id)

  // Face `id` oriented so that its normal (BRepAdaptor_Surface with orientation) points
  // out of the material.
  TopoDS_Face outwardFace(int id) const;
};

// Builds faces, solids, outward orientation and the triangle mesh of `part` from a shape
// in millimetres. Names and colours, if any, are filled in by the caller afterwards.
void buildFromShape(Part& part, const TopoDS_Shape& shape, double linear_deflection,
                    double angular_deflection_rad, const Progress& progress);

}  // namespace scanplan::detail
