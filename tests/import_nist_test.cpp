// Import of the NIST MBE PMI test models against what OCCT's own XDE reports for them
// (../shared/data/STATS.txt): faces, surface types, GD&T counts; plus the mesh checks
// every later stage relies on: every face triangulated, closed, outward.

#include "support.h"

#include <scanplan/cad/elementary.h>
#include <scanplan/cad/import.h>

#include <gtest/gtest-spi.h>

#include <cstdlib>
#include <fstream>

#include <map>
#include <set>

namespace scanplan {
namespace {

struct NistCase {
  std::string file;
  bool committed;  // a copy is in tests/data or examples/parts
  int faces;
  std::map<std::string, int> surfaces;
  std::size_t dimensions, tolerances, datum_labels;
};

// Expected values: ../shared/data/STATS.txt (OCCT 7.6.3 XDE reader with GD&T mode).
const std::vector<NistCase> kNistCases = {
    {"nist_ctc_01_asme1_ap242-e1.stp",
     true,
     117,
     {{"Cone", 4}, {"Cylinder", 57}, {"Plane", 56}},
     12,
     6,
     11},
    {"nist_ctc_02_asme1_ap242-e2.stp",
     false,
     637,
     {{"BSpline", 34}, {"Cone", 158}, {"Cylinder", 314}, {"Plane", 107}, {"Sphere", 24}},
     7,
     22,
     87},
    {"nist_ctc_03_asme1_ap242-e2.stp", true, 120, {{"Cylinder", 58}, {"Plane", 62}}, 10, 12, 26},
    {"nist_ctc_04_asme1_ap242-e1.stp",
     false,
     484,
     {{"Cone", 116}, {"Cylinder", 228}, {"Plane", 89}, {"Sphere", 22}, {"Torus", 29}},
     13,
     6,
     15},
    {"nist_ftc_06_asme1_ap242-e1.stp",
     false,
     187,
     {{"Cone", 8}, {"Cylinder", 88}, {"Plane", 71}, {"Sphere", 8}, {"Torus", 12}},
     48,
     27,
     59},
    {"nist_ftc_07_asme1_ap242-e2.stp",
     false,
     338,
     {{"BSpline", 20},
      {"Cone", 36},
      {"Cylinder", 143},
      {"Plane", 97},
      {"Sphere", 18},
      {"Torus", 24}},
     21,
     24,
     56},
    {"nist_ftc_08_asme1_ap242-e1.stp",
     false,
     248,
     {{"Cylinder", 134}, {"Plane", 82}, {"Sphere", 20}, {"Torus", 12}},
     13,
     33,
     76},
    {"nist_ftc_11_asme1_ap242-e1.stp",
     true,
     8,
     {{"Cylinder", 2}, {"Plane", 2}, {"Torus", 4}},
     6,
     4,
     4},
};

void PrintTo(const NistCase& c, std::ostream* os) { *os << c.file; }

std::string pathOf(const NistCase& c) {
  if (c.file == "nist_ctc_01_asme1_ap242-e1.stp") return test::example("parts/" + c.file);
  if (c.committed) return test::testData(c.file);
  return std::string(SCANPLAN_SHARED_DATA) + "/nist/" + c.file;
}

// A test that needs a file of the shared data that is not there.
void needsAMissingSharedFile() {
  SHARED_FILE_OR_SKIP(std::string("/nonexistent/scanplan-shared/part.stp"));
}

// Where the shared data is required (as scripts/check.sh requires it in CI), a test whose
// file of it is missing fails, naming the file, rather than skipping.
TEST(SharedData, AMissingFileFailsTheTestWhereTheDataIsRequired) {
  const char* before = std::getenv("SCANPLAN_REQUIRE_SHARED_DATA");
  const std::string saved = before != nullptr ? before : "";
  setenv("SCANPLAN_REQUIRE_SHARED_DATA", "1", 1);
  EXPECT_FATAL_FAILURE(needsAMissingSharedFile(),
                       "shared data not found: /nonexistent/scanplan-shared/part.stp");
  if (before != nullptr)
    setenv("SCANPLAN_REQUIRE_SHARED_DATA", saved.c_str(), 1);
  else
    unsetenv("SCANPLAN_REQUIRE_SHARED_DATA");
}

class NistImport : public testing::TestWithParam<NistCase> {};

TEST_P(NistImport, MatchesXdeAndMeshIsClosedAndOutward) {
  const NistCase& c = GetParam();
  std::string path = pathOf(c);
  SHARED_FILE_OR_SKIP(path);
  const Part& part = test::importedOnce(path);

  ASSERT_EQ(part.faces.size(), static_cast<std::size_t>(c.faces));
  std::map<std::string, int> surfaces;
  for (const Face& face : part.faces) ++surfaces[std::string(toString(face.type))];
  EXPECT_EQ(surfaces, c.surfaces);
  EXPECT_EQ(part.gdt.dimensions.size(), c.dimensions);
  EXPECT_EQ(part.gdt.tolerances.size(), c.tolerances);
  EXPECT_EQ(part.gdt.datum_labels, c.datum_labels);
  ASSERT_EQ(part.solids.size(), 1u);

  for (const Face& face : part.faces) {
    EXPECT_EQ(face.id, &face - part.faces.data() + 1);
    EXPECT_GT(face.triangle_count, 0) << "face " << face.id << " has no triangles";
    EXPECT_GT(face.area, 0) << "face " << face.id;
  }
  // The solid is closed: after welding coincident nodes every edge of its triangles has
  // exactly two of them, wound in opposite directions. (Some NIST files add free shells
  // outside the solid.)
  TriangleMesh solid = part.meshOf(part.solids.front().faces);
  EdgeReport edges = edgeReport(solid, 1e-6 * part.bounds().diagonal());
  EXPECT_EQ(edges.boundary, 0u);
  EXPECT_EQ(edges.non_manifold, 0u);
  EXPECT_EQ(edges.misoriented, 0u);
  // Outward: the mesh encloses the solid's exact volume up to the chordal tolerance.
  double mesh_volume = signedVolume(solid);
  EXPECT_GT(mesh_volume, 0);
  EXPECT_NEAR(mesh_volume, part.volume(), 2 * part.linear_deflection * part.area());
}

TEST_P(NistImport, ToleranceFacesAreValidIds) {
  const NistCase& c = GetParam();
  std::string path = pathOf(c);
  SHARED_FILE_OR_SKIP(path);
  const Part& part = test::importedOnce(path);
  std::size_t attached = 0;
  for (const GeometricTolerance& t : part.gdt.tolerances) {
    EXPECT_NE(t.type, "unknown");
    EXPECT_GT(t.value, 0) << t.type << " on faces " << testing::PrintToString(t.faces);
    attached += !t.faces.empty();
    for (int id : t.faces) EXPECT_NO_THROW(part.face(id));
  }
  // Every NIST tolerance is attached to geometry.
  EXPECT_EQ(attached, part.gdt.tolerances.size());
}

// A diameter or radius the file gives on cylinders of one radius is that radius (twice
// for a diameter) as the B-Rep models it, within its tolerance and a hundredth of a
// millimetre: the file's unit read once, whether it writes the value as a qualified item
// (FTC 06, 07), which OCCT leaves in the file's unit, or not (FTC 08), which it converts.
TEST_P(NistImport, SizeDimensionsAreTheirCylindersSize) {
  const NistCase& c = GetParam();
  std::string path = pathOf(c);
  SHARED_FILE_OR_SKIP(path);
  const Part& part = test::importedOnce(path);
  std::size_t checked = 0;
  for (const Dimension& d : part.gdt.dimensions) {
    if ((d.type != "diameter" && d.type != "radius") || d.faces.empty()) continue;
    std::set<double> radii;
    for (int id : d.faces) {
      const auto surface = elementarySurface(part, id);
      radii.insert(surface && surface->type == SurfaceType::Cylinder ? surface->radius : -1);
    }
    if (radii.size() != 1 || *radii.begin() < 0) continue;
    const double modelled = (d.type == "diameter" ? 2 : 1) * *radii.begin();
    EXPECT_NEAR(d.value, modelled, std::max(d.lower, d.upper) + 0.01)
        << d.type << " on faces " << testing::PrintToString(d.faces);
    ++checked;
  }
  EXPECT_GT(checked, 0u);
}

// A distance the file gives between faces that lie on two parallel planes is those planes'
// distance apart as the B-Rep models them, within its tolerance and a hundredth of a
// millimetre.
TEST_P(NistImport, DistancesBetweenParallelPlanesAreTheirSpacing) {
  const NistCase& c = GetParam();
  std::string path = pathOf(c);
  SHARED_FILE_OR_SKIP(path);
  const Part& part = test::importedOnce(path);
  for (const Dimension& d : part.gdt.dimensions) {
    if (d.type != "linear_distance" || d.faces.empty()) continue;
    std::vector<std::pair<Vec3, double>> planes;  // normal (one way), offset along it
    bool all_planes = true;
    for (int id : d.faces) {
      const auto s = elementarySurface(part, id);
      if (!s || s->type != SurfaceType::Plane) {
        all_planes = false;
        break;
      }
      Vec3 n = s->axis.normalized();
      if (!planes.empty() && n.dot(planes.front().first) < 0) n = -n;
      const double offset = n.dot(s->origin);
      if (std::none_of(planes.begin(), planes.end(), [&](const auto& q) {
            return q.first.dot(n) > 1 - 1e-9 && std::abs(q.second - offset) < 1e-6;
          }))
        planes.emplace_back(n, offset);
    }
    if (!all_planes || planes.size() != 2 || planes[0].first.dot(planes[1].first) < 1 - 1e-9)
      continue;
    RecordProperty("distance_" + std::to_string(&d - part.gdt.dimensions.data()),
                   std::to_string(d.value) + " " +
                       std::to_string(std::abs(planes[0].second - planes[1].second)));
    EXPECT_NEAR(d.value, std::abs(planes[0].second - planes[1].second),
                std::max(d.lower, d.upper) + 0.01)
        << "faces " << testing::PrintToString(d.faces);
  }
}

INSTANTIATE_TEST_SUITE_P(Nist, NistImport, testing::ValuesIn(kNistCases),
                         [](const auto& param_info) {
                           std::string name = param_info.param.file.substr(0, 11);
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

// The GD&T of FTC 06 as its drawing gives it (NIST FTC definitions): the flatness of
// datum A is 0.01 in on one face, and datum A is that face.
TEST(NistGdt, Ftc06FlatnessOfDatumA) {
  SHARED_DATA_OR_SKIP(path, "nist/nist_ftc_06_asme1_ap242-e1.stp");
  const Part& part = test::importedOnce(path);
  const GeometricTolerance& flatness = part.gdt.tolerances.front();
  EXPECT_EQ(flatness.type, "flatness");
  EXPECT_NEAR(flatness.value, 0.254, 1e-9);  // 0.01 in
  ASSERT_EQ(flatness.faces.size(), 1u);
  auto datum_a = std::find_if(part.gdt.datums.begin(), part.gdt.datums.end(),
                              [](const Datum& d) { return d.name == "A"; });
  ASSERT_NE(datum_a, part.gdt.datums.end());
  EXPECT_EQ(datum_a->faces, flatness.faces);
  EXPECT_EQ(part.face(flatness.faces.front()).type, SurfaceType::Plane);
}

// FTC 08 names two common datums (COMMON_DATUM_LIST in its text: E with F, H with J, each
// in the second compartment after D): they read as one reference, "E-F", not as a
// secondary and a tertiary; the profile's 48 faces are referred to D then E-F.
TEST(NistGdt, Ftc08CommonDatumsReadAsOneReference) {
  SHARED_DATA_OR_SKIP(path, "nist/nist_ftc_08_asme1_ap242-e1.stp");
  const Part part = importPart(path);
  std::size_t common = 0;
  for (const GeometricTolerance& t : part.gdt.tolerances) {
    for (const std::string& d : t.datums) common += d.find('-') != std::string::npos;
    if (t.faces.size() == 48) {
      EXPECT_EQ(t.datums, (std::vector<std::string>{"D", "E-F"}));
    }
  }
  EXPECT_EQ(common, 2u);
  EXPECT_EQ(datumLetters("E-F"), (std::vector<std::string>{"E", "F"}));
  std::vector<int> both = datumFaces(part.gdt, "E");
  for (int f : datumFaces(part.gdt, "F")) both.push_back(f);
  std::sort(both.begin(), both.end());
  EXPECT_EQ(datumFaces(part.gdt, "E-F"), both);
  EXPECT_FALSE(both.empty());
}

// FTC 06 gives its dimensions in inches as 'nominal value' items; the 12 in distance
// between faces 22 and 107 (datum B) is the part's width along x.
TEST(NistGdt, Ftc06DimensionsAreInMillimetres) {
  SHARED_DATA_OR_SKIP(path, "nist/nist_ftc_06_asme1_ap242-e1.stp");
  const Part& part = test::importedOnce(path);
  auto width =
      std::find_if(part.gdt.dimensions.begin(), part.gdt.dimensions.end(), [](const Dimension& d) {
        return d.faces == std::vector<int>{22, 107};
      });
  ASSERT_NE(width, part.gdt.dimensions.end());
  EXPECT_EQ(width->type, "linear_distance");
  EXPECT_NEAR(width->value, 12 * 25.4, 1e-9);
  EXPECT_NEAR(width->value, part.bounds().size().x(), 0.01);
  EXPECT_NEAR(width->upper, 0.01 * 25.4, 1e-9);  // #16683: 0.01 in, converted by OCCT
}

// CTC 01 writes every tolerance magnitude as a complex measure entity, which OCCT 7.6
// reads as 0; the values come from the STEP text. Expected, as the file writes them:
// #57 FLATNESS_TOLERANCE magnitude #82 = 0.2 mm; #25, #30 position magnitudes #95,
// #96 = 0.75 mm (unit #4361, SI millimetre).
TEST(NistGdt, Ctc01ToleranceMagnitudes) {
  const Part& part = test::importedOnce(test::example("parts/nist_ctc_01_asme1_ap242-e1.stp"));
  ASSERT_EQ(part.gdt.tolerances.size(), 6u);
  std::map<std::string, std::vector<double>> values;
  for (const GeometricTolerance& t : part.gdt.tolerances) values[t.type].push_back(t.value);
  EXPECT_EQ(values["flatness"], std::vector<double>{0.2});
  EXPECT_EQ(values["position"], (std::vector<double>{0.75, 0.75}));
}

// CTC 01 names the faces of its datum features B and C by ITEM_IDENTIFIED_REPRESENTATION_USAGE
// of a SET_REPRESENTATION_ITEM (#28: feature #35, datum B, faces #854 and #853; #29: #36,
// datum C, faces #839 and #840), which OCCT 7.6 reads as no face. Each pair is the two
// halves of a Ø35 bore, the two bores apart, and each carries one of the file's Ø35
// diameters (whose faces OCCT links by GEOMETRIC_ITEM_SPECIFIC_USAGE, another path).
TEST(NistGdt, Ctc01DatumsBAndCAreTwoBoresOfTheFilesDiameters) {
  const Part& part = test::importedOnce(test::example("parts/nist_ctc_01_asme1_ap242-e1.stp"));
  std::set<int> seen;
  for (const std::string letter : {"B", "C"}) {
    SCOPED_TRACE(letter);
    const std::vector<int> faces = datumFaces(part.gdt, letter);
    ASSERT_EQ(faces.size(), 2u);
    Box bore;
    for (int f : faces) {
      EXPECT_EQ(part.face(f).type, SurfaceType::Cylinder);
      EXPECT_TRUE(seen.insert(f).second);
      bore.add(part.face(f).bounds);
    }
    const Vec3 size = bore.size();
    const double across = std::max(
        {std::min(size.x(), size.y()), std::min(size.y(), size.z()), std::min(size.x(), size.z())});
    EXPECT_NEAR(across, 35, 0.5);
    const bool dimensioned = std::any_of(
        part.gdt.dimensions.begin(), part.gdt.dimensions.end(), [&](const Dimension& d) {
          return d.type == "diameter" && std::abs(d.value - 35) < 1e-9 && d.faces == faces;
        });
    EXPECT_TRUE(dimensioned);
  }
}

// A usage whose name runs to 5,000 characters is not read as one: the import goes on,
// datum B (the usage #28 names its faces) left on no face, C linked as before.
TEST(NistGdt, AnOverlongItemUsageIsPassedOver) {
  test::TempDir dir;
  std::ifstream in(test::example("parts/nist_ctc_01_asme1_ap242-e1.stp"), std::ios::binary);
  std::string text{std::istreambuf_iterator<char>(in), {}};
  const std::string usage = "#28=ITEM_IDENTIFIED_REPRESENTATION_USAGE('',";
  const std::size_t at = text.find(usage);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, usage.size(),
               "#28=ITEM_IDENTIFIED_REPRESENTATION_USAGE('" + std::string(5000, 'x') + "',");
  test::writeText(dir.file("long.stp"), text);
  const Part part = importPart(dir.file("long.stp"));
  EXPECT_TRUE(datumFaces(part.gdt, "B").empty());
  EXPECT_EQ(datumFaces(part.gdt, "C").size(), 2u);
}

// CTC 02's datum A is three target points (#102-#104, datum #125 'A'), placed by the file at
// (0, 705.44, -330), (180, 75.44, -330) and (-180, 75.44, -330): datum A is the plane face
// at z = -330 that holds them.
TEST(NistGdt, Ctc02DatumAIsTheFaceItsTargetPointsLieOn) {
  SHARED_DATA_OR_SKIP(path, "nist/nist_ctc_02_asme1_ap242-e2.stp");
  const Part part = importPart(path);
  const std::vector<int> faces = datumFaces(part.gdt, "A");
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_EQ(part.face(faces.front()).type, SurfaceType::Plane);
  const Box& face = part.face(faces.front()).bounds;
  EXPECT_NEAR(face.min.z(), -330, 1e-6);
  EXPECT_NEAR(face.max.z(), -330, 1e-6);
  for (const Vec3& target :
       {Vec3(0, 705.44388876, -330), Vec3(180, 75.44388876, -330), Vec3(-180, 75.44388876, -330)})
    EXPECT_TRUE((target.array() >= face.min.array() - 1e-6).all() &&
                (target.array() <= face.max.array() + 1e-6).all())
        << target.transpose();
}

}  // namespace
}  // namespace scanplan
