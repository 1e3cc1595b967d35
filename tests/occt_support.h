#pragma once
// Test helpers that write OCCT shapes to the files scanplan reads: BREP and STEP.

#include <BRepTools.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <TopoDS_Shape.hxx>

#include <gtest/gtest.h>

#include <string>

namespace scanplan::test {

inline std::string writeBrep(const TopoDS_Shape& shape, const std::string& path) {
  EXPECT_TRUE(BRepTools::Write(shape, path.c_str()));
  return path;
}

// `shape` as a STEP file in `unit` (OCCT's write.step.unit: MM, INCH, ...).
inline std::string writeStep(const TopoDS_Shape& shape, const std::string& path,
                             const char* unit = "MM") {
  STEPControl_Controller::Init();  // declares the static parameters set below
  Interface_Static::SetCVal("write.step.unit", unit);
  STEPControl_Writer writer;
  writer.Transfer(shape, STEPControl_AsIs);
  EXPECT_EQ(writer.Write(path.c_str()), IFSelect_RetDone);
  Interface_Static::SetCVal("write.step.unit", "MM");
  return path;
}

}  // namespace scanplan::test
