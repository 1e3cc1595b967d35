// CAD files made to crash, hang or exhaust OCCT's readers: each is refused with an
// InputError naming the file, and the process goes on. The readers run in a child process
// (core/isolated.h), tested here on work that crashes, loops and allocates without end.

#include "occt_support.h"
#include "support.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/core/isolated.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>

#include <csignal>
#include <fstream>
#include <iterator>
#include <sstream>
#include <thread>
#include <vector>

namespace scanplan {
namespace {

using test::contains;
using test::importError;

// A 100 x 60 x 40 mm box with a through hole, every face a B-spline.
TopoDS_Shape nurbsBoxWithHole() {
  TopoDS_Shape box = BRepPrimAPI_MakeBox(100, 60, 40).Shape();
  TopoDS_Shape hole =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(50, 30, -1), gp::DZ()), 10, 42).Shape();
  return BRepBuilderAPI_NurbsConvert(BRepAlgoAPI_Cut(box, hole).Shape()).Shape();
}

std::string writeIges(const TopoDS_Shape& shape, const std::string& path) {
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 1);
  writer.AddShape(shape);
  writer.ComputeModel();
  EXPECT_TRUE(writer.Write(path.c_str()));
  return path;
}

// The IGES text with the parameter lines of its first rational B-spline curve (type 126)
// cut after `kept`, the entity's lines kept in number (blank) so that the directory and
// the Terminate section still match.
std::string cutFirstBSplineCurve(const std::string& text, const std::string& kept) {
  std::istringstream in(text);
  std::ostringstream out;
  std::string line, entity;
  bool done = false;
  while (std::getline(in, line)) {
    const bool parameter = line.size() >= 73 && line[72] == 'P';
    if (!done && parameter && entity.empty() && line.rfind("126,", 0) == 0) {
      entity = line.substr(64, 8);  // its directory pointer, columns 65-72
      out << (kept + std::string(64 - kept.size(), ' ')) << line.substr(64) << '\n';
      continue;
    }
    if (!done && !entity.empty() && parameter && line.substr(64, 8) == entity) {
      out << std::string(64, ' ') << line.substr(64) << '\n';
      continue;
    }
    if (!entity.empty()) done = true;
    out << line << '\n';
  }
  return out.str();
}

// OCCT's IGES reader dereferences parameters past the end of an entity whose parameter
// lines stop early, and dies on SIGSEGV: the reader runs apart, and its crash is an error.
TEST(HostileCad, IgesBSplineWithItsParametersCutShortIsRefusedWithoutACrash) {
  test::TempDir dir;
  const std::string whole = writeIges(nurbsBoxWithHole(), dir.file("whole.igs"));
  EXPECT_EQ(importPart(whole).faces.size(), 7u);
  test::writeText(dir.file("cut.igs"), cutFirstBSplineCurve(test::readText(whole), "126,5,3;"));
  EXPECT_PRED2(contains, importError(dir.file("cut.igs")), "the IGES reader crashed on it");
  // The process that survived reads the whole file again, unchanged.
  EXPECT_EQ(importPart(whole).faces.size(), 7u);
}

