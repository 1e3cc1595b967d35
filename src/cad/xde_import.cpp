// STEP, IGES and BREP import through OCCT's XDE document, which keeps names, colours,
// assembly structure and (for STEP AP242) semantic PMI.

#include "cad/brep_import.h"
#include "cad/xde.h"

#include <scanplan/core/errors.h>
#include <scanplan/core/geometry.h>
#include <scanplan/core/isolated.h>

#include <BRepBndLib.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BinTools.hxx>
#include <BinXCAFDrivers.hxx>
#include <Bnd_Box.hxx>
#include <IGESCAFControl_Reader.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <Interface_InterfaceModel.hxx>
#include <Interface_Static.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Controller.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_OutOfMemory.hxx>
#include <StepBasic_ConversionBasedUnitAndLengthUnit.hxx>
#include <StepBasic_HArray1OfNamedUnit.hxx>
#include <StepData_StepModel.hxx>
#include <StepGeom_Curve.hxx>
#include <StepGeom_GeomRepContextAndGlobUnitAssCtxAndGlobUncertaintyAssCtx.hxx>
#include <StepGeom_GeometricRepresentationContextAndGlobalUnitAssignedContext.hxx>
#include <StepGeom_Direction.hxx>
#include <StepGeom_Placement.hxx>
#include <StepGeom_Point.hxx>
#include <StepGeom_Surface.hxx>
#include <StepGeom_Vector.hxx>
#include <StepShape_TopologicalRepresentationItem.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TCollection_AsciiString.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDF_Tool.hxx>
#include <TDataStd_Name.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS_Compound.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <XSControl_WorkSession.hxx>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>
#include <new>
#include <sstream>

