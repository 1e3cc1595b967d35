#include "cad/xde.h"

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <Bnd_Box.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TDF_LabelSequence.hxx>
#include <TopoDS_Vertex.hxx>
#include <XCAFDimTolObjects_DatumObject.hxx>
#include <XCAFDimTolObjects_DimensionObject.hxx>
#include <XCAFDimTolObjects_GeomToleranceObject.hxx>
#include <XCAFDoc_Datum.hxx>
#include <XCAFDoc_DimTolTool.hxx>
#include <XCAFDoc_Dimension.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_GeomTolerance.hxx>

#include <algorithm>
#include <cmath>

namespace scanplan::detail {
namespace {

std::string toleranceType(XCAFDimTolObjects_GeomToleranceType type) {
  switch (type) {
    case XCAFDimTolObjects_GeomToleranceType_Angularity: return "angularity";
    case XCAFDimTolObjects_GeomToleranceType_CircularRunout: return "circular_runout";
    case XCAFDimTolObjects_GeomToleranceType_CircularityOrRoundness: return "circularity";
    case XCAFDimTolObjects_GeomToleranceType_Coaxiality: return "coaxiality";
    case XCAFDimTolObjects_GeomToleranceType_Concentricity: return "concentricity";
    case XCAFDimTolObjects_GeomToleranceType_Cylindricity: return "cylindricity";
    case XCAFDimTolObjects_GeomToleranceType_Flatness: return "flatness";
    case XCAFDimTolObjects_GeomToleranceType_Parallelism: return "parallelism";
    case XCAFDimTolObjects_GeomToleranceType_Perpendicularity: return "perpendicularity";
    case XCAFDimTolObjects_GeomToleranceType_Position: return "position";
    case XCAFDimTolObjects_GeomToleranceType_ProfileOfLine: return "profile_of_line";
    case XCAFDimTolObjects_GeomToleranceType_ProfileOfSurface: return "profile_of_surface";
    case XCAFDimTolObjects_GeomToleranceType_Straightness: return "straightness";
    case XCAFDimTolObjects_GeomToleranceType_Symmetry: return "symmetry";
    case XCAFDimTolObjects_GeomToleranceType_TotalRunout: return "total_runout";
    default: return "unknown";
  }
}

std::string dimensionType(XCAFDimTolObjects_DimensionType type) {
  switch (type) {
    case XCAFDimTolObjects_DimensionType_Location_CurvedDistance: return "curved_distance";
    case XCAFDimTolObjects_DimensionType_Location_LinearDistance:
    case XCAFDimTolObjects_DimensionType_Location_LinearDistance_FromCenterToOuter:
    case XCAFDimTolObjects_DimensionType_Location_LinearDistance_FromCenterToInner:
    case XCAFDimTolObjects_DimensionType_Location_LinearDistance_FromOuterToCenter:
    case XCAFDimTolObjects_DimensionType_Location_LinearDistance_FromOuterToOuter:
    case XCAFDimTolObjects_DimensionType_Location_LinearDistance_FromOuterToInner:
    case XCAFDimTolObjects_DimensionType_Location_LinearDistance_FromInnerToCenter:
    case XCAFDimTolObjects_DimensionType_Location_LinearDistance_FromInnerToOuter:
    case XCAFDimTolObjects_DimensionType_Location_LinearDistance_FromInnerToInner:
      return "linear_distance";
    case XCAFDimTolObjects_DimensionType_Location_Angular: return "angular_location";
    case XCAFDimTolObjects_DimensionType_Location_Oriented: return "oriented_location";
    case XCAFDimTolObjects_DimensionType_Location_WithPath: return "location_with_path";
    case XCAFDimTolObjects_DimensionType_Size_CurveLength: return "curve_length";
    case XCAFDimTolObjects_DimensionType_Size_Diameter: return "diameter";
    case XCAFDimTolObjects_DimensionType_Size_SphericalDiameter: return "spherical_diameter";
    case XCAFDimTolObjects_DimensionType_Size_Radius: return "radius";
    case XCAFDimTolObjects_DimensionType_Size_SphericalRadius: return "spherical_radius";
    case XCAFDimTolObjects_DimensionType_Size_ToroidalMinorDiameter:
    case XCAFDimTolObjects_DimensionType_Size_ToroidalMajorDiameter:
    case XCAFDimTolObjects_DimensionType_Size_ToroidalHighMajorDiameter:
    case XCAFDimTolObjects_DimensionType_Size_ToroidalLowMajorDiameter: return "toroidal_diameter";
    case XCAFDimTolObjects_DimensionType_Size_ToroidalMinorRadius:
    case XCAFDimTolObjects_DimensionType_Size_ToroidalMajorRadius:
    case XCAFDimTolObjects_DimensionType_Size_ToroidalHighMajorRadius:
    case XCAFDimTolObjects_DimensionType_Size_ToroidalLowMajorRadius: return "toroidal_radius";
    case XCAFDimTolObjects_DimensionType_Size_Thickness: return "thickness";
    case XCAFDimTolObjects_DimensionType_Size_Angular: return "angular_size";
    case XCAFDimTolObjects_DimensionType_Size_WithPath: return "size_with_path";
    case XCAFDimTolObjects_DimensionType_CommonLabel: return "common_label";
    case XCAFDimTolObjects_DimensionType_DimensionPresentation: return "presentation";
    default: return "other";
  }
}

// Faces of all shapes a GD&T label is attached to (both ends of a dimension).
std::vector<int> attachedFaces(const Handle(XCAFDoc_DimTolTool) & tool, const TDF_Label& label,
                               const XdeFaceLookup& lookup) {
  TDF_LabelSequence first, second;
  tool->GetRefShapeLabel(label, first, second);
  std::vector<int> ids;
  for (const TDF_LabelSequence* seq : {&first, &second})
    for (const TDF_Label& shape_label : *seq) {
      std::vector<int> more = lookup.faceIds(shape_label);
      ids.insert(ids.end(), more.begin(), more.end());
    }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

// Where a datum stands in its tolerance's reference frame: 1 primary, 2 secondary, ...; 0
// when the file does not say.
int datumPosition(const TDF_Label& label) {
  Handle(XCAFDoc_Datum) datum;
  if (!label.FindAttribute(XCAFDoc_Datum::GetID(), datum)) return 0;
  Handle(XCAFDimTolObjects_DatumObject) object = datum->GetObject();
  return object.IsNull() ? 0 : object->GetPosition();
}

// A tolerance's datum references in precedence: datums the file puts at the same place of
// the frame (a common datum, COMMON_DATUM_LIST) joined as "A-B".
std::vector<std::string> datumReferences(const TDF_LabelSequence& datums) {
  std::vector<std::string> references;
  int last = -1;
  for (const TDF_Label& datum : datums) {
    const int position = datumPosition(datum);
    if (position > 0 && position == last && !references.empty()) {
      const std::string name = datumName(datum);
      references.back().append(1, '-').append(name);
    } else {
      references.push_back(datumName(datum));
    }
    last = position;
  }
  return references;
}

bool isAngular(const std::string& dimension_type) {
  return dimension_type == "angular_location" || dimension_type == "angular_size";
}

// How far from a face a datum target's point may lie and still be on it, mm.
constexpr double kOnFace = 0.01;

// The faces a datum target point lies on (NIST CTC 02's datums A, B and C are three, two and
// one target points): those within kOnFace of it. The faces stand for the datum, which is
// the plane or line through its targets. Targets of other kinds (lines, areas) are placed
// by a corner or an end that may lie on a neighbouring face, and are left unlinked. The
// faces' boxes are found once, at the first target (a file repeats each target for every
// tolerance that refers to its datum).
class TargetFaces {
 public:
  explicit TargetFaces(const BRepModel& model) : model_(model) {}

  std::vector<int> operator()(const TDF_Label& label) {
    Handle(XCAFDoc_Datum) datum;
    if (!label.FindAttribute(XCAFDoc_Datum::GetID(), datum)) return {};
    const Handle(XCAFDimTolObjects_DatumObject) object = datum->GetObject();
    if (object.IsNull() || !object->IsDatumTarget() || !object->HasDatumTargetParams() ||
        object->GetDatumTargetType() != XCAFDimTolObjects_DatumTargetType_Point)
      return {};
    if (boxes_.empty())
      for (int id = 1; id <= model_.faces.Extent(); ++id) {
        Bnd_Box& box = boxes_.emplace_back();
        BRepBndLib::Add(model_.faces(id), box);
        box.Enlarge(kOnFace);
      }
    const gp_Pnt at = object->GetDatumTargetAxis().Location();
    const TopoDS_Vertex point = BRepBuilderAPI_MakeVertex(at);
    std::vector<int> ids;
    for (int id = 1; id <= model_.faces.Extent(); ++id) {
      if (boxes_[id - 1].IsOut(at)) continue;
      BRepExtrema_DistShapeShape distance(point, model_.faces(id));
      if (distance.IsDone() && distance.Value() <= kOnFace) ids.push_back(id);
    }
    return ids;
  }

 private:
  const BRepModel& model_;
  std::vector<Bnd_Box> boxes_;  // per face id - 1, grown by kOnFace
};

}  // namespace

std::string datumName(const TDF_Label& label) {
  Handle(XCAFDoc_Datum) datum;
  if (!label.FindAttribute(XCAFDoc_Datum::GetID(), datum)) return {};
  Handle(XCAFDimTolObjects_DatumObject) object = datum->GetObject();
  if (object.IsNull() || object->GetName().IsNull()) return {};
  return object->GetName()->String().ToCString();
}

namespace {

// The geometric tolerance at `label`: its type, its value (from the file's own measure
// where XDE gives none), its datums and faces.
GeometricTolerance toleranceAt(const Handle(XCAFDoc_DimTolTool) & tool, const TDF_Label& label,
                               const XdeFaceLookup& lookup, const StepPmiMeasures& measures) {
  GeometricTolerance tolerance;
  Handle(XCAFDoc_GeomTolerance) attribute;
  if (label.FindAttribute(XCAFDoc_GeomTolerance::GetID(), attribute)) {
    Handle(XCAFDimTolObjects_GeomToleranceObject) object = attribute->GetObject();
    if (!object.IsNull()) {
      tolerance.type = toleranceType(object->GetType());
      tolerance.value = object->GetValue();
      Handle(TCollection_HAsciiString) name = object->GetSemanticName();
      if (tolerance.value == 0 && !name.IsNull()) {
        auto found = measures.tolerance_magnitudes.find(name->ToCString());
        if (found != measures.tolerance_magnitudes.end()) tolerance.value = found->second;
      }
    }
  }
  TDF_LabelSequence datums;
  tool->GetDatumWithObjectOfTolerLabels(label, datums);
  tolerance.datums = datumReferences(datums);
  tolerance.faces = attachedFaces(tool, label, lookup);
  return tolerance;
}

// The dimension at `label`: its type, its nominal value in mm (degrees for angles), its
// limits and faces.
Dimension dimensionAt(const Handle(XCAFDoc_DimTolTool) & tool, const TDF_Label& label,
                      const XdeFaceLookup& lookup, const StepPmiMeasures& measures) {
  Dimension dimension;
  Handle(XCAFDoc_Dimension) attribute;
  if (label.FindAttribute(XCAFDoc_Dimension::GetID(), attribute)) {
    Handle(XCAFDimTolObjects_DimensionObject) object = attribute->GetObject();
    if (!object.IsNull()) {
      dimension.type = dimensionType(object->GetType());
      if (!object->GetValues().IsNull()) dimension.value = object->GetValue();
      if (!isAngular(dimension.type)) dimension.value *= measures.nominal_value_scale;
      if (object->IsDimWithPlusMinusTolerance()) {
        dimension.lower = std::abs(object->GetLowerTolValue());
        dimension.upper = std::abs(object->GetUpperTolValue());
      }
    }
  }
  dimension.faces = attachedFaces(tool, label, lookup);
  return dimension;
}

// The datums of the document by name, each with the faces of all its labels (or of its
// target points), sorted by name; `labels` gets how many datum labels there are.
std::vector<Datum> datumsOf(const Handle(XCAFDoc_DimTolTool) & tool, const XdeFaceLookup& lookup,
                            std::size_t& labels) {
  TDF_LabelSequence sequence;
  tool->GetDatumLabels(sequence);
  labels = static_cast<std::size_t>(sequence.Length());
  std::vector<Datum> datums;
  TargetFaces targetFaces(*lookup.model);
  for (const TDF_Label& label : sequence) {
    std::string name = datumName(label);
    auto same =
        std::find_if(datums.begin(), datums.end(), [&](const Datum& d) { return d.name == name; });
    if (same == datums.end()) same = datums.insert(datums.end(), Datum{name, {}});
    std::vector<int> faces = attachedFaces(tool, label, lookup);
    if (faces.empty()) faces = targetFaces(label);
    same->faces.insert(same->faces.end(), faces.begin(), faces.end());
    std::sort(same->faces.begin(), same->faces.end());
    same->faces.erase(std::unique(same->faces.begin(), same->faces.end()), same->faces.end());
  }
  std::sort(datums.begin(), datums.end(),
            [](const Datum& a, const Datum& b) { return a.name < b.name; });
  return datums;
}

}  // namespace

Gdt readGdt(const Handle(TDocStd_Document) & doc, const XdeFaceLookup& lookup,
            const std::string& path) {
  Gdt gdt;
  Handle(XCAFDoc_DimTolTool) tool = XCAFDoc_DocumentTool::DimTolTool(doc->Main());
  if (tool.IsNull()) return gdt;
  TDF_LabelSequence tolerances, dimensions;
  tool->GetGeomToleranceLabels(tolerances);
  tool->GetDimensionLabels(dimensions);
  // The file is scanned again only when there is something to complete.
  const StepPmiMeasures measures =
      tolerances.IsEmpty() && dimensions.IsEmpty() ? StepPmiMeasures{} : scanStepPmiMeasures(path);
  for (const TDF_Label& label : tolerances)
    gdt.tolerances.push_back(toleranceAt(tool, label, lookup, measures));
  for (const TDF_Label& label : dimensions)
    gdt.dimensions.push_back(dimensionAt(tool, label, lookup, measures));
  gdt.datums = datumsOf(tool, lookup, gdt.datum_labels);
  return gdt;
}

}  // namespace scanplan::detail