// A BREP table announcing a billion curves, a byte that is no text or a letter in a
// number sends OCCT's reader round a loop without end, or makes it read nonsense.
TEST(HostileCad, BrepThatWouldLoopTheReaderIsRefused) {
  test::TempDir dir;
  const std::string whole =
      test::writeBrep(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), dir.file("box.brep"));
  std::string text = test::readText(whole);
  for (const char* table : {"Curves", "Curve2ds"}) {
    const std::size_t at = text.find(std::string("\n") + table + " ");
    ASSERT_NE(at, std::string::npos) << table;
    std::string edited = text;
    edited.replace(at + 1, edited.find('\n', at + 1) - at - 1, std::string(table) + " 1000000000");
    test::writeText(dir.file("edited.brep"), edited);
    EXPECT_PRED2(contains, importError(dir.file("edited.brep")),
                 "the table " + std::string(table) + " announces 1000000000 entries");
  }
  // Bytes that are no text inside a number: OCCT's reader loops on them.
  const std::size_t shapes = text.find("\nTShapes ");
  ASSERT_NE(shapes, std::string::npos);
  const std::size_t digit = text.find_first_of("0123456789", text.find('\n', shapes + 1));
  test::writeText(dir.file("bytes.brep"), std::string(text).insert(digit + 1, "\xff\xff"));
  EXPECT_PRED2(contains, importError(dir.file("bytes.brep")),
               "a byte that is no text (0xff): an OCCT BREP file is plain ASCII");
  // A letter in a number: in the kind of an edge's curve on a surface ("2  1 1 0 0 40")
  // OCCT's reader loops on it, in a vertex's tolerance it reads nonsense and says nothing.
  for (const std::string& kind : {std::string("\n2  "), std::string("\nVe\n")}) {
    const std::size_t shape = text.find(kind, shapes);
    ASSERT_NE(shape, std::string::npos) << kind;
    const std::size_t at = text.find_first_of("0123456789", shape);
    std::string edited = text;
    edited.insert(at + 1, "x");
    test::writeText(dir.file("letter.brep"), edited);
    const std::size_t end = edited.find_first_of(" \n", at);
    EXPECT_PRED2(contains, importError(dir.file("letter.brep")),
                 "'" + edited.substr(at, end - at) +
                     "' is neither a number nor a word of an OCCT BREP file");
  }
}