namespace scanplan::detail {

std::string labelEntry(const TDF_Label& label) {
  TCollection_AsciiString entry;
  TDF_Tool::Entry(label, entry);
  return entry.ToCString();
}

std::string labelName(const TDF_Label& label) {
  Handle(TDataStd_Name) name;
  if (!label.FindAttribute(TDataStd_Name::GetID(), name)) return {};
  TCollection_AsciiString text(name->Get());
  return text.ToCString();
}

std::vector<int> XdeFaceLookup::faceIds(const TDF_Label& label) const {
  std::vector<int> ids;
  TopoDS_Shape shape = XCAFDoc_ShapeTool::GetShape(label);
  if (shape.IsNull()) return ids;
  // A sub-shape label lives under its part's label; the part may be placed several times.
  TDF_Label part = XCAFDoc_ShapeTool::IsSubShape(label) ? label.Father() : label;
  auto found = placements.find(labelEntry(part));
  std::vector<TopLoc_Location> locations =
      found != placements.end() ? found->second : std::vector<TopLoc_Location>{TopLoc_Location()};
  for (const TopLoc_Location& location : locations)
    for (TopExp_Explorer it(shape.Moved(location), TopAbs_FACE); it.More(); it.Next()) {
      int id = model->faces.FindIndex(it.Current());
      if (id > 0) ids.push_back(id);
    }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

namespace {

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// Millimetres per unit for the length unit names STEP and IGES use.
double millimetresPer(const std::string& unit) {
  std::string u = lowercase(unit);
  if (u == "mm" || u == "millimetre" || u == "millimeter") return 1;
  if (u == "cm" || u == "centimetre" || u == "centimeter") return 10;
  if (u == "m" || u == "metre" || u == "meter") return 1000;
  if (u == "in" || u == "inch") return 25.4;
  if (u == "ft" || u == "foot") return 304.8;
  if (u == "um" || u == "micron" || u == "micrometre") return 1e-3;
  return 0;
}

// The name of the conversion-based length unit (inch, foot) a geometric context of the
// STEP model assigns; empty when none does. OCCT's FileUnits names such a unit only when
// its factor is a LENGTH_MEASURE_WITH_UNIT, and leaves the name empty for a plain
// MEASURE_WITH_UNIT(LENGTH_MEASURE(..)), as NIST CTC 05 writes its inch.
std::string conversionLengthUnit(const Handle(StepData_StepModel) & model) {
  for (Standard_Integer i = 1; i <= model->NbEntities(); ++i) {
    Handle(StepBasic_HArray1OfNamedUnit) units;
    const Handle(Standard_Transient) entity = model->Value(i);
    if (auto a = Handle(StepGeom_GeomRepContextAndGlobUnitAssCtxAndGlobUncertaintyAssCtx)::DownCast(
            entity))
      units = a->Units();
    else if (auto b =
                 Handle(StepGeom_GeometricRepresentationContextAndGlobalUnitAssignedContext)::DownCast(
                     entity))
      units = b->Units();
    if (units.IsNull()) continue;
    for (Standard_Integer k = units->Lower(); k <= units->Upper(); ++k)
      if (auto length = Handle(StepBasic_ConversionBasedUnitAndLengthUnit)::DownCast(units->Value(k));
          !length.IsNull() && !length->Name().IsNull())
        return lowercase(length->Name()->ToCString());
  }
  return "";
}

// Walks the XDE assembly tree: records where every part label is placed, the name of
// each solid, and the names and colours attached to shapes and sub-shapes.
class XdeWalker {
 public:
  XdeWalker(const Handle(TDocStd_Document) & doc, Part& part, const BRepModel& model,
            XdeFaceLookup& lookup)
      : shapes_(XCAFDoc_DocumentTool::ShapeTool(doc->Main())),
        colors_(XCAFDoc_DocumentTool::ColorTool(doc->Main())),
        part_(part),
        model_(model),
        lookup_(lookup) {
    TopExp::MapShapes(model.shape, TopAbs_SOLID, solids_);
  }

  void walk(const TDF_Label& label, const TopLoc_Location& location) {
    if (XCAFDoc_ShapeTool::IsAssembly(label)) {
      TDF_LabelSequence components;
      XCAFDoc_ShapeTool::GetComponents(label, components);
      for (const TDF_Label& component : components) {
        TDF_Label referred;
        if (!XCAFDoc_ShapeTool::GetReferredShape(component, referred)) continue;
        walk(referred, location * XCAFDoc_ShapeTool::GetLocation(component));
      }
      return;
    }
    lookup_.placements[labelEntry(label)].push_back(location);
    TopoDS_Shape shape = XCAFDoc_ShapeTool::GetShape(label).Moved(location);
    std::string name = labelName(label);
    for (TopExp_Explorer it(shape, TopAbs_SOLID); it.More(); it.Next()) {
      int s = solids_.FindIndex(it.Current());
      if (s > 0 && part_.solids[s - 1].name.empty()) part_.solids[s - 1].name = name;
    }
    annotate(label, shape, /*name_faces=*/false);
    TDF_LabelSequence subs;
    XCAFDoc_ShapeTool::GetSubShapes(label, subs);
    for (const TDF_Label& sub : subs)
      annotate(sub, XCAFDoc_ShapeTool::GetShape(sub).Moved(location), /*name_faces=*/true);
  }

 private:
  // Gives the faces of `shape` the colour (and, for sub-shapes, the name) of `label`.
  void annotate(const TDF_Label& label, const TopoDS_Shape& shape, bool name_faces) {
    Quantity_Color color;
    bool has_color = !colors_.IsNull() && (colors_->GetColor(label, XCAFDoc_ColorSurf, color) ||
                                           colors_->GetColor(label, XCAFDoc_ColorGen, color));
    std::string name = name_faces ? labelName(label) : std::string();
    if (!has_color && name.empty()) return;
    for (TopExp_Explorer it(shape, TopAbs_FACE); it.More(); it.Next()) {
      int id = model_.faces.FindIndex(it.Current());
      if (id <= 0) continue;
      Face& face = part_.faces[id - 1];
      if (has_color)
        face.color = Color{static_cast<float>(color.Red()), static_cast<float>(color.Green()),
                           static_cast<float>(color.Blue())};
      if (!name.empty()) face.name = name;
    }
  }

  Handle(XCAFDoc_ShapeTool) shapes_;
  Handle(XCAFDoc_ColorTool) colors_;
  Part& part_;
  const BRepModel& model_;
  XdeFaceLookup& lookup_;
  TopTools_IndexedMapOfShape solids_;
};

// OCCT's XDE application, which stores and retrieves documents in its binary format.
Handle(XCAFApp_Application) application() {
  static std::once_flag defined;
  std::call_once(defined,
                 [] { BinXCAFDrivers::DefineFormat(XCAFApp_Application::GetApplication()); });
  return XCAFApp_Application::GetApplication();
}

// A new XDE document, in the binary format it is handed on in.
Handle(TDocStd_Document) newDocument() {
  Handle(TDocStd_Document) doc;
  application()->NewDocument("BinXCAF", doc);
  return doc;
}

// Points, directions, placements, curves, surfaces and topology: what the shape
// translator reads (presentation and PMI entities are not).
bool isShapeGeometry(const Handle(Standard_Transient) & entity) {
  for (const Handle(Standard_Type) & type :
       {STANDARD_TYPE(StepGeom_Point), STANDARD_TYPE(StepGeom_Direction),
        STANDARD_TYPE(StepGeom_Vector), STANDARD_TYPE(StepGeom_Placement),
        STANDARD_TYPE(StepGeom_Curve), STANDARD_TYPE(StepGeom_Surface),
        STANDARD_TYPE(StepShape_TopologicalRepresentationItem)})
    if (entity->IsKind(type)) return true;
  return false;
}

// A geometric or topological entity the STEP parser could not read as its type (a
// parameter missing, or of the wrong kind) is left half-made, and OCCT's translator
// follows it into a crash: the file is refused, naming the entity. (Files in use carry
// such failures in their PMI, which the translator tolerates.)
void refuseBrokenGeometry(XSControl_Reader& reader, const std::string& path) {
  const Handle(XSControl_WorkSession) session = reader.WS();
  const Handle(Interface_InterfaceModel) model = session->Model();
  const Interface_CheckIterator checks = session->ModelCheckList(false);
  for (checks.Start(); checks.More(); checks.Next()) {
    const int number = checks.Number();
    if (!checks.Value()->HasFailed() || number < 1 || number > model->NbEntities()) continue;
    const Handle(Standard_Transient) entity = model->Value(number);
    if (!isShapeGeometry(entity)) continue;
    throw InputError(path, "entity " + std::string(model->StringLabel(entity)->ToCString()) + " (" +
                               entity->DynamicType()->Name() +
                               ") cannot be read: " + checks.Value()->CFail(1));
  }
}

// Reads a STEP or IGES file into a new XDE document, filling the file's declared unit.
Handle(TDocStd_Document) readExchangeFile(const std::string& path, const std::string& format,
                                          const ImportOptions& options, Part& part) {
  Handle(TDocStd_Document) doc = newDocument();
  // Shapes are converted to millimetres on transfer, whatever the file declares. The
  // controllers declare the static parameter; setting it before they run is a no-op.
  STEPCAFControl_Controller::Init();
  IGESControl_Controller::Init();
  Interface_Static::SetCVal("xstep.cascade.unit", "MM");
  Interface_Static::SetIVal("read.stepcaf.subshapes.name", 1);  // face names, e.g. DATUM_A
  if (format == "STEP") {
    STEPCAFControl_Reader reader;
    reader.SetColorMode(true);
    reader.SetNameMode(true);
    reader.SetLayerMode(false);
    reader.SetPropsMode(false);
    reader.SetGDTMode(options.read_gdt);
    reader.SetMatMode(false);
    reader.SetViewMode(false);
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
      throw InputError(path, "not a readable STEP file: the STEP parser rejected it");
    refuseBrokenGeometry(reader.ChangeReader(), path);
    TColStd_SequenceOfAsciiString lengths, angles, solid_angles;
    reader.ChangeReader().FileUnits(lengths, angles, solid_angles);
    if (!lengths.IsEmpty()) part.file_unit = lowercase(lengths.First().ToCString());
    if (!lengths.IsEmpty() && part.file_unit.empty())
      part.file_unit = conversionLengthUnit(reader.ChangeReader().StepModel());
    if (!reader.Transfer(doc))
      throw InputError(path, "no geometry could be transferred from the STEP file");
    if (options.read_gdt) linkDatumsByItemUsage(*reader.ChangeReader().WS(), doc, path);
  } else {
    IGESCAFControl_Reader reader;
    reader.SetColorMode(true);
    reader.SetNameMode(true);
    reader.SetLayerMode(false);
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
      throw InputError(path, "not a readable IGES file: the IGES parser rejected it");
    Handle(IGESData_IGESModel) model = Handle(IGESData_IGESModel)::DownCast(reader.Model());
    if (!model.IsNull() && !model->GlobalSection().UnitName().IsNull())
      part.file_unit = lowercase(model->GlobalSection().UnitName()->ToCString());
    if (!reader.Transfer(doc))
      throw InputError(path, "no geometry could be transferred from the IGES file");
  }
  part.unit_scale = millimetresPer(part.file_unit);
  return doc;
}

TopoDS_Shape freeShapes(const Handle(TDocStd_Document) & doc) {
  Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
  TDF_LabelSequence roots;
  shapes->GetFreeShapes(roots);
  if (roots.Length() == 1) return XCAFDoc_ShapeTool::GetShape(roots.First());
  TopoDS_Compound compound;
  BRep_Builder builder;
  builder.MakeCompound(compound);
  for (const TDF_Label& root : roots) {
    TopoDS_Shape shape = XCAFDoc_ShapeTool::GetShape(root);
    if (!shape.IsNull()) builder.Add(compound, shape);
  }
  return compound;
}

// The finest chordal tolerance, as a share of the part's diagonal: a fiftieth of the
// default. Finer ones mesh for minutes into gigabytes, or fail inside the CAD kernel.
constexpr double kFinestRelativeDeflection = 1e-5;

// How far the geometry's bounding box may reach from the file's origin before meshing, mm:
// farther, it is corrupt (the part itself must lie within kLongestLength, checked on its
// mesh) and the mesher would run without end.
constexpr double kFarthestGeometry = 1000 * kLongestLength;

// How far the geometry of `shape` reaches from the origin, mm (infinite when unbounded);
// its bounding box in `box`.
double reachOf(const TopoDS_Shape& shape, Bnd_Box& box) {
  BRepBndLib::Add(shape, box, false);
  if (box.IsVoid()) return 0;
  if (box.IsOpen()) return std::numeric_limits<double>::infinity();
  double x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  return std::max(
      {std::abs(x0), std::abs(y0), std::abs(z0), std::abs(x1), std::abs(y1), std::abs(z1)});
}

// The diagonal of the shape's geometry, mm.
// \throw InputError naming `path` and the first face that is unbounded or reaches beyond
//        kFarthestGeometry.
double geometryDiagonal(const TopoDS_Shape& shape, const std::string& path) {
  Bnd_Box box;
  if (reachOf(shape, box) <= kFarthestGeometry)
    return box.IsVoid() ? 1.0 : std::sqrt(box.SquareExtent());
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  for (int id = 1; id <= faces.Extent(); ++id) {
    Bnd_Box face_box;
    const double reach = reachOf(faces(id), face_box);
    if (!(reach <= kFarthestGeometry))
      throw InputError(path, fmt::format("face {} reaches {:.3g} mm from the origin, beyond "
                                         "{:.0f} km: it has no boundary, or a radius, point or "
                                         "pole of it is corrupt",
                                         id, reach, kFarthestGeometry / 1e6));
  }
  throw InputError(path, fmt::format("the geometry reaches beyond {:.0f} km from the origin: an "
                                     "edge or vertex is corrupt",
                                     kFarthestGeometry / 1e6));
}

// The mesh's chordal tolerance: the options' own, or their share of the diagonal.
// \throw InputError naming `path` when it is finer than kFinestRelativeDeflection allows.
double chooseDeflection(double diagonal, const ImportOptions& options, const std::string& path) {
  const double finest = std::max(kFinestRelativeDeflection * diagonal, 1e-4);
  const double chosen = options.linear_deflection > 0
                            ? options.linear_deflection
                            : std::max(options.relative_deflection * diagonal, 1e-4);
  if (chosen < finest)
    throw InputError(path, fmt::format("a chordal deflection of {:.3g} mm is too fine for a part "
                                       "{:.3g} mm across: the finest is {:.3g} mm",
                                       chosen, diagonal, finest));
  return chosen;
}

// The shape a file holds, and for STEP and IGES the XDE document it came in (null for BREP).
struct ReadShape {
  Handle(TDocStd_Document) doc;
  TopoDS_Shape shape;
};

ReadShape readShape(const std::string& path, const std::string& format,
                    const ImportOptions& options, Part& part) {
  ReadShape read;
  if (format == "BREP") {
    BRep_Builder builder;
    if (!BRepTools::Read(read.shape, path.c_str(), builder) || read.shape.IsNull())
      throw InputError(path, "not a readable OCCT BREP file");
    part.file_unit = "mm";  // BREP carries no unit; OCCT's convention is millimetres
    return read;
  }
  read.doc = readExchangeFile(path, format, options, part);
  read.shape = freeShapes(read.doc);
  if (read.shape.IsNull())
    throw InputError(path, "no geometry: the file holds no shape that could be read");
  return read;
}

// What the isolated reader hands back: the file's unit on the first line, then the shape
// in OCCT's binary formats, as an XDE document (STEP, IGES) or a bare shape (BREP).
std::string serialize(const ReadShape& read, const Part& part) {
  std::ostringstream out(std::ios::binary);
  out << part.file_unit << '\n';
  if (read.doc.IsNull())
    BinTools::Write(read.shape, out);
  else if (application()->SaveAs(read.doc, out) != PCDM_SS_OK)
    throw InputError(part.file, "the document read from it could not be handed on");
  return out.str();
}

ReadShape deserialize(const std::string& bytes, const std::string& format, Part& part) {
  std::istringstream in(bytes, std::ios::binary);
  std::getline(in, part.file_unit);
  part.unit_scale = millimetresPer(part.file_unit);
  ReadShape read;
  if (format == "BREP") {
    BinTools::Read(read.shape, in);
    return read;
  }
  if (application()->Open(in, read.doc) != PCDM_RS_OK)
    throw InputError(part.file, "the document read from it could not be taken over");
  read.shape = freeShapes(read.doc);
  return read;
}

// OCCT's readers can crash on a corrupt file, loop on it or allocate out of all proportion:
// they run in a child process bounded by readerLimits(), which hands the shape back.
ReadShape readInIsolation(const std::string& path, const std::string& format,
                          const ImportOptions& options, Part& part) {
  const std::size_t size = static_cast<std::size_t>(std::filesystem::file_size(path));
  const std::string bytes = runIsolated(path, "the " + format + " reader", readerLimits(size), [&] {
    try {
      Part scratch;
      scratch.file = path;
      return serialize(readShape(path, format, options, scratch), scratch);
    } catch (const Standard_OutOfMemory&) {
      throw std::bad_alloc();
    } catch (const Standard_Failure& failure) {
      throw kernelError(path, failure);
    }
  });
  return deserialize(bytes, format, part);
}

}  // namespace

Part importBRep(const std::string& path, const std::string& format, const ImportOptions& options,
                const Progress& progress) {
  Part part;
  part.file = path;
  part.format = format;
  report(progress, "reading and transferring " + format, 0);
  const ReadShape read = readInIsolation(path, format, options, part);
  const double deflection = chooseDeflection(geometryDiagonal(read.shape, path), options, path);
  buildFromShape(part, read.shape, deflection, radians(options.angular_deflection), progress);
  if (read.doc.IsNull()) return part;

  report(progress, "reading names and colours", 0);
  XdeFaceLookup lookup;
  lookup.model = part.brep.get();
  XdeWalker walker(read.doc, part, *part.brep, lookup);
  Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(read.doc->Main());
  TDF_LabelSequence roots;
  shapes->GetFreeShapes(roots);
  for (const TDF_Label& root : roots) walker.walk(root, TopLoc_Location());
  if (format == "STEP" && options.read_gdt) {
    report(progress, "reading GD&T", 0);
    part.gdt = readGdt(read.doc, lookup, path);
  }
  report(progress, "closing the document", 0);
  application()->Close(read.doc);
  return part;
}

}  // namespace scanplan::detail
