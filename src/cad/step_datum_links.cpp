// Datum features whose faces a STEP file names by ITEM_IDENTIFIED_REPRESENTATION_USAGE.
// OCCT 7.6 links a datum to its faces through GEOMETRIC_ITEM_SPECIFIC_USAGE; the NIST CTC
// models, among others, identify the faces of most datum features (a bore's two halves, say)
// by an item-identified usage of a SET_REPRESENTATION_ITEM, whose items OCCT reads as none,
// and those datums came in on no face. The usages' items are read from the file's text, the
// features' datums and the faces from the translated model, and the links written into the
// document.

#include "cad/step_pmi_units.h"
#include "cad/xde.h"

#include <StepData_StepModel.hxx>
#include <StepDimTol_Datum.hxx>
#include <StepDimTol_DatumFeature.hxx>
#include <StepRepr_ShapeAspectRelationship.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TDF_LabelSequence.hxx>
#include <TopAbs_ShapeEnum.hxx>
#include <TransferBRep.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XCAFDoc_DimTolTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>

#include <map>
#include <string>
#include <vector>

namespace scanplan::detail {
namespace {

using FeatureNames = std::map<const Standard_Transient*, std::string>;

// Each datum feature's datum letter, from the shape aspect relationships that tie a
// DATUM_FEATURE to its DATUM.
FeatureNames datumOfFeature(const Handle(StepData_StepModel) & model) {
  FeatureNames names;
  for (int i = 1; i <= model->NbEntities(); ++i) {
    const auto relation = Handle(StepRepr_ShapeAspectRelationship)::DownCast(model->Value(i));
    if (relation.IsNull()) continue;
    const auto feature = Handle(StepDimTol_DatumFeature)::DownCast(relation->RelatingShapeAspect());
    const auto datum = Handle(StepDimTol_Datum)::DownCast(relation->RelatedShapeAspect());
    if (feature.IsNull() || datum.IsNull() || datum->Identification().IsNull()) continue;
    names[feature.get()] = datum->Identification()->ToCString();
  }
  return names;
}

// The faces each datum letter's features identify by item-identified usages, as translated.
std::map<std::string, std::vector<TopoDS_Shape>> featureFaces(
    const Handle(StepData_StepModel) & model, const Handle(Transfer_TransientProcess) & process,
    const std::map<long, std::vector<long>>& usages) {
  const FeatureNames names = datumOfFeature(model);
  std::map<long, Handle(Standard_Transient)> entities;  // the usages' ends by their #id
  for (const auto& [definition, items] : usages) {
    entities[definition];
    for (long item : items) entities[item];
  }
  for (int i = 1; i <= model->NbEntities(); ++i) {
    const auto found = entities.find(model->IdentLabel(model->Value(i)));
    if (found != entities.end()) found->second = model->Value(i);
  }
  std::map<std::string, std::vector<TopoDS_Shape>> faces;
  for (const auto& [definition, items] : usages) {
    const auto name = names.find(entities[definition].get());
    if (name == names.end()) continue;
    for (long item : items) {
      if (entities[item].IsNull()) continue;
      const TopoDS_Shape shape = TransferBRep::ShapeResult(process, entities[item]);
      if (!shape.IsNull() && shape.ShapeType() == TopAbs_FACE) faces[name->second].push_back(shape);
    }
  }
  return faces;
}

// The document's label of a face: the sub-shape label under the shape that holds it.
TDF_Label faceLabel(const Handle(XCAFDoc_ShapeTool) & shapes, const TopoDS_Shape& face) {
  TDF_Label label;
  const TDF_Label holder = shapes->FindMainShape(face);
  if (holder.IsNull()) return label;
  if (!shapes->FindSubShape(holder, face, label)) label = shapes->AddSubShape(holder, face);
  return label;
}

}  // namespace

void linkDatumsByItemUsage(XSControl_WorkSession& session, const Handle(TDocStd_Document) & doc,
                           const std::string& path) {
  const Handle(XSControl_TransferReader) reader = session.TransferReader();
  const auto model = Handle(StepData_StepModel)::DownCast(session.Model());
  const Handle(XCAFDoc_DimTolTool) tool = XCAFDoc_DocumentTool::DimTolTool(doc->Main());
  if (model.IsNull() || reader.IsNull() || reader->TransientProcess().IsNull() || tool.IsNull())
    return;
  TDF_LabelSequence datums, unlinked;
  tool->GetDatumLabels(datums);
  for (const TDF_Label& datum : datums) {
    TDF_LabelSequence first, second;
    if (!tool->GetRefShapeLabel(datum, first, second) || first.IsEmpty()) unlinked.Append(datum);
  }
  if (unlinked.IsEmpty()) return;  // the file is read again only when there is a datum to link
  const auto faces = featureFaces(model, reader->TransientProcess(), scanSetItemUsages(path));
  const Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
  for (const TDF_Label& datum : unlinked) {
    const auto found = faces.find(datumName(datum));
    if (found == faces.end()) continue;
    TDF_LabelSequence labels;
    for (const TopoDS_Shape& face : found->second) {
      const TDF_Label label = faceLabel(shapes, face);
      if (!label.IsNull()) labels.Append(label);
    }
    if (!labels.IsEmpty()) tool->SetDatum(labels, datum);
  }
}

}  // namespace scanplan::detail