// The cylinder of FTC 11's first CYLINDRICAL_SURFACE with radius `radius`; its reason.
std::string cylinderRadiusError(const test::TempDir& dir, const std::string& radius) {
  std::string text = test::readText(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  const std::size_t at = text.find("CYLINDRICAL_SURFACE('',#");
  if (at == std::string::npos) return "no cylinder in the file";
  const std::size_t comma = text.find(',', text.find('#', at));
  text.replace(comma + 1, text.find(')', comma) - comma - 1, radius);
  test::writeText(dir.file("radius.stp"), text);
  return importError(dir.file("radius.stp"));
}

// A radius that overflows to infinity makes OCCT mesh without end; one of 1e14 mm gives a
// face 1e16 mm² wide. The first is refused as a number, the second as geometry.
TEST(HostileCad, StepNumbersBeyondAnyPartAreRefusedBeforeMeshing) {
  test::TempDir dir;
  EXPECT_PRED2(contains, cylinderRadiusError(dir, "1.E400"),
               "holds the number 1.E400, beyond the ±1e15");
  EXPECT_PRED2(contains, cylinderRadiusError(dir, "-1.E300"),
               "holds the number -1.E300, beyond the ±1e15");
  EXPECT_PRED2(contains, cylinderRadiusError(dir, "1.E14"), "reaches 1e+14 mm from the origin");
}

// OCCT takes one of two definitions of an entity silently, and drops a face of negative
// radius with its solid: the first is refused, the second warned of by count.
TEST(HostileCad, StepEntityDefinedTwiceIsRefusedAndALostFaceWarnedOf) {
  test::TempDir dir;
  std::string text = test::readText(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  const std::size_t at = text.find("\n#", text.find("DATA;"));
  const std::string first = text.substr(at + 1, text.find(';', at + 1) - at);  // one entity
  test::writeText(dir.file("twice.stp"), std::string(text).insert(at + 1, first + "\n"));
  const std::string id = first.substr(0, first.find('='));
  EXPECT_EQ(importError(dir.file("twice.stp")), "entity " + id + " is defined twice");
  const Part whole = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  EXPECT_TRUE(whole.warnings.empty());
  const std::size_t cylinder = text.find("CYLINDRICAL_SURFACE('',#");
  const std::size_t comma = text.find(',', text.find('#', cylinder));
  text.replace(comma + 1, text.find(')', comma) - comma - 1, "-2.");
  test::writeText(dir.file("negative.stp"), text);
  const Part part = importPart(dir.file("negative.stp"));
  ASSERT_EQ(part.faces.size(), whole.faces.size() - 1);
  ASSERT_EQ(part.warnings.size(), 2u);
  EXPECT_EQ(part.warnings[0],
            "the file defines 8 faces, of which 7 could be read: the others' "
            "geometry is corrupt");
  EXPECT_EQ(part.warnings[1],
            "the file defines 1 solids, of which 0 could be read: a face of "
            "the others could not be");
}

// Single-precision ray casting keeps 0.01 mm only within 100 m of the origin: a small part
// far away is refused, not simulated with millimetre noise.
TEST(HostileCad, PartFarFromTheOriginIsRefused) {
  test::TempDir dir;
  gp_Trsf far;
  far.SetTranslation(gp_Vec(5e5, 0, 0));
  const TopoDS_Shape box =
      BRepBuilderAPI_Transform(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), far).Shape();
  EXPECT_PRED2(contains, importError(test::writeBrep(box, dir.file("far.brep"))),
               "the part lies 5e+05 mm from the origin of its file, more than 100 m");
  far.SetTranslation(gp_Vec(5e4, 0, 0));
  const TopoDS_Shape near =
      BRepBuilderAPI_Transform(BRepPrimAPI_MakeBox(10, 20, 30).Shape(), far).Shape();
  EXPECT_EQ(importPart(test::writeBrep(near, dir.file("near.brep"))).faces.size(), 6u);
}

std::string isolatedError(const IsolationLimits& limits, const std::function<std::string()>& work) {
  try {
    runIsolated("file.x", "the reader", limits, work);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "file.x");
    return e.reason();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

TEST(Isolation, ResultOfTheChildIsHandedBackWhole) {
  std::string big(5'000'000, '\0');
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>(i * 7919 % 251);
  EXPECT_EQ(runIsolated("file.x", "the reader", {}, [&] { return big; }), big);
  EXPECT_EQ(runIsolated("file.x", "the reader", {}, [] { return std::string(); }), "");
}

TEST(Isolation, ErrorOfTheChildKeepsItsReason) {
  EXPECT_EQ(isolatedError({}, []() -> std::string { throw InputError("other", "line 3: bad"); }),
            "line 3: bad");
  EXPECT_PRED2(contains,
               isolatedError({}, []() -> std::string { throw std::runtime_error("odd"); }),
               "the reader failed on it: odd");
}

TEST(Isolation, CrashOfTheChildIsAnErrorOfThisProcess) {
  EXPECT_PRED2(contains,
               isolatedError({},
                             []() -> std::string {
                               std::raise(SIGSEGV);
                               return {};
                             }),
               "the reader crashed on it (");
  EXPECT_PRED2(contains, isolatedError({}, []() -> std::string { std::abort(); }),
               "the reader crashed on it (");
}

TEST(Isolation, ChildThatDoesNotFinishIsStoppedAtItsTime) {
  IsolationLimits limits;
  limits.seconds = 0.5;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_PRED2(contains,
               isolatedError(limits,
                             []() -> std::string {
                               for (;;) std::this_thread::sleep_for(std::chrono::milliseconds(10));
                             }),
               "the reader did not finish within 0.5 s");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(3));
}

TEST(Isolation, ChildThatAllocatesBeyondItsLimitRunsOutOfMemory) {
  if (readerLimits(1).bytes == 0) GTEST_SKIP() << "sanitizer build: no address-space limit";
  IsolationLimits limits;
  limits.bytes = std::size_t{256} << 20;
  EXPECT_PRED2(contains,
               isolatedError(limits,
                             []() -> std::string {
                               std::vector<char> huge(std::size_t{1} << 30, 'x');
                               return std::string(1, huge.back());
                             }),
               "the reader ran out of memory on it (more than 0.2 GiB");
}

}  // namespace
}  // namespace scanplan
