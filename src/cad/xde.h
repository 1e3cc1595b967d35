#pragma once
// Helpers over an OCCT XDE document (private to the library): resolving shape labels to
// the part's face ids, and reading GD&T.

#include "cad/brep_model.h"
#include "cad/step_pmi_units.h"

#include <TDF_Label.hxx>
#include <TDocStd_Document.hxx>
#include <TopLoc_Location.hxx>
#include <XSControl_WorkSession.hxx>

#include <map>
#include <string>
#include <vector>

namespace scanplan::detail {

// Where each XDE shape label lands in the part: the placements of every instance of a
// part label in the assembly, so that a label's faces can be found in the face map.
struct XdeFaceLookup {
  const BRepModel* model = nullptr;
  std::map<std::string, std::vector<TopLoc_Location>> placements;  // label entry → instances

  // Sorted, unique 1-based ids of the faces under `label` (a shape or sub-shape label).
  std::vector<int> faceIds(const TDF_Label& label) const;
};

std::string labelEntry(const TDF_Label& label);
std::string labelName(const TDF_Label& label);  // TDataStd_Name, or ""
std::string datumName(const TDF_Label& label);  // a datum label's letter, or ""

// Geometric tolerances, dimensions and datums of the document's AP242 semantic PMI, with
// the values OCCT misses taken from the measures of the STEP file at `path`
// (scanStepPmiMeasures), scanned only when the document has tolerances or dimensions.
// Links the document's datums that have no face to the faces their features identify by an
// ITEM_IDENTIFIED_REPRESENTATION_USAGE of a SET_REPRESENTATION_ITEM, which OCCT 7.6's
// translation leaves out, from the session that read and transferred the STEP file at
// `path` into `doc`.
void linkDatumsByItemUsage(XSControl_WorkSession& session, const Handle(TDocStd_Document) & doc,
                           const std::string& path);

Gdt readGdt(const Handle(TDocStd_Document) & doc, const XdeFaceLookup& lookup,
            const std::string& path);

}  // namespace scanplan::detail
