#pragma once
// The OCCT surface of an interpolated patch (private to the library).

#include <Geom_BSplineSurface.hxx>

namespace scanplan::detail {

struct PatchSurface {
  Handle(Geom_BSplineSurface) surface;  // S(x, y) = (x, y, z(x, y)) in the patch frame
};

}  // namespace scanplan::detail
