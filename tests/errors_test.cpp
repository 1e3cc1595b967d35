// Every kind of bad input gives an InputError that names the file and the problem.

#include "support.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/points_csv.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/io/study_yaml.h>
#include <scanplan/planning.h>
#include <scanplan/scanner/sensor.h>
#include <scanplan/spec/spec.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <set>

namespace scanplan {
namespace {

using test::contains;
using test::importError;
using test::inputError;

std::string truncatedCopy(const std::string& from, const std::string& to, double fraction) {
  std::ifstream in(from, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  test::writeText(
      to, text.substr(0, static_cast<std::size_t>(static_cast<double>(text.size()) * fraction)));
  return to;
}

TEST(ImportErrors, MissingFile) {
  EXPECT_EQ(importError("/nonexistent/part.step"), "no such file");
}

TEST(ImportErrors, EmptyFile) {
  test::TempDir dir;
  test::writeText(dir.file("empty.step"), "");
  EXPECT_EQ(importError(dir.file("empty.step")), "empty file");
}

TEST(ImportErrors, UnsupportedExtension) {
  test::TempDir dir;
  test::writeText(dir.file("part.xyz"), "1 2 3\n");
  EXPECT_NE(importError(dir.file("part.xyz")).find("unsupported file type '.xyz'"),
            std::string::npos);
}

TEST(ImportErrors, TruncatedStep) {
  test::TempDir dir;
  std::string path = truncatedCopy(test::testData("nist_ftc_11_asme1_ap242-e1.stp"),
                                   dir.file("truncated.stp"), 0.5);
  EXPECT_NE(importError(path).find("truncated STEP file"), std::string::npos);
}

TEST(ImportErrors, NotAStepFile) {
  test::TempDir dir;
  test::writeText(dir.file("text.step"), "this is not STEP\n");
  EXPECT_NE(importError(dir.file("text.step")).find("not a STEP file"), std::string::npos);
}

TEST(ImportErrors, CorruptStepBody) {
  test::TempDir dir;
  test::writeText(dir.file("corrupt.step"),
                  "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('x'),'2;1');\n"
                  "FILE_NAME('x','',(''),(''),'','','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\n"
                  "ENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.);\n#2=(((garbage\nENDSEC;\n"
                  "END-ISO-10303-21;\n");
  std::string reason = importError(dir.file("corrupt.step"));
  EXPECT_FALSE(reason.empty());
}

// An entity removed from a STEP file leaves references to it: OCCT's translator would
// follow one into a crash, so the file is refused, naming both entities.
TEST(ImportErrors, StepReferringToAMissingEntity) {
  test::TempDir dir;
  std::ifstream in(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t point = text.find("\n#", text.find("CARTESIAN_POINT") - 40);
  ASSERT_NE(point, std::string::npos);
  const std::size_t end = text.find('\n', point + 1);
  const std::string id = text.substr(point + 1, text.find('=', point) - point - 1);
  text.erase(point, end - point);  // the point's line, with its id
  test::writeText(dir.file("cut.stp"), text);
  const std::string reason = importError(dir.file("cut.stp"));
  EXPECT_NE(reason.find("refers to " + id.substr(0, id.find_last_not_of(' ') + 1) +
                        ", which the file does not define"),
            std::string::npos)
      << reason;
}

// The bundled FTC 11 test part with `from` replaced by `to`, written to `dir`; the reason
// importPart gives for it.
std::string editedStepError(const test::TempDir& dir, const std::string& from,
                            const std::string& to) {
  std::ifstream in(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t at = text.find(from);
  if (at == std::string::npos) return "'" + from + "' is not in the file";
  text.replace(at, from.size(), to);
  test::writeText(dir.file("edited.stp"), text);
  return importError(dir.file("edited.stp"));
}

// An entity of the shape with a parameter removed is half-made by the STEP parser, and
// OCCT's translator would follow it into a crash; a face whose bound is removed is an
// untrimmed surface of endless area. Both are refused, naming the entity or the face.
TEST(ImportErrors, StepWithAnEntityOrABoundRemoved) {
  test::TempDir dir;
  EXPECT_PRED2(contains,
               editedStepError(dir, "#632=EDGE_CURVE('',#624,#624,#610,.T.);",
                               "#632=EDGE_CURVE('',#624,#610,.T.);"),
               "entity #632 (StepShape_EdgeCurve) cannot be read: Count of Parameters is not 5");
  EXPECT_PRED2(contains,
               editedStepError(dir, "#679=ADVANCED_FACE('',(#593,#579),#581,.T.);",
                               "#679=ADVANCED_FACE('',(),#581,.T.);"),
               "it has no boundary");
}

TEST(ImportErrors, StepWithoutGeometry) {
  test::TempDir dir;
  test::writeText(dir.file("nogeometry.step"),
                  "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('x'),'2;1');\n"
                  "FILE_NAME('x','',(''),(''),'','','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\n"
                  "ENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.));\nENDSEC;\n"
                  "END-ISO-10303-21;\n");
  std::string reason = importError(dir.file("nogeometry.step"));
  EXPECT_NE(reason.find("geometry"), std::string::npos) << reason;
}

TEST(ImportErrors, TruncatedIges) {
  SHARED_DATA_OR_SKIP(source, "mech/occt_bearing.iges");
  test::TempDir dir;
  std::string path = truncatedCopy(source, dir.file("truncated.iges"), 0.5);
  EXPECT_NE(importError(path).find("truncated IGES file"), std::string::npos);
}

// OCCT's BREP reader prints its complaint on std::cout, which is the program's output
// (`info --json`): the reader's output goes nowhere.
TEST(ImportErrors, CorruptBrepIsRefusedWithoutAWordOnStdout) {
  test::TempDir dir;
  test::writeText(dir.file("corrupt.brep"), "DBRep_DrawableShape\nnot really\n");
  testing::internal::CaptureStdout();
  const std::string reason = importError(dir.file("corrupt.brep"));
  EXPECT_EQ(testing::internal::GetCapturedStdout(), "");
  EXPECT_NE(reason.find("BREP"), std::string::npos);
}

TEST(ImportErrors, StlWithoutTriangles) {
  test::TempDir dir;
  test::writeText(dir.file("empty.stl"), "solid empty\nendsolid empty\n");
  EXPECT_NE(importError(dir.file("empty.stl")).find("no triangles"), std::string::npos);
}

TEST(ImportErrors, OffWithoutTriangles) {
  test::TempDir dir;
  test::writeText(dir.file("points.off"), "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  EXPECT_NE(importError(dir.file("points.off")).find("no triangles"), std::string::npos);
}

TEST(ImportErrors, TruncatedOff) {
  test::TempDir dir;
  test::writeText(dir.file("cut.off"), "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n");
  EXPECT_NE(importError(dir.file("cut.off")).find("truncated OFF file"), std::string::npos);
}

TEST(ImportErrors, OffVertexThatIsNotANumber) {
  test::TempDir dir;
  test::writeText(dir.file("nan.off"), "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(importError(dir.file("nan.off")), "OFF file: vertex 2 of 3 is not three numbers");
}

// An ASCII STL is read strictly: a facet out of shape is an error naming its line, never
// a mesh with the facet left out.
TEST(ImportErrors, MalformedAsciiStl) {
  test::TempDir dir;
  const std::string facet =
      " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
      "  endloop\n endfacet\n";
  test::writeText(dir.file("good.stl"), "solid t\n" + facet + facet + "endsolid t\n");
  EXPECT_EQ(importPart(dir.file("good.stl")).mesh.triangles.size(), 2u);
  std::string bad = facet;
  bad.replace(bad.find("vertex 1 0 0"), 12, "vertex 1 x 0");
  test::writeText(dir.file("bad.stl"), "solid t\n" + facet + bad + "endsolid t\n");
  EXPECT_EQ(importError(dir.file("bad.stl")), "line 12: three numbers expected");
  test::writeText(dir.file("text.stl"), "solid x\n this is not stl\nendsolid\n");
  EXPECT_NE(importError(dir.file("text.stl")).find("line 2: 'facet normal' expected"),
            std::string::npos);
  test::writeText(dir.file("cut.stl"), "solid t\n" + facet.substr(0, facet.find("vertex 1")));
  EXPECT_NE(importError(dir.file("cut.stl")).find("truncated STL file"), std::string::npos);
}

TEST(ImportErrors, PartOfAbsurdSize) {
  test::TempDir dir;
  test::writeText(dir.file("huge.off"),
                  "OFF\n4 4 0\n0 0 0\n1e30 0 0\n0 1e30 0\n0 0 1e30\n"
                  "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  EXPECT_NE(importError(dir.file("huge.off")).find("more than 100 m"), std::string::npos);
}

TEST(ImportErrors, TruncatedBinaryPly) {
  test::TempDir dir;
  test::writeText(dir.file("cut.ply"),
                  "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                  "property float y\nproperty float z\nelement face 1\n"
                  "property list uchar int vertex_indices\nend_header\n\x01\x02");
  EXPECT_NE(importError(dir.file("cut.ply")).find("truncated PLY file"), std::string::npos);
}

// Found by the mesh fuzzer: an index far beyond an int was converted regardless.
TEST(ImportErrors, PlyIndexThatIsNoIndex) {
  test::TempDir dir;
  test::writeText(dir.file("big.ply"),
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                  "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1e30\n");
  EXPECT_PRED2(contains, importError(dir.file("big.ply")), "not an index");
}

// An ASCII PLY item is one line: a vertex short of a value is named by its line and item,
// not read on into the next line.
TEST(ImportErrors, AsciiPlyItemOfTheWrongLengthIsNamedByItsLine) {
  test::TempDir dir;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  test::writeText(dir.file("short.ply"), header + "0 0 0\n1 0 0\n0 1\n3 0 1 2\n");
  EXPECT_EQ(importError(dir.file("short.ply")),
            "line 12, element 'vertex' item 3: fewer values than the element's properties, or one "
            "not a number");
  test::writeText(dir.file("long.ply"), header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2 7\n");
  EXPECT_EQ(importError(dir.file("long.ply")),
            "line 13, element 'face' item 1: more values than the element's properties");
  test::writeText(dir.file("good.ply"), header + "0 0 0\r\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(importPart(dir.file("good.ply")).mesh.triangles.size(), 1u);
}

TEST(ImportErrors, PlyHeaderClaimingMoreThanTheFileHolds) {
  test::TempDir dir;
  test::writeText(dir.file("huge.ply"),
                  "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
                  "property float x\nproperty float y\nproperty float z\nend_header\n");
  EXPECT_NE(importError(dir.file("huge.ply")).find("truncated PLY file"), std::string::npos);
}

// The index is named as the file writes it: OBJ counts from 1, OFF and PLY from 0, and an
// index of INT_MAX is no negative number.
TEST(ImportErrors, FaceIndexOutOfRangeIsNamedAsTheFileWritesIt) {
  test::TempDir dir;
  test::writeText(dir.file("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  EXPECT_EQ(importError(dir.file("bad.obj")),
            "a face refers to vertex 9 but the file has 3 vertices, numbered 1 to 3");
  for (const char* index : {"3", "2147483647"}) {
    test::writeText(dir.file("bad.off"),
                    std::string("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 ") + index + "\n");
    EXPECT_EQ(importError(dir.file("bad.off")),
              std::string("a face refers to vertex ") + index +
                  " but the file has 3 vertices, numbered 0 to 2");
  }
}

// A face of two vertices is no face; a polygon collapsed onto a line gives triangles of no
// area, which are warned of.
TEST(ImportErrors, FaceOfTwoVerticesIsRefusedAndEmptyTrianglesWarnedOf) {
  test::TempDir dir;
  test::writeText(dir.file("two.off"), "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n2 0 3\n");
  EXPECT_EQ(importError(dir.file("two.off")), "a face of 2 vertices: a face needs at least 3");
  test::writeText(dir.file("line.off"),
                  "OFF\n6 2 0\n0 0 0\n10 0 0\n0 10 0\n1 1 1\n2 2 2\n3 3 3\n"
                  "3 0 1 2\n3 3 4 5\n");
  const Part part = importPart(dir.file("line.off"));
  ASSERT_FALSE(part.warnings.empty());
  EXPECT_EQ(part.warnings.back(),
            "1 of the mesh's 2 triangles have no area (corners coincident or in a line)");
}

// A chordal tolerance far finer than the part needs would mesh for minutes into gigabytes,
// or fail inside the CAD kernel.
TEST(ImportErrors, DeflectionTooFineForThePart) {
  ImportOptions options;
  options.linear_deflection = 1e-9;
  std::string path = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  const std::string reason = importError(path, options);
  EXPECT_NE(reason.find("too fine for a part 96.5 mm across"), std::string::npos) << reason;
}

TEST(ImportErrors, NonsenseOptions) {
  ImportOptions options;
  options.angular_deflection = -5;
  std::string path = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  EXPECT_NE(importError(path, options).find("invalid import options"), std::string::npos);
  // An infinite chordal tolerance (--deflection inf) or mesh unit is no tolerance at all.
  for (const auto change : {+[](ImportOptions& o) { o.linear_deflection = INFINITY; },
                            +[](ImportOptions& o) { o.mesh_unit = INFINITY; }}) {
    ImportOptions infinite;
    change(infinite);
    EXPECT_NE(importError(path, infinite).find("invalid import options"), std::string::npos);
  }
}

// The bundled example's plan, changed by `change`, written to `path`; the reason readPlan
// gives for it, or a failure when it reads it.
std::string planError(const std::string& path, const std::function<void(nlohmann::json&)>& change) {
  std::ifstream in(test::examplePlan());
  nlohmann::json plan = nlohmann::json::parse(in);
  change(plan);
  test::writeText(path, plan.dump());
  return inputError(path, [&] { readPlan(path); });
}

// Each face's measured area: read back as written, and refused when an entry names another
// face, or measures more than the face has.
TEST(PlanErrors, FaceAreasReadBackAndNoFaceMeasuresMoreThanItHas) {
  const Plan plan = readPlan(test::examplePlan());
  ASSERT_EQ(plan.face_areas.size(), plan.part_faces);
  double area = 0, measured = 0;
  for (const FaceArea& f : plan.face_areas) {
    area += f.area;
    measured += f.measured;
  }
  EXPECT_GT(measured, 0);
  EXPECT_LT(measured, area);  // the bottom stands on the plate
  test::TempDir dir;
  const std::string path = dir.file("plan.json");
  EXPECT_EQ(planError(path, [](auto& p) { p["face_areas"][3]["measured"] = 1e12; }),
            "face_areas entry 4: expected face 4 with a finite area and at most that measured");
  EXPECT_EQ(planError(path, [](auto& p) { p["face_areas"][0]["face"] = 2; }),
            "face_areas entry 1: expected face 1 with a finite area and at most that measured");
  EXPECT_EQ(planError(path, [](auto& p) { p["face_areas"].erase(0); }),
            "face_areas: expected one entry per face of the part");
}

// A plan over several rest orientations takes each view in one setup: a view two
// orientations list, or none does, is refused naming it.
TEST(PlanErrors, EachViewIsInOneOrientation) {
  test::TempDir dir;
  const std::string path = dir.file("plan.json");
  // The example's views split into two setups standing alike: the first view alone, then
  // the others.
  auto twoSetups = [](nlohmann::json& p) {
    nlohmann::json first = nlohmann::json::array(), rest = nlohmann::json::array();
    for (const nlohmann::json& view : p["views"])
      (first.empty() ? first : rest).push_back(view["id"]);
    for (const nlohmann::json& ids : {first, rest})
      p["orientations"].push_back(
          {{"part_to_world", p["part"]["part_to_world"]}, {"down", {0, 0, -1}}, {"views", ids}});
  };
  nlohmann::json plan = nlohmann::json::parse(test::readText(test::examplePlan()));
  twoSetups(plan);
  test::writeText(path, plan.dump());
  EXPECT_EQ(readPlan(path).orientations.size(), 2u);
  EXPECT_PRED2(contains,
               planError(path,
                         [&](auto& p) {
                           twoSetups(p);
                           p["orientations"][1]["views"].push_back(p["views"][0]["id"]);
                         }),
               "orientation 2 lists view 1, which orientation 1 lists too");
  EXPECT_PRED2(contains,
               planError(path,
                         [&](auto& p) {
                           twoSetups(p);
                           p["orientations"][1]["views"].erase(0);
                         }),
               "view 2 is in no orientation");
}

TEST(PlanErrors, ReferencesToViewsAndFacesThePlanDoesNotHave) {
  test::TempDir dir;
  const std::string path = dir.file("plan.json");
  EXPECT_PRED2(contains, planError(path, [](auto& p) { p["views"][0]["id"] = -5; }),
               "ids must be positive");
  EXPECT_PRED2(contains,
               planError(path, [](auto& p) { p["views"][1]["registration"]["to"] = 77777; }),
               "view 2 registration refers to view 77777");
  EXPECT_PRED2(contains, planError(path, [](auto& p) { p["samples"][0]["face"] = 99999; }),
               "sample 1: face 99999 is not a face of the part");
  EXPECT_PRED2(contains, planError(path, [](auto& p) { p["sequence"][0] = 4242; }),
               "the sequence refers to view 4242");
  EXPECT_PRED2(contains,
               planError(path,
                         [](auto& p) {
                           p["samples"][3]["measured_by"] = {1, 999};
                         }),
               "sample 4 measured_by refers to view 999");
  EXPECT_PRED2(contains,
               planError(path, [](auto& p) { p["views"][0]["registration"]["to"] = "x"; }),
               "view 1 registration: 'to' has the wrong type");
  EXPECT_PRED2(contains, planError(path, [](auto& p) { p["summary"]["path_length"] = "x"; }),
               "a value has the wrong type");
  // A number where a whole one belongs (converting 1e38 to an int is undefined).
  EXPECT_PRED2(contains, planError(path, [](auto& p) { p["samples"][0]["face"] = 1.1e38; }),
               "sample 1: 'face' has the wrong type");
  EXPECT_PRED2(contains,
               planError(path, [](auto& p) { p["views"][0]["registration"]["to"] = 2.5; }),
               "view 1 registration: 'to' has the wrong type");
}

// A plan in inches, of another version, with a key or a task this version does not know,
// or a key given twice, is refused as the spec's unknown keys are, not read in part.
TEST(PlanErrors, WhatThisVersionDoesNotUnderstandIsRefused) {
  test::TempDir dir;
  const std::string path = dir.file("plan.json");
  EXPECT_EQ(planError(path, [](auto& p) { p["units"] = "inch"; }), "units 'inch': plans are in mm");
  EXPECT_EQ(planError(path, [](auto& p) { p["version"] = 5; }),
            "version 5 is not one this scanplan reads (it reads versions 1 to 4)");
  EXPECT_EQ(planError(path, [](auto& p) { p["version"] = 0; }),
            "version 0 is not one this scanplan reads (it reads versions 1 to 4)");
  EXPECT_EQ(planError(path, [](auto& p) { p["views"][2]["task"] = "gdtt"; }),
            "view 3: unknown task 'gdtt'");
  EXPECT_EQ(planError(path, [](auto& p) { p["view"] = p["views"]; }), "plan: unknown key 'view'");
  EXPECT_EQ(planError(path, [](auto& p) { p["views"][0]["camera"] = 1; }),
            "view 1: unknown key 'camera'");
  EXPECT_EQ(planError(path, [](auto& p) { p["samples"][1]["weight"] = 2; }),
            "sample 2: unknown key 'weight'");
  EXPECT_EQ(planError(path, [](auto& p) { p["part"]["unit"] = "mm"; }), "part: unknown key 'unit'");
  EXPECT_EQ(planError(path, [](auto& p) { p["spec"]["txt"] = ""; }), "spec: unknown key 'txt'");
  EXPECT_EQ(planError(path, [](auto& p) { p["spec"]["text"] = 1; }),
            "spec: 'text' has the wrong type");
  EXPECT_EQ(planError(path, [](auto& p) { p["registration"]["tolerence"] = 0.1; }),
            "registration: unknown key 'tolerence'");
  EXPECT_EQ(planError(path, [](auto& p) { p["characteristics"][1]["toleranse"] = 0.1; }),
            "characteristic 2: unknown key 'toleranse'");
  EXPECT_EQ(planError(path, [](auto& p) { p["summary"]["path_lenght"] = 1.0; }),
            "summary: unknown key 'path_lenght'");
  // nlohmann would keep the second "units" silently.
  std::ifstream in(test::examplePlan());
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find('{'), 1, "{\"units\": \"inch\", ");
  test::writeText(path, text);
  EXPECT_EQ(inputError(path, [&] { readPlan(path); }),
            "the key 'units' is given twice in one object");
  // The plan as written reads with the spec it was made with, and so does a version 3 plan
  // without one, and a version 1 plan without a cycle time.
  EXPECT_EQ(readPlan(test::examplePlan()).spec.value_or(PlanSpec{}).text,
            test::readText(test::example("specs/ctc01.yaml")));
  nlohmann::json three = nlohmann::json::parse(test::readText(test::examplePlan()));
  three["version"] = 3;
  three.erase("spec");
  test::writeText(path, three.dump());
  EXPECT_FALSE(readPlan(path).spec.has_value());
  nlohmann::json old = nlohmann::json::parse(test::readText(test::examplePlan()));
  old["version"] = 1;
  old["summary"].erase("cycle");
  test::writeText(path, old.dump());
  EXPECT_FALSE(readPlan(path).cycle.has_value());
  // Versions 1 and 2 named a budget too large for the tolerance too_noisy; version 3 does not.
  nlohmann::json two = nlohmann::json::parse(test::readText(test::examplePlan()));
  two["version"] = 2;
  std::size_t renamed = 0;
  for (auto& c : two["characteristics"])
    if (c["capability"]["reason"] == "too_uncertain") {
      c["capability"]["reason"] = "too_noisy";
      ++renamed;
    }
  ASSERT_GT(renamed, 0u) << "the example plan has no characteristic too uncertain";
  test::writeText(path, two.dump());
  const Plan read_two = readPlan(path);
  EXPECT_EQ(std::count_if(read_two.capabilities.begin(), read_two.capabilities.end(),
                          [](const Capability& c) { return c.reason == Shortfall::TooUncertain; }),
            static_cast<long>(renamed));
  two["version"] = 3;
  test::writeText(path, two.dump());
  EXPECT_PRED2(contains, inputError(path, [&] { readPlan(path); }), "unknown value 'too_noisy'");
  EXPECT_PRED2(contains, planError(path, [](auto& p) { p["summary"]["cycle"]["model"] = "x"; }),
               "summary cycle: unknown model 'x'");
  EXPECT_PRED2(contains, planError(path, [](auto& p) { p["summary"]["cycle"]["motion"] = -1; }),
               "summary cycle: 'motion' is not a number of seconds");
}

// Loads the spec `text` (written to spec.yaml in `dir`) and returns the error's reason.
std::string specError(const test::TempDir& dir, const std::string& text) {
  const std::string path = dir.file("spec.yaml");
  test::writeText(path, text);
  return inputError(path, [&] { loadSpec(path); });
}

// What a file holds is quoted in a message only so far: a line of 200,000 bytes, or a key
// of 1,000, is cut at kQuotedBytes and its control bytes are '?'.
TEST(ErrorMessages, LongOrControlTextIsQuotedBriefly) {
  test::TempDir dir;
  test::writeText(dir.file("long.stl"), "solid t\n" + std::string(200000, 'A') + "\x1b[2J\n");
  const std::string stl = importError(dir.file("long.stl"));
  EXPECT_PRED2(
      contains, stl,
      "line 2: 'facet normal' expected, found '" + std::string(kQuotedBytes - 3, 'A') + "...'");
  EXPECT_LT(stl.size(), 200u);
  EXPECT_EQ(stl.find('\x1b'), std::string::npos);
  test::writeText(dir.file("escape.stl"), "solid t\nfacet \x1b[2Jnormal\n");
  EXPECT_PRED2(contains, importError(dir.file("escape.stl")), "found 'facet ?[2Jnormal'");
  const std::string spec = specError(dir, "planner:\n  " + std::string(1000, 'k') + ": 1\n");
  EXPECT_PRED2(contains, spec,
               "unknown key '" + std::string(kQuotedBytes - 3, 'k') + "...' in planner");
  EXPECT_LT(spec.size(), 200u);
  // A cut never splits a character: 'é' is two bytes, and 77 bytes end inside one.
  std::string accents;
  for (int k = 0; k < 60; ++k) accents += "\xc3\xa9";
  EXPECT_PRED2(contains, briefReason("found '" + accents + "'"),
               "found '" + accents.substr(0, 76) + "...'");
  EXPECT_EQ(briefReason("short 'ok' and 'fine'"), "short 'ok' and 'fine'");
  // An apostrophe in a word opens and closes nothing, however far the next quote lies.
  const std::string prose =
      "the robot's arm, whose controller takes its maker's format only, "
      "and this part's name: '";
  EXPECT_EQ(briefReason(prose + std::string(100, 'x') + "'"),
            prose + std::string(kQuotedBytes - 3, 'x') + "...'");
}

TEST(SpecErrors, DuplicateKeysUnusedFacesAndUnknownPresetsNameTheSpec) {
  test::TempDir dir;
  EXPECT_PRED2(contains, specError(dir, "tasks:\n  - {type: global}\ntasks:\n  - {type: gdt}\n"),
               "key 'tasks' given twice in the spec");
  EXPECT_PRED2(contains, specError(dir, "planner:\n  seed: 1\n  seed: 2\n"),
               "key 'seed' given twice in planner");
  EXPECT_PRED2(contains, specError(dir, "tasks:\n  - {type: global, faces: [1, 2]}\n"),
               "tasks[1]: a global task takes no faces");
  EXPECT_PRED2(contains, specError(dir, "scanner: hyperscan-9000\n"),
               "scanner 'hyperscan-9000': unknown scanner preset");
  // Found by the spec fuzzer: a name too long for a file name threw from the file system.
  EXPECT_PRED2(contains, specError(dir, "scanner: " + std::string(300, 'x') + "\n"),
               "unknown scanner preset");
  // Numbers must be finite, wherever they are.
  EXPECT_PRED2(contains,
               specError(dir, "cell:\n  robot:\n    preset: abb-irb4600-60-205\n    a1: .nan\n"),
               "cell.robot.a1: '.nan' is not a finite number");
  EXPECT_PRED2(contains, specError(dir, "registration: {tolerance: .inf}\n"),
               "registration.tolerance: '.inf' is not a finite number");
  // Settings that would exhaust memory are refused before anything is allocated.
  EXPECT_PRED2(contains, specError(dir, "planner: {vm_step: 0.0001}\n"),
               "planner.vm_step must be within [1, 45] degrees");
  EXPECT_PRED2(contains,
               specError(dir,
                         "cell:\n  robot: {preset: abb-irb4600-60-205}\n"
                         "  table: {step: 1.0e-9}\n"),
               "cell.table.step must be at least 0.1 degrees");
  // Coverage targets are shares of the coverable samples.
  EXPECT_PRED2(contains, specError(dir, "planner: {coverage: 1.5}\n"),
               "planner.coverage must be a share within (0, 1]");
  EXPECT_PRED2(contains, specError(dir, "planner: {coverage: {global: 0}}\n"),
               "planner.coverage.global must be a share within (0, 1]");
  EXPECT_PRED2(contains, specError(dir, "planner: {coverage: {globl: 0.9}}\n"),
               "unknown key 'globl' in planner.coverage");
  EXPECT_PRED2(contains, specError(dir, "planner: {objective: seconds}\n"),
               "planner.objective must be views or cycle_time, not 'seconds'");
  EXPECT_PRED2(contains, specError(dir, "planner: {aim: tolerances}\n"),
               "planner.aim must be samples or characteristics, not 'tolerances'");
}

// What YAML or a CSV would let through silently: a second document, a key given twice in a
// scanner file, a first line of data mistyped (taken for a header), a markers file that
// is missing while registration is off and nothing reads it.
TEST(SpecErrors, WhatWouldPassSilentlyIsRefused) {
  test::TempDir dir;
  EXPECT_EQ(specError(dir, "scanner: laser-line\n---\nscanner: generic-structured-light\n"),
            "holds more than one YAML document (split by ---): a spec is one");
  // yaml-cpp's reading of every document loops without end on these three bytes.
  EXPECT_PRED2(contains, specError(dir, std::string("\0,\xc1", 3)),
               "byte 1 is a control character (0x00): a spec is YAML, which is text");
  test::writeText(dir.file("scanner.yaml"), "standoff: 300\nstandoff: 400\n");
  EXPECT_EQ(inputError(dir.file("scanner.yaml"), [&] { scannerNamed(dir.file("scanner.yaml")); }),
            "key 'standoff' given twice");
  test::writeText(dir.file("scanner.yaml"), "standoff: 300\n---\nstandoff: 400\n");
  EXPECT_EQ(inputError(dir.file("scanner.yaml"), [&] { scannerNamed(dir.file("scanner.yaml")); }),
            "holds more than one YAML document (split by ---): a scanner file is one");
  test::writeText(dir.file("points.csv"), "1;2;3\n4,5,6\n");
  EXPECT_EQ(inputError(dir.file("points.csv"), [&] { readPointsCsv(dir.file("points.csv")); }),
            "line 1: not a number in '1;2;3'");
  test::writeText(dir.file("points.csv"), "x,y,z\n4,5,6\n");
  EXPECT_EQ(readPointsCsv(dir.file("points.csv")).size(), 1u);       // a header names columns
  test::writeText(dir.file("points.csv"), "x,y,z\r4,5,6\r7,8,9\r");  // CR line ends
  EXPECT_EQ(readPointsCsv(dir.file("points.csv")).size(), 2u);
  EXPECT_PRED2(contains, specError(dir, "roles:\n  priority: [{name: \"\"}]\n"),
               "roles.priority: a face name must not be empty");
  EXPECT_PRED2(contains,
               specError(dir,
                         "cell:\n  robot: {preset: ur10e, speeds: [1e-300, 180, 180, 180, "
                         "180, 180]}\n"),
               "cell.robot.speeds: joint 1 needs a speed within [1, 3600] °/s");
  test::writeText(dir.file("spec.yaml"), "markers: missing.csv\n");
  EXPECT_EQ(inputError(dir.file("missing.csv"), [&] { loadSpec(dir.file("spec.yaml")); }),
            "no such file");
}

// planner.most_views bounds the plan, not only the estimate from the part's size.
TEST(SpecErrors, PlanOfMoreViewsThanMostViewsIsRefused) {
  const Part part = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  Spec spec = defaultSpec();
  spec.source = "spec.yaml";
  spec.planner.most_views = 2;
  PlanningOptions options;
  options.registration = false;
  try {
    planViews(part, spec, options);
    ADD_FAILURE() << "a plan of more than 2 views was accepted";
  } catch (const PlanningError& e) {
    EXPECT_PRED2(contains, std::string(e.what()),
                 "spec.yaml: the plan needs 4 views, more than planner.most_views (2)");
  }
  spec.planner.most_views = 4;
  EXPECT_EQ(planViews(part, spec, options).views.size(), 4u);
}

// A marker grid finer than the part can hold is refused by size, naming the spec.
TEST(SpecErrors, MarkerGridOfAMillionMarkers) {
  test::TempDir dir;
  TriangleMesh mesh;
  test::addCube(mesh, Vec3::Zero(), 100, 1);
  test::writeText(dir.file("spec.yaml"), "markers: {grid: 0.001}\n");
  const std::string reason = inputError(dir.file("spec.yaml"), [&] {
    planViews(test::meshPart(mesh), loadSpec(dir.file("spec.yaml")));
  });
  EXPECT_PRED2(contains, reason, "more than a million markers");
}

// Settings absurd for the part's size are refused naming the key and a sensible value:
// a 0.5 mm field of view on a 100 mm cube (60,000 mm²) would take 240,000 views to
// cover once; surface points every 0.01 mm would be 600 million.
TEST(SpecErrors, SettingsAbsurdForThePartsSize) {
  test::TempDir dir;
  TriangleMesh mesh;
  test::addCube(mesh, Vec3::Zero(), 100, 1);
  const Part part = test::meshPart(mesh);
  auto reason = [&](const std::string& text) {
    test::writeText(dir.file("spec.yaml"), text);
    return inputError(dir.file("spec.yaml"),
                      [&] { resolveSpec(part, loadSpec(dir.file("spec.yaml"))); });
  };
  EXPECT_PRED2(contains, reason("scanner: {preset: laser-line, fov_width: 0.5, fov_height: 0.5}\n"),
               "takes 240000 views, more than planner.most_views (10000); a field of at least "
               "2.45 x 2.45 mm");
  EXPECT_PRED2(contains,
               reason("scanner: {preset: laser-line, fov_width: 0.5, fov_height: 0.5}\n"
                      "planner: {most_views: 100000}\n"),
               "a field of at least 0.775 x 0.775 mm");
  EXPECT_PRED2(contains, reason("registration: {point_spacing: 0.01}\n"),
               "registration.point_spacing: surface points every 0.01 mm are more than 30 million");
  EXPECT_PRED2(contains, reason("registration: {cloud_spacing: 0.01}\n"),
               "registration.cloud_spacing: a cloud point every 0.01 mm is more than a million "
               "points per view; at least 0.26 mm");
  // The same field of view is sensible on a part its size allows.
  test::writeText(dir.file("spec.yaml"),
                  "scanner: {preset: laser-line, fov_width: 3, fov_height: 3}\n");
  EXPECT_NO_THROW(resolveSpec(part, loadSpec(dir.file("spec.yaml"))));
}

TEST(InputFiles, ADirectoryIsNotAFile) {
  test::TempDir dir;
  std::filesystem::create_directory(dir.file("folder"));
  const std::string folder = dir.file("folder");
  for (const std::function<void()>& read : std::initializer_list<std::function<void()>>{
           [&] { loadSpec(folder); }, [&] { readPlan(folder); }, [&] { importPart(folder); }})
    EXPECT_EQ(inputError(folder, read), "not a regular file (a directory)");
}

// The names in `dir`, sorted.
std::vector<std::string> entries(const test::TempDir& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir.file("")))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Outputs go to regular files only, through a link to its target, and leave no
// temporary behind when writing fails.
TEST(OutputFiles, OnlyRegularFilesAreWrittenAndLinksAreKept) {
  test::TempDir dir;
  auto write = [](const std::string& path) {
    writeFileAtomically(path, [](std::ostream& out) { out << "x\n"; });
  };
  std::filesystem::create_directory(dir.file("folder"));
  EXPECT_THROW(write(dir.file("folder")), OutputError);
  EXPECT_THROW(write("/dev/null"), OutputError);
  std::filesystem::create_symlink("target.txt", dir.file("link.txt"));
  write(dir.file("link.txt"));
  EXPECT_TRUE(std::filesystem::is_symlink(dir.file("link.txt")));
  EXPECT_TRUE(std::filesystem::is_regular_file(dir.file("target.txt")));
  EXPECT_THROW(writeFileAtomically(dir.file("failed.txt"),
                                   [](std::ostream&) { throw OutputError("x", "stop"); }),
               OutputError);
  EXPECT_FALSE(std::filesystem::exists(dir.file("failed.txt")));
  // An interrupt's handler removes the temporary of a write under way.
  EXPECT_THROW(writeFileAtomically(dir.file("cut.txt"),
                                   [&](std::ostream& out) {
                                     out << "x\n";
                                     EXPECT_EQ(entries(dir).size(), 4u);  // with the temporary
                                     removeTemporaries();
                                   }),
               OutputError);
  EXPECT_FALSE(std::filesystem::exists(dir.file("cut.txt")));
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"folder", "link.txt", "target.txt"}));
}

// A temporary is never written through a link planted where it would be (at the fixed
// name of earlier versions, or at this process's next names), and the file replaced
// keeps its permissions.
TEST(OutputFiles, TemporariesAreCreatedAfreshAndPermissionsKept) {
  test::TempDir dir;
  const std::string pid = std::to_string(::getpid());
  test::writeText(dir.file("outside.txt"), "not an output");
  for (int n = 0; n < 50; ++n)  // a link at the names this process picks first
    for (const char* kind : {"tmp", "staged"})
      std::filesystem::create_symlink(
          dir.file("outside.txt"),
          dir.file("plan." + std::string(kind) + "-" + pid + "-" + std::to_string(n) + ".json"));
  std::filesystem::create_symlink(dir.file("outside.txt"), dir.file("plan.staged.json"));
  test::writeText(dir.file("plan.json"), "old");
  std::filesystem::permissions(dir.file("plan.json"), std::filesystem::perms::owner_read |
                                                          std::filesystem::perms::owner_write);
  FileSet outputs;
  writeFileAtomically(outputs.stage(dir.file("plan.json")),
                      [](std::ostream& out) { out << "new"; });
  outputs.commit();
  EXPECT_EQ(test::readText(dir.file("outside.txt")), "not an output");
  EXPECT_EQ(test::readText(dir.file("plan.json")), "new");
  EXPECT_EQ(
      std::filesystem::status(dir.file("plan.json")).permissions() & std::filesystem::perms::all,
      std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
}

// A run's files are written as a set: none is in place before all are written, a failed
// or interrupted set leaves none (and no temporary), and a file of the set the run does
// not write is removed, so that no earlier run's file sits beside the new ones.
TEST(OutputFiles, ARunsFilesAreWrittenAsASet) {
  test::TempDir dir;
  auto write = [](const std::string& path, const std::string& text) {
    writeFileAtomically(path, [&](std::ostream& out) { out << text; });
  };
  auto files = [&] {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir.file("")))
      names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  };
  write(dir.file("report.html"), "an earlier run's report");
  {
    FileSet outputs;
    write(outputs.stage(dir.file("plan.json")), "{}");
    outputs.drop(dir.file("report.html"));
    EXPECT_FALSE(std::filesystem::exists(dir.file("plan.json")));
    outputs.commit();
  }
  EXPECT_EQ(files(), std::vector<std::string>{"plan.json"});
  {
    FileSet outputs;  // fails after its first file: nothing changes
    write(outputs.stage(dir.file("plan.json")), "a new plan");
    EXPECT_THROW(write(outputs.stage(dir.file("folder/report.html")), "x"), OutputError);
  }
  EXPECT_EQ(files(), std::vector<std::string>{"plan.json"});
  std::ifstream plan(dir.file("plan.json"));
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(plan), {}), "{}");
  {
    FileSet outputs;  // interrupted: the handler removes the staged files
    write(outputs.stage(dir.file("views.csv")), "x");
    removeTemporaries();
    EXPECT_EQ(files(), std::vector<std::string>{"plan.json"});
  }
}

}  // namespace
}  // namespace scanplan

namespace scanplan {
namespace {

// A study file's rows, and each mistake named by the file and its key.
TEST(StudyErrors, RowsAreEveryCombinationAndMistakesAreNamed) {
  test::TempDir dir;
  const std::string path = dir.file("study.yaml");
  test::writeText(path,
                  "parts: [a.stp, sub/b.stl]\nscanners: [laser-line, heads/h.yaml]\n"
                  "orientations: [auto, 3]\ncoverage: [1, 0.95]\nregistration: false\n");
  const Study study = loadStudy(path);
  ASSERT_EQ(study.rows.size(), 16u);
  EXPECT_FALSE(study.registration);
  EXPECT_EQ(study.rows[0].part, dir.file("a.stp"));
  EXPECT_EQ(study.rows[0].scanner, "laser-line");
  EXPECT_EQ(study.rows[4].scanner, dir.file("heads/h.yaml"));
  EXPECT_EQ(study.rows[15].part, dir.file("sub/b.stl"));
  EXPECT_EQ(study.rows[15].rest, "3");
  EXPECT_EQ(study.rows[15].coverage, 0.95);
  EXPECT_EQ(study.rows[15].name, "b__h__3__0.95");
  std::set<std::string> names;
  for (const StudyRow& row : study.rows) EXPECT_TRUE(names.insert(row.name).second) << row.name;

  auto error = [&](const std::string& text) {
    test::writeText(path, text);
    return test::inputError(path, [&] { loadStudy(path); });
  };
  EXPECT_EQ(error("scanners: [laser-line]\n"), "parts: the study names no part");
  EXPECT_EQ(error("parts: [a.stp]\nscanner: [x]\n"), "unknown key 'scanner'");
  EXPECT_EQ(error("parts: [a.stp]\norientations: [sideways]\n"),
            "orientations: 'sideways' is not auto, all, drawn or a face id");
  EXPECT_EQ(error("parts: [a.stp]\ncoverage: [1.5]\n"), "coverage: 1.5 is not within (0, 1]");
  EXPECT_EQ(error("parts: []\n"), "parts: the list is empty");
  EXPECT_EQ(error("parts: [a.stp]\nregistration: maybe\n"), "registration: expected true or false");
  std::string many = "parts: [";
  for (int i = 0; i < 200; ++i) many += (i ? ", p" : "p") + std::to_string(i);
  many += "]\nscanners: [";
  for (int i = 0; i < 60; ++i) many += (i ? ", s" : "s") + std::to_string(i);
  EXPECT_EQ(error(many + "]\n"), "12000 plans: a study holds at most 10000");
  EXPECT_THROW(loadStudy(dir.file("missing.yaml")), InputError);
  // A name from hostile file names stays a folder of its own under the study's.
  test::writeText(path, "parts: [\"...stp\", \"a b;c\\n.stp\"]\n");
  const Study odd = loadStudy(path);
  EXPECT_EQ(odd.rows[0].name, "_.");
  EXPECT_EQ(odd.rows[1].name, "a_b_c_");
}

}  // namespace
}  // namespace scanplan
