// The scanplan tool run as a user runs it: output, exit codes, error messages.

#include "support.h"

#include <scanplan/cad/elementary.h>
#include <scanplan/cad/import.h>
#include <scanplan/cad/ply.h>
#include <scanplan/core/version.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/points_csv.h>
#include <scanplan/io/views_csv.h>
#include <scanplan/registration/registration.h>
#include <scanplan/report/report.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <tuple>

namespace scanplan {
namespace {

struct CommandResult {
  int code = -1;
  std::string out;  // stdout and stderr together
};

// Runs scanplan with `arguments` in `folder` (default: the test's).
CommandResult run(const std::string& arguments, const std::string& folder = "") {
  CommandResult result;
  std::string command = std::string(SCANPLAN_EXE) + " " + arguments + " 2>&1";
  if (!folder.empty()) command = "cd '" + folder + "' && " + command;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  while (std::size_t n = fread(buffer.data(), 1, buffer.size(), pipe))
    result.out.append(buffer.data(), n);
  int status = pclose(pipe);
  result.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

TEST(Cli, InfoOnTheExamplePart) {
  std::string part = test::example("parts/nist_ctc_01_asme1_ap242-e1.stp");
  CommandResult r = run("info " + part);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("faces        117"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("6 tolerances, 12 dimensions"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("flatness"), std::string::npos) << r.out;
}

TEST(Cli, VerboseWritesTheTimeOfEachImportStep) {
  const std::string part = test::example("parts/nist_ctc_01_asme1_ap242-e1.stp");
  CommandResult r = run("--verbose --quiet info " + part);
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* step : {"checking STEP entities", "reading and transferring STEP",
                           "orienting faces", "meshing", "measuring faces", "reading GD&T"})
    EXPECT_TRUE(
        std::regex_search(r.out, std::regex(std::string("(^|\\n)  ") + step + " +[0-9.]+ s\\n")))
        << step << "\n"
        << r.out;
  // Without it, no times.
  r = run("--quiet info " + part);
  EXPECT_EQ(r.out.find("reading STEP"), std::string::npos) << r.out;
}

TEST(Cli, InfoJsonIsOneObject) {
  std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  CommandResult r = run("info --json --quiet " + part);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.out.front(), '{');
  EXPECT_NE(r.out.find("\"faces\": 8"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"tolerances\""), std::string::npos) << r.out;
}

TEST(Cli, Ftc06PrintsItsFacesAndTolerances) {
  SHARED_DATA_OR_SKIP(part, "nist/nist_ftc_06_asme1_ap242-e1.stp");
  CommandResult r = run("info " + part);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("faces        187"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("27 tolerances"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("position             0.381 | E | A | B  faces 164"), std::string::npos)
      << r.out;
}

TEST(Cli, MissingFileIsExitCodeTwo) {
  CommandResult r = run("info /nonexistent/part.step");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.out, "error: /nonexistent/part.step: no such file\n");
}

TEST(Cli, UnsupportedExtensionIsExitCodeTwo) {
  test::TempDir dir;
  test::writeText(dir.file("part.dwg"), "x");
  CommandResult r = run("info " + dir.file("part.dwg"));
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.out.rfind("error: " + dir.file("part.dwg") + ": unsupported file type", 0), 0u)
      << r.out;
}

TEST(Cli, EmptyMeshIsExitCodeTwo) {
  test::TempDir dir;
  test::writeText(dir.file("empty.stl"), "solid empty\nendsolid empty\n");
  CommandResult r = run("info " + dir.file("empty.stl"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("no triangles"), std::string::npos) << r.out;
}

TEST(Cli, BadUsageIsExitCodeOne) {
  EXPECT_EQ(run("").code, 1);
  EXPECT_EQ(run("frobnicate").code, 1);
  EXPECT_EQ(run("info").code, 1);
  EXPECT_EQ(run("info x.step --deflection nonsense").code, 1);
  EXPECT_EQ(run("--threads 0 info x.step").code, 1);
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  const CommandResult r = run("plan " + part + " --coverage 0 -o never-written -q");
  EXPECT_EQ(r.code, 1);
  EXPECT_PRED2(test::contains, r.out, "--coverage: must be a share within (0, 1]");
  EXPECT_FALSE(std::filesystem::exists("never-written"));
  // A number out of its option's range is named in one short line, its range in it.
  for (const std::string bad : {"export p.json --format rapid --setup 0 -o x.mod",
                                "export p.json --format clouds-ply --spacing -1 -o x.ply",
                                "inspect p.json x.stp --spacing 0", "inspect p.json x.stp --runs 1",
                                "--threads 0 info x.step"}) {
    const CommandResult refused = run(bad);
    EXPECT_EQ(refused.code, 1) << bad;
    const std::string line = refused.out.substr(0, refused.out.find('\n'));
    EXPECT_LT(line.size(), 100u) << bad << ": " << line;
    EXPECT_PRED2(test::contains, line, "not in range") << bad;
  }
  // Markers are placed for one rest orientation: refused before the part is planned.
  const CommandResult every =
      run("plan " + part + " --rest all --place-markers -o never-written -q");
  EXPECT_EQ(every.code, 1);
  EXPECT_PRED2(test::contains, every.out, "--place-markers: plans one rest orientation only");
  EXPECT_FALSE(std::filesystem::exists("never-written"));
}

TEST(Cli, SimulateTwoViewsWithClouds) {
  test::TempDir dir;
  // The example part lifted onto the working plane, seen from above at the standoff.
  test::writeText(dir.file("views.json"),
                  R"({"part": {"part_to_world": [[1,0,0,0],[0,1,0,0],[0,0,1,100],[0,0,0,1]]},
                      "views": [{"id": 1, "camera_to_world": [[1,0,0,0],[0,-1,0,0],[0,0,-1,550],[0,0,0,1]]},
                                {"id": 2, "camera_to_world": [[1,0,0,-200],[0,-1,0,0],[0,0,-1,550],[0,0,0,1]]}]})");
  test::writeText(dir.file("spec.yaml"),
                  "scanner:\n  preset: generic-structured-light\n  point_spacing: 2\n");
  std::string part = test::example("parts/nist_ctc_01_asme1_ap242-e1.stp");
  CommandResult r = run("simulate " + part + " --views " + dir.file("views.json") + " --spec " +
                        dir.file("spec.yaml") + " -o " + dir.file("clouds"));
  ASSERT_EQ(r.code, 0) << r.out;
  // Face 98 is the top plate (z = 50 in the part frame): both views measure it.
  EXPECT_NE(r.out.find("view 1: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("view 2: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(98,"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir.file("clouds/view_1.ply")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("clouds/view_2.ply")));

  CommandResult json = run("simulate -q --json " + part + " --views " + dir.file("views.json"));
  ASSERT_EQ(json.code, 0) << json.out;
  EXPECT_EQ(json.out.front(), '{');
  EXPECT_NE(json.out.find("\"camera_angle\""), std::string::npos);
}

// A plan of NIST FTC 11 with the laser-line head, in both its rest orientations: simulated
// from its plan.json, each view is simulated with the plan's scanner and the part standing
// as the view's setup places it, as when each setup's views are given with that placement
// and the scanner named.
TEST(Cli, SimulatingAPlanTakesItsScannerAndEachSetupsPlacement) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  test::writeText(dir.file("spec.yaml"),
                  "part: {rest: all}\nscanner: laser-line\ntasks: [{type: global}]\n");
  CommandResult r = run("-q plan " + part + " --spec " + dir.file("spec.yaml") + " -o " +
                        dir.file("out") + " --no-report --no-registration");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string plan = dir.file("out/plan.json");
  const nlohmann::json planned = nlohmann::json::parse(test::readText(plan));
  ASSERT_EQ(planned["orientations"].size(), 2u);
  r = run("-q simulate --json " + part + " --views " + plan);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json all = nlohmann::json::parse(r.out);
  EXPECT_EQ(all["scanner"], "laser-line");
  std::map<int, double> area;  // by view id
  for (const nlohmann::json& view : all["views"])
    area[view["id"].get<int>()] = view["measured_area"].get<double>();
  ASSERT_EQ(area.size(), planned["views"].size());
  for (const nlohmann::json& setup : planned["orientations"]) {
    nlohmann::json views = nlohmann::json::array();
    for (const nlohmann::json& view : planned["views"])
      if (view["orientation"] == setup["id"])
        views.push_back({{"id", view["id"]}, {"camera_to_world", view["camera_to_world"]}});
    ASSERT_FALSE(views.empty()) << "setup " << setup["id"];
    test::writeText(
        dir.file("setup.json"),
        nlohmann::json{{"part", {{"part_to_world", setup["part_to_world"]}}}, {"views", views}}
            .dump());
    r = run("-q simulate --json " + part + " --views " + dir.file("setup.json") +
            " --scanner laser-line");
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json alone = nlohmann::json::parse(r.out);
    ASSERT_EQ(alone["views"].size(), views.size());
    for (const nlohmann::json& view : alone["views"]) {
      const int id = view["id"].get<int>();
      EXPECT_GT(view["measured_area"].get<double>(), 0) << "view " << id;
      EXPECT_NEAR(area.at(id), view["measured_area"].get<double>(), 1e-6) << "view " << id;
    }
  }
}

TEST(Cli, SimulateBadInputsAreExitCodeTwo) {
  test::TempDir dir;
  std::string part = test::example("parts/nist_ctc_01_asme1_ap242-e1.stp");
  test::writeText(dir.file("scaled.json"),
                  R"([{"camera_to_world": [[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}])");
  CommandResult r = run("simulate " + part + " --views " + dir.file("scaled.json"));
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.out.rfind("error: " + dir.file("scaled.json") +
                            ": view 1 camera_to_world: not a rigid transform",
                        0),
            0u)
      << r.out;
  test::writeText(dir.file("ok.json"),
                  R"([{"camera_to_world": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}])");
  r = run("simulate " + part + " --views " + dir.file("ok.json") + " --scanner nonesuch");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("unknown scanner preset"), std::string::npos) << r.out;
  EXPECT_EQ(run("simulate " + part).code, 1);  // --views is required
}

TEST(Cli, SampleGdtFromFileWritesPlyAndJson) {
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"),
                  "gdt: from-file\ntasks:\n  - {type: gdt}\n  - {type: global}\n");
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  CommandResult r =
      run("sample " + part + " --spec " + dir.file("spec.yaml") + " --out " + dir.file("s.ply"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("task gdt"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("task global"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("clusters  "), std::string::npos) << r.out;
  const PlyData samples = readPly(dir.file("s.ply"));
  ASSERT_NE(samples.find("vertex"), nullptr);
  EXPECT_GT(samples.find("vertex")->count, 0u);
  EXPECT_NE(samples.find("vertex")->find("cluster"), nullptr);
  r = run("sample -q " + part + " -o " + dir.file("s.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(dir.file("s.json"));
  std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"cluster\""), std::string::npos);
  EXPECT_EQ(run("sample " + part + " --out " + dir.file("s.txt")).code, 4);  // unsupported output
  r = run("sample -q " + part + " --cvm " + dir.file("cvm"));
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream pgm(dir.file("cvm/cluster_0.pgm"), std::ios::binary);
  std::string magic;
  pgm >> magic;
  EXPECT_EQ(magic, "P5");
}

TEST(Cli, SampleSpecErrorsAreExitCodeTwo) {
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"), "tasks:\n  - {type: trim, faces: [42]}\n");
  CommandResult r = run("sample " + test::testData("nist_ftc_11_asme1_ap242-e1.stp") + " --spec " +
                        dir.file("spec.yaml"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("error: " + dir.file("spec.yaml") + ": unknown face id 42"),
            std::string::npos)
      << r.out;
}

// What import warns of (an open mesh, a part a fraction of a millimetre across) reaches
// the commands that plan and sample, for the part and for fixture models, not `info` only.
TEST(Cli, ImportWarningsOfThePartAndItsFixturesReachTheCommands) {
  test::TempDir dir;
  // An open square, 0.5 mm wide: two warnings.
  test::writeText(dir.file("square.off"),
                  "OFF\n4 2 0\n0 0 0\n0.5 0 0\n0.5 0.5 0\n0 0.5 0\n3 0 1 2\n3 0 2 3\n");
  test::writeText(dir.file("spec.yaml"), "fixtures:\n  - file: " + dir.file("square.off") + "\n");
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  CommandResult r = run("--quiet sample " + dir.file("square.off") + " -o " + dir.file("s.ply"));
  EXPECT_NE(r.out.find("warning: " + dir.file("square.off") + ": the mesh is not closed"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("warning: " + dir.file("square.off") + ": the part is only 0.5"),
            std::string::npos)
      << r.out;
  r = run("--quiet sample " + part + " --spec " + dir.file("spec.yaml") + " -o " +
          dir.file("t.ply"));
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("warning: " + dir.file("square.off") + ": the mesh is not closed"),
            std::string::npos)
      << r.out;
  // The bundled part has nothing to warn of.
  EXPECT_EQ(r.out.find("warning: " + part), std::string::npos) << r.out;
}

// Also: a picture an earlier run left in the folder does not stay beside this run's plan.
TEST(Cli, PlanWritesPlanJsonAndSummary) {
  test::TempDir dir;
  std::filesystem::create_directory(dir.file("out"));
  test::writeText(dir.file("out/plan.png"), "an earlier run's picture");
  CommandResult r = run("plan " + test::example("parts/nist_ctc_01_asme1_ap242-e1.stp") + " -o " +
                        dir.file("out") + " --no-registration");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("views      "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("occluded_by_working_plane"), std::string::npos) << r.out;
  std::ifstream in(dir.file("out/plan.json"));
  ASSERT_TRUE(in.good());
  std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"format\": \"scanplan.plan\""), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir.file("out/report.html")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("out/plan.png")));
}

// plan.json of `path` without the seconds anything took, which are the machine's.
nlohmann::json withoutSeconds(const std::string& path) {
  std::ifstream in(path);
  nlohmann::json plan = nlohmann::json::parse(in);
  const std::function<void(nlohmann::json&)> strip = [&](nlohmann::json& node) {
    if (node.is_object()) {
      node.erase("seconds");
      node.erase("stage_seconds");
    }
    if (node.is_structured())
      for (nlohmann::json& child : node) strip(child);
  };
  strip(plan);
  return plan;
}

// The plan (registration included) is the same on one thread as on two: every limit that
// decides it is a count of work, and parallel work is gathered in order.
TEST(Cli, PlanIsTheSameOnOneThreadAndOnTwo) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  for (const char* threads : {"1", "2"}) {
    const CommandResult r = run(std::string("-q -j ") + threads + " plan " + part + " -o " +
                                dir.file(threads) + " --no-report");
    ASSERT_EQ(r.code, 0) << r.out;
  }
  const nlohmann::json one = withoutSeconds(dir.file("1/plan.json"));
  EXPECT_GT(one["views"].size(), 1u);
  EXPECT_EQ(one, withoutSeconds(dir.file("2/plan.json")));
}

// A run ended by SIGHUP (its terminal closed) leaves no temporary, as one ended by SIGINT
// or SIGTERM does: the shell waits for the export's temporary, then hangs the run up.
TEST(Cli, RunEndedByAHangupLeavesNoTemporary) {
  test::TempDir dir;
  const std::string script =
      std::string(SCANPLAN_EXE) + " export " + test::examplePlan() +
      " --format clouds-ply --spacing 0.5 -o clouds.ply -q & pid=$!; "
      "for i in $(seq 1 400); do ls | grep -q 'clouds.tmp-' && break; sleep 0.025; done; "
      "ls; kill -HUP $pid; wait $pid; echo \"status $?\"; ls";
  CommandResult r = run("--version >/dev/null; " + script, dir.file(""));
  const std::size_t seen = r.out.find("clouds.tmp-");
  ASSERT_NE(seen, std::string::npos) << r.out;
  EXPECT_NE(r.out.find("status 129", seen), std::string::npos) << r.out;  // 128 + SIGHUP
  EXPECT_EQ(r.out.find("clouds", r.out.find("status 129")), std::string::npos) << r.out;
}

// The files a spec names are inputs too: an export or a plan that would write over the
// spec's control points or markers is refused (exit 4), and they are left as they were.
TEST(Cli, OutputsNeverReplaceFilesTheSpecNames) {
  test::TempDir dir;
  std::filesystem::create_directory(dir.file("out"));
  test::writeText(dir.file("points.csv"), "0,0,0\n");
  test::writeText(dir.file("out/proposed-markers.csv"), "1,2,3\n");
  test::writeText(dir.file("points.yaml"), "tasks:\n  - {type: points, file: points.csv}\n");
  test::writeText(dir.file("markers.yaml"), "markers: out/proposed-markers.csv\n");
  CommandResult r = run("export " + test::examplePlan() + " --spec " + dir.file("points.yaml") +
                        " --format csv -o " + dir.file("points.csv"));
  EXPECT_EQ(r.code, 4) << r.out;
  EXPECT_NE(r.out.find("error: " + dir.file("points.csv") + ": is an input of this command"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(test::readText(dir.file("points.csv")), "0,0,0\n");
  r = run("plan " + test::testData("nist_ftc_11_asme1_ap242-e1.stp") + " --spec " +
          dir.file("markers.yaml") + " -o " + dir.file("out") + " -q");
  EXPECT_EQ(r.code, 4) << r.out;
  EXPECT_NE(r.out.find("proposed-markers.csv: is an input of this command"), std::string::npos)
      << r.out;
  EXPECT_EQ(test::readText(dir.file("out/proposed-markers.csv")), "1,2,3\n");
}

// The bundled example as `scanplan plan` planned it once for the test run (support.h).
TEST(Cli, PlanReportsRegistrationAndVerifyChecksItAgain) {
  test::TempDir dir;
  const std::string part = test::example("parts/nist_ctc_01_asme1_ap242-e1.stp");
  const std::string spec = test::example("specs/ctc01.yaml");
  const std::string plan = test::examplePlan();
  std::ifstream in(test::examplePlan("summary.txt"));
  const std::string summary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* row : {"model faces", "fixture faces", "target samples", "measured samples",
                          "views registered", "bridging views added", "path length"})
    EXPECT_NE(summary.find(row), std::string::npos) << row << "\n" << summary;
  // Unregistrable views are numbered as the report and the programs number them: their
  // place in the sequence, with their id beside.
  const Plan planned = readPlan(plan);
  const std::size_t line = summary.find("unregistrable views");
  ASSERT_NE(line, std::string::npos) << summary;
  const std::string listed = summary.substr(line, summary.find('\n', line) - line);
  const std::regex entry(R"((\d+) \(id (\d+)\))");
  std::size_t entries = 0;
  for (auto it = std::sregex_iterator(listed.begin(), listed.end(), entry);
       it != std::sregex_iterator(); ++it, ++entries) {
    const std::size_t place = std::stoul((*it)[1]);
    ASSERT_TRUE(planned.sequence && place >= 1 && place <= planned.sequence->views.size());
    EXPECT_EQ(planned.sequence->views[place - 1], std::stoi((*it)[2])) << listed;
  }
  EXPECT_GT(entries, 0u) << listed;

  // The results row as the method's authors table theirs, the plan's own figures.
  const std::size_t header = summary.find("alignable views\n");
  ASSERT_NE(header, std::string::npos) << summary;
  std::istringstream row(summary.substr(header + 16));
  std::size_t model = 0, fixture = 0, targets = 0, acquired = 0, views = 0, alignable = 0;
  std::string share;
  row >> model >> fixture >> targets >> acquired >> share >> views >> alignable;
  EXPECT_EQ(model, 117u);
  EXPECT_EQ(fixture, 0u);
  EXPECT_EQ(targets, planned.samples.size());
  EXPECT_EQ(acquired, planned.measuredCount());
  EXPECT_EQ(views, planned.views.size());
  ASSERT_TRUE(planned.registration);
  EXPECT_EQ(alignable, planned.registration->registered());

  // Views of the example register to nothing: the plan holds as planned, but fails.
  CommandResult r = run("verify " + plan + " " + part + " --spec " + spec + " -q");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("coverage check         as planned"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("registration check     as planned"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("each after one it registers to"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("views register to nothing"), std::string::npos) << r.out;

  // The plan checked against another part, a broken plan, a missing one.
  r = run("verify " + plan + " " + test::testData("nist_ftc_11_asme1_ap242-e1.stp") + " -q");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("faces where the plan's part has 117"), std::string::npos) << r.out;
  r = run("export " + plan + " " + test::testData("nist_ftc_11_asme1_ap242-e1.stp") +
          " --format csv -o " + dir.file("views.csv") + " -q");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("faces where the plan's part has 117"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("views.csv")));
  test::writeText(dir.file("broken.json"),
                  "{\"format\": \"scanplan.plan\", \"version\": 1, \"units\": \"mm\", "
                  "\"views\": []}");
  r = run("verify " + dir.file("broken.json") + " " + part + " -q");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("error: " + dir.file("broken.json") + ": part: no 'file'"),
            std::string::npos)
      << r.out;
  r = run("verify " + dir.file("none.json") + " " + part + " -q");
  EXPECT_EQ(r.code, 2) << r.out;
}

// verify fails a plan with a view that registers to nothing, unless the plan does not
// require registration or was made without it; the robot registers every view when its
// accuracy is within the tolerance.
TEST(Cli, VerifyFailsUnregisteredViewsUnlessThePlanSaysOtherwise) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  auto planAndVerify = [&](const std::string& name, const std::string& spec,
                           const std::string& flags) {
    test::writeText(dir.file(name + ".yaml"), spec + "tasks:\n  - {type: global}\n");
    const std::string out = dir.file(name);
    CommandResult r = run("plan " + part + " --spec " + dir.file(name + ".yaml") + " -o " + out +
                          " --no-report -q " + flags);
    EXPECT_EQ(r.code, 0) << r.out;
    return std::pair{r, run("verify " + out + "/plan.json " + part + " -q")};
  };
  auto [plan, verify] = planAndVerify("geometry", "", "");
  ASSERT_NE(plan.out.find("by geometry"), std::string::npos) << plan.out;
  ASSERT_EQ(plan.out.find("views registered       4"), std::string::npos) << plan.out;
  EXPECT_EQ(verify.code, 3) << verify.out;
  EXPECT_NE(verify.out.find("views register to nothing"), std::string::npos) << verify.out;

  std::tie(plan, verify) = planAndVerify("optional", "registration: {required: false}\n", "");
  EXPECT_EQ(verify.code, 0) << verify.out;
  EXPECT_NE(verify.out.find("(the plan does not require registration)"), std::string::npos)
      << verify.out;

  std::tie(plan, verify) = planAndVerify("none", "", "--no-registration");
  EXPECT_EQ(verify.code, 0) << verify.out;
  EXPECT_NE(verify.out.find("none: planned without registration"), std::string::npos) << verify.out;

  std::tie(plan, verify) =
      planAndVerify("robot", "registration: {method: robot, robot_accuracy: 0.05}\n", "");
  EXPECT_NE(plan.out.find("views registered       4 (100.0%), by robot"), std::string::npos)
      << plan.out;
  EXPECT_EQ(verify.code, 0) << verify.out;
}

// Views registered by ICP before every view they register to in `plan`'s sequence (the
// pairs' own flags: shared markers or a passed ICP).
std::size_t icpViewsAheadOfTheirLinks(const Plan& plan) {
  std::map<int, std::size_t> place;
  for (std::size_t k = 0; k < plan.sequence->views.size(); ++k) place[plan.sequence->views[k]] = k;
  std::size_t ahead = 0;
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    if (plan.registration->views[v].method != RegistrationMethod::Icp) continue;
    const int id = plan.views[v].id;
    bool follows = false;
    for (const PairCheck& pair : plan.registration->pairs)
      if ((pair.a == id || pair.b == id) && (pair.markers || (pair.icp && pair.icp->passed)))
        follows = follows || place[pair.a == id ? pair.b : pair.a] < place[id];
    ahead += !follows;
  }
  return ahead;
}

// CTC 03's GD&T registered by its geometry (9 views by ICP), its scans aligned as they are
// taken and once all are taken: the same views; aligned once all are taken, views registered
// by ICP come before every view they register to where that shortens the motion, plan.json
// says so, and verify walks the sequence by it.
TEST(Cli, ScansAlignedOnceAllAreTakenComeInAShorterOrder) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ctc_03_asme1_ap242-e2.stp");
  auto planned = [&](const std::string& aligned) {
    const std::string spec = dir.file(aligned + ".yaml"), out = dir.file(aligned);
    test::writeText(spec,
                    "gdt: from-file\ntasks:\n  - {type: gdt}\nregistration: {aligned_as_taken: " +
                        aligned + "}\n");
    const CommandResult r =
        run("plan " + part + " --spec " + spec + " -o " + out + " --no-report -q");
    EXPECT_EQ(r.code, 0) << r.out;
    return readPlan(out + "/plan.json");
  };
  const Plan taken = planned("true"), after = planned("false");
  ASSERT_EQ(taken.views.size(), after.views.size());
  for (std::size_t v = 0; v < taken.views.size(); ++v)
    EXPECT_TRUE(taken.views[v].camera_to_world.isApprox(after.views[v].camera_to_world)) << v;
  ASSERT_TRUE(taken.registration && after.registration && taken.cycle && after.cycle &&
              taken.sequence && after.sequence);
  EXPECT_TRUE(taken.registration->aligned_as_taken);
  EXPECT_FALSE(after.registration->aligned_as_taken);
  EXPECT_EQ(icpViewsAheadOfTheirLinks(taken), 0u);
  EXPECT_GT(icpViewsAheadOfTheirLinks(after), 0u);
  EXPECT_LT(after.cycle->motion, taken.cycle->motion);
  const CommandResult verify = run("verify " + dir.file("false") + "/plan.json " + part + " -q");
  EXPECT_NE(verify.out.find("each after one it registers to (those registered by ICP in any order"),
            std::string::npos)
      << verify.out;
}

// Views of FTC 11's GD&T faces that its geometry cannot register: the plan proposes markers
// as a CSV that `markers:` reads, and with --place-markers plans again with them.
TEST(Cli, PlaceMarkersPlansAgainWithTheProposedOnes) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  test::writeText(dir.file("gdt.yaml"), "gdt: from-file\ntasks:\n  - {type: gdt}\n");
  CommandResult r = run("plan " + part + " --spec " + dir.file("gdt.yaml") + " -o " +
                        dir.file("out") + " --no-report -q --place-markers");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::vector<Marker> proposed = readMarkers(dir.file("out/proposed-markers.csv"));
  EXPECT_GT(proposed.size(), 2u);
  EXPECT_NE(r.out.find("(placed: the plan above uses them)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("%), by markers"), std::string::npos) << r.out;
  const Plan plan = readPlan(dir.file("out/plan.json"));
  ASSERT_EQ(plan.markers.size(), proposed.size());
  for (std::size_t k = 0; k < proposed.size(); ++k)
    EXPECT_LT((plan.markers[k].position - proposed[k].position).norm(), 1e-6);
  // A spec registering by geometry: the plan registers by the markers placed, and verify
  // checks it so, given the spec or taking the plan's.
  test::writeText(dir.file("geometry.yaml"),
                  "registration: {method: geometry}\ntasks: [{type: global}]\n");
  r = run("plan " + part + " --spec " + dir.file("geometry.yaml") + " -o " + dir.file("geo") +
          " --no-report -q --place-markers");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_PRED2(test::contains, r.out, "%), by markers");
  for (const std::string& spec : {std::string(), " --spec " + dir.file("geometry.yaml")}) {
    r = run("verify " + dir.file("geo/plan.json") + " -q" + spec);
    EXPECT_EQ(r.code, 0) << spec << "\n" << r.out;
    EXPECT_PRED2(test::contains, r.out, "registration check     as planned\n");
  }
}

// inspect: every characteristic of the plan in inspection.json beside it, a value per run
// and the precision of its U + |bias|, or the reason it has none; a deviations file at
// fault, or a precision out of range, is refused with its name and the entry, nothing
// written.
TEST(Cli, InspectWritesEveryCharacteristicAndRefusesBadDeviations) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  CommandResult r =
      run("plan " + part + " -o " + dir.file("out") + " --no-report --no-registration -q");
  ASSERT_EQ(r.code, 0) << r.out;
  r = run("inspect " + dir.file("out/plan.json") + " " + part + " --runs 3 -q");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("3 runs"), std::string::npos) << r.out;
  std::ifstream in(dir.file("out/inspection.json"));
  const nlohmann::json inspection = nlohmann::json::parse(in);
  const Plan plan = readPlan(dir.file("out/plan.json"));
  ASSERT_EQ(inspection["characteristics"].size(), plan.characteristics.size());
  std::size_t evaluated = 0;
  for (const nlohmann::json& c : inspection["characteristics"]) {
    if (c["evaluated"]) {
      ++evaluated;
      EXPECT_EQ(c["values"].size(), 3u) << c.dump();
      EXPECT_GE(c["precision"].get<double>(), 0) << c.dump();
      EXPECT_GE(c["error_95"].get<double>(), 0) << c.dump();
    } else {
      EXPECT_FALSE(c["not_evaluated"].get<std::string>().empty()) << c.dump();
    }
  }
  EXPECT_GT(evaluated, 0u);
  // The report shows it; an inspection file at fault is refused, naming it.
  r = run("report " + dir.file("out/plan.json") + " " + part + " -q");
  EXPECT_EQ(r.code, 0) << r.out;
  test::writeText(
      dir.file("broken.json"),
      R"({"runs": 3, "spacing": 2, "characteristics": [{"id": 999, "evaluated": false}]})");
  r = run("report " + dir.file("out/plan.json") + " " + part + " -q -o " + dir.file("r.html") +
          " --inspection " + dir.file("broken.json"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("broken.json: characteristic 1: the plan has no characteristic 999"),
            std::string::npos)
      << r.out;
  const auto refused = [&](const std::string& text, const std::string& says) {
    test::writeText(dir.file("deviations.yaml"), text);
    const CommandResult bad =
        run("inspect " + dir.file("out/plan.json") + " " + part + " --runs 2 -q -o " +
            dir.file("bad.json") + " --deviations " + dir.file("deviations.yaml"));
    EXPECT_EQ(bad.code, 2) << bad.out;
    EXPECT_NE(bad.out.find(says), std::string::npos) << bad.out;
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.json")));
  };
  // A precision the runs allowed cannot reach: they stop at --runs, and name the
  // characteristics whose U + |bias| they know less well than asked.
  r = run("inspect " + dir.file("out/plan.json") + " " + part +
          " --precision 0.01 --runs 20 -q -o " + dir.file("short.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("20 runs (until each U + |bias| is known within 1 %; the runs ran out "
                       "first for "),
            std::string::npos)
      << r.out;
  const nlohmann::json short_of = nlohmann::json::parse(std::ifstream(dir.file("short.json")));
  std::vector<int> imprecise;
  for (const nlohmann::json& c : short_of["characteristics"])
    if (c["evaluated"] && c["precision"].get<double>() > 0.01 * (c["uncertainty"].get<double>() +
                                                                 std::abs(c["bias"].get<double>())))
      imprecise.push_back(c["id"].get<int>());
  EXPECT_FALSE(imprecise.empty());
  EXPECT_EQ(short_of["imprecise"].get<std::vector<int>>(), imprecise);
  // A precision that is no share of U + |bias|.
  r = run("inspect " + dir.file("out/plan.json") + " " + part + " --precision 1.5 -q -o " +
          dir.file("bad.json"));
  EXPECT_EQ(r.code, 1) << r.out;  // a usage error
  EXPECT_NE(r.out.find("--precision: Value 1.5 not in range"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.json")));
  refused("deviations:\n  - {faces: [1], twist: 0.1}\n", "deviation 1: unknown key 'twist'");
  refused("deviations:\n  - {faces: [100000], offset: 0.1}\n", "has no face 100000");
  refused("deviations:\n  - {faces: [1], offset: 0.1, bow: 0.2}\n", "exactly one of");
  refused("deviations:\n  - {faces: [1], offset: .nan}\n", "within [-100, 100]");
  refused("nothing: here\n", "no 'deviations:' list");
  const CommandResult missing = run("inspect " + dir.file("out/plan.json") + " " + part +
                                    " -q --deviations " + dir.file("none.yaml"));
  EXPECT_EQ(missing.code, 2) << missing.out;
  EXPECT_NE(missing.out.find("none.yaml"), std::string::npos) << missing.out;
}

// inspect --icp registered: the bundled example's views registered by ICP are registered
// by ICP in each run, and the terminal says how many; it prints the table and nothing else
// (a line per characteristic, the plan, part, inspection and ICP lines, the header, what
// its ± means, the file written). An --icp it does not know is refused, naming the option.
TEST(Cli, InspectRegistersTheIcpLinksInEachRunAndSaysSo) {
  test::TempDir dir;
  const std::string part = test::example("parts/nist_ctc_01_asme1_ap242-e1.stp");
  const std::string inspect = "inspect " + test::examplePlan() + " " + part + " --spec " +
                              test::example("specs/ctc01.yaml") + " --runs 2 -q -o " +
                              dir.file("inspection.json") + " --icp ";
  const CommandResult r = run(inspect + "registered");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("views registered by ICP in every run"), std::string::npos) << r.out;
  const nlohmann::json inspection =
      nlohmann::json::parse(std::ifstream(dir.file("inspection.json")));
  EXPECT_GT(inspection.at("icp_registered").get<std::size_t>(), 0u);
  const std::size_t lines = static_cast<std::size_t>(std::count(r.out.begin(), r.out.end(), '\n'));
  EXPECT_EQ(lines, inspection.at("characteristics").size() + 8) << r.out;
  const CommandResult bad = run(inspect + "sideways");
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.out.find("--icp"), std::string::npos) << bad.out;
}

// FTC 11 planned on both its faces (rest: all) has two setups that nothing joins: its
// profile to A | B lies on the bottom face, datum B (the bore) is measured from the top.
// The inspection says so rather than fitting datums across frames; the flatness of the top
// face (datum A), seen in one frame, is measured.
TEST(Cli, InspectNamesCharacteristicsSplitOverSetupsNotJoined) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  test::writeText(dir.file("spec.yaml"),
                  "gdt: from-file\npart: {rest: all}\ntasks:\n  - {type: gdt}\n");
  CommandResult r = run("plan " + part + " --spec " + dir.file("spec.yaml") + " -o " +
                        dir.file("out") + " --no-report -q");
  ASSERT_EQ(r.code, 0) << r.out;
  r = run("inspect " + dir.file("out/plan.json") + " " + part + " --spec " + dir.file("spec.yaml") +
          " --runs 2 -q");
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(dir.file("out/inspection.json"));
  const nlohmann::json inspection = nlohmann::json::parse(in);
  std::map<std::string, nlohmann::json> by_kind;
  for (const nlohmann::json& c : inspection["characteristics"]) by_kind[c["kind"]] = c;
  ASSERT_TRUE(by_kind.count("profile_of_surface") && by_kind.count("flatness"));
  EXPECT_FALSE(by_kind["profile_of_surface"]["evaluated"]);
  EXPECT_NE(
      by_kind["profile_of_surface"]["not_evaluated"].get<std::string>().find("setups not joined"),
      std::string::npos)
      << by_kind["profile_of_surface"].dump();
  EXPECT_TRUE(by_kind["flatness"]["evaluated"]) << by_kind["flatness"].dump();
}

TEST(Cli, VerifyFailsAPlanThatDoesNotHold) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  CommandResult r = run("plan " + part + " -o " + dir.file("out") + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  // Claim that the first sample some view measures is measured by none.
  std::ifstream in(dir.file("out/plan.json"));
  nlohmann::json plan = nlohmann::json::parse(in);
  auto measured = std::find_if(plan["samples"].begin(), plan["samples"].end(),
                               [](const nlohmann::json& s) { return !s["measured_by"].empty(); });
  ASSERT_NE(measured, plan["samples"].end());
  (*measured)["measured_by"] = nlohmann::json::array();
  test::writeText(dir.file("tampered.json"), plan.dump());
  r = run("verify " + dir.file("tampered.json") + " " + part + " -q");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("1 samples measured otherwise than planned"), std::string::npos) << r.out;
  // The plan is an input: exporting over it is refused, and it is left as it was.
  r = run("export " + dir.file("tampered.json") + " --format csv -o " + dir.file("tampered.json"));
  EXPECT_EQ(r.code, 4) << r.out;
  EXPECT_NE(r.out.find("is an input of this command"), std::string::npos) << r.out;
  EXPECT_NO_THROW(readPlan(dir.file("tampered.json")));
  // A view the plan does not have is an error in the plan, named as such.
  (*measured)["measured_by"] = {999};
  test::writeText(dir.file("broken.json"), plan.dump());
  r = run("verify " + dir.file("broken.json") + " " + part + " -q");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("broken.json"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("refers to view 999, which the plan does not have"), std::string::npos)
      << r.out;
}

// A part changed since its plan was made, with the same faces, is not the plan's: FTC 11
// with its 32 mm bore 0.1 mm larger in the file (the samples on the bore lie off it), and a
// box mesh made 0.5 mm taller (those on its top). Every command that reads the plan against
// a part refuses it, naming the file, and writes nothing; the part as planned verifies.
TEST(Cli, APartChangedSinceThePlanWasMadeIsRefused) {
  test::TempDir dir;
  std::ifstream in(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  std::string step((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  test::writeText(dir.file("ftc11.stp"), step);
  const std::string bore = "CYLINDRICAL_SURFACE('',#739,16.);";
  ASSERT_NE(step.find(bore), std::string::npos);
  step.replace(step.find(bore), bore.size(), "CYLINDRICAL_SURFACE('',#739,16.05);");
  test::writeText(dir.file("ftc11-changed.stp"), step);
  auto box = [](double height) {
    std::string off = "OFF\n8 12 0\n";
    for (int k = 0; k < 8; ++k)
      off += fmt::format("{} {} {}\n", k & 1 ? 100 : 0, k & 2 ? 60 : 0, k & 4 ? height : 0);
    return off +
           "3 0 2 1\n3 1 2 3\n3 4 5 6\n3 5 7 6\n3 0 1 4\n3 1 5 4\n3 2 6 3\n3 3 6 7\n"
           "3 0 4 2\n3 2 4 6\n3 1 3 5\n3 3 7 5\n";
  };
  test::writeText(dir.file("box.off"), box(40));
  test::writeText(dir.file("box-changed.off"), box(40.5));
  // The face changed: the bore, a cylinder of radius 16; the box's top.
  auto changedFace = [](const Part& part) {
    for (const Face& face : part.faces) {
      const auto surface = elementarySurface(part, face.id);
      if ((surface && surface->type == SurfaceType::Cylinder &&
           std::abs(surface->radius - 16) < 1e-9) ||
          (part.format == "OFF" && face.bounds.min.z() > 39.9))
        return face.id;
    }
    return 0;
  };
  for (const std::string& file : {std::string("ftc11.stp"), std::string("box.off")}) {
    const std::string name = file.substr(0, file.find('.'));
    const std::string plan = dir.file(name + "/plan.json");
    CommandResult r = run("plan " + dir.file(file) + " -o " + dir.file(name) +
                          " --no-report --no-registration -q");
    ASSERT_EQ(r.code, 0) << r.out;
    r = run("verify " + plan + " -q");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("part check             every sample on its face"), std::string::npos)
        << r.out;
    const int face = changedFace(importPart(dir.file(file)));
    ASSERT_GT(face, 0) << file;
    const Plan planned = readPlan(plan);
    const auto on_face =
        std::count_if(planned.samples.begin(), planned.samples.end(),
                      [&](const PlannedSample& s) { return s.sample.face == face; });
    ASSERT_GT(on_face, 0) << file;
    const std::string changed = dir.file(name + "-changed" + file.substr(file.find('.')));
    const std::string refused = fmt::format(
        "error: {}: {} of the plan's {} samples lie off their "
        "faces on it",
        changed, on_face, planned.samples.size());
    for (const std::string& command :
         {"verify " + plan, "inspect " + plan + " -o " + dir.file("i.json"),
          "report " + plan + " -o " + dir.file("report.html"),
          "export " + plan + " --format glb -o " + dir.file("v.glb")}) {
      r = run(command + " " + changed + " -q");
      EXPECT_EQ(r.code, 2) << command << "\n" << r.out;
      EXPECT_NE(r.out.find(refused), std::string::npos) << command << "\n" << r.out;
      EXPECT_NE(r.out.find("not the part the plan was made for"), std::string::npos) << r.out;
    }
    for (const char* written : {"i.json", "report.html", "v.glb"})
      EXPECT_FALSE(std::filesystem::exists(dir.file(written))) << written;
  }
}

// A plan holds the spec it was made with, and the commands reading it take that one when
// given none: FTC 11 planned with markers on the part, whose disks hide the surface under
// them, verifies as planned without --spec, also once the spec file is rewritten or gone;
// checked with a spec without those markers, samples under them count as measured.
TEST(Cli, CommandsGivenNoSpecTakeTheOneThePlanWasMadeWith) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  const std::string spec = dir.file("spec.yaml");
  test::writeText(spec, "markers: {grid: 10, on: both}\ntasks: [{type: global}]\n");
  const std::string plan = dir.file("out/plan.json");
  CommandResult r =
      run("-q plan " + part + " --spec " + spec + " -o " + dir.file("out") + " --no-report");
  ASSERT_EQ(r.code, 0) << r.out;
  test::writeText(dir.file("unmarked.yaml"), "tasks: [{type: global}]\n");
  r = run("-q verify " + plan + " " + part + " --spec " + dir.file("unmarked.yaml"));
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_PRED2(test::contains, r.out, "samples measured otherwise than planned");
  // simulate too: each view measures as with the spec given, not as without its markers.
  const std::string simulate = "-q simulate --json " + part + " --views " + plan;
  const CommandResult own = run(simulate), given = run(simulate + " --spec " + spec),
                      unmarked = run(simulate + " --spec " + dir.file("unmarked.yaml"));
  ASSERT_EQ(own.code, 0) << own.out;
  EXPECT_EQ(own.out, given.out);
  EXPECT_NE(own.out, unmarked.out);
  const std::string absolute = std::filesystem::absolute(spec).lexically_normal().string();
  const std::string source = "spec                   " + absolute + " (the plan's)\n";
  // Planned in every rest (--rest over the spec's), with markers on each rest's upward
  // faces: checked so, where the spec's own rest puts them on the first rest's only.
  r = run("-q plan " + part + " --spec " + spec + " --rest all -o " + dir.file("every") +
          " --no-report");
  ASSERT_EQ(r.code, 0) << r.out;
  r = run("-q verify " + dir.file("every/plan.json") + " " + part);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_PRED2(test::contains, r.out, "spec                   " + absolute + ", resting all");
  EXPECT_PRED2(test::contains, r.out, "coverage check         as planned\n");
  r = run("-q verify " + dir.file("every/plan.json") + " " + part + " --spec " + spec);
  EXPECT_PRED2(test::contains, r.out, "samples measured otherwise than planned");
  for (const std::string change : {"as it was", "rewritten", "removed"}) {
    if (change == "rewritten") test::writeText(spec, "tasks: [{type: global}]\n");
    if (change == "removed") std::filesystem::remove(spec);
    r = run("-q verify " + plan + " " + part);
    EXPECT_EQ(r.code, 0) << change << "\n" << r.out;
    EXPECT_PRED2(test::contains, r.out, "coverage check         as planned\n");
    EXPECT_PRED2(test::contains, r.out, source);
  }
  // The spec's file as the plan names it is printed without its control bytes.
  nlohmann::json broken = nlohmann::json::parse(test::readText(plan));
  broken["spec"]["file"] = "/tmp/\x1b[2Jspec.yaml";
  test::writeText(plan, broken.dump());
  r = run("-q verify " + plan + " " + part);
  EXPECT_PRED2(test::contains, r.out, "/tmp/?[2Jspec.yaml (the plan's)\n");
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos);
  // A plan's spec that no longer reads is named as the plan's.
  broken["spec"]["rest"] = "sideways";
  test::writeText(plan, broken.dump());
  r = run("-q verify " + plan + " " + part);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_PRED2(test::contains, r.out,
               "error: " + plan + ": spec.rest: expected auto, all, drawn or a face id");
  broken["spec"]["text"] = "tasks: [";
  test::writeText(plan, broken.dump());
  r = run("-q verify " + plan + " " + part);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_PRED2(test::contains, r.out, "error: " + plan + ": the spec it was made with, ");
}

// verify catches each way a plan can lie about its registration and its sequence, and a
// view moved after planning: on a plan that holds (exit 0), each tampering alone fails it
// (exit 3) and is named.
TEST(Cli, VerifyCatchesAFalseLinkABrokenSequenceAndAMovedView) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  test::writeText(dir.file("spec.yaml"),
                  "markers: {grid: 40, on: plate}\nregistration: {required: false}\n");
  const std::string spec = dir.file("spec.yaml");
  CommandResult r =
      run("plan " + part + " --spec " + spec + " -o " + dir.file("out") + " --no-report -q");
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(dir.file("out/plan.json"));
  const nlohmann::json planned = nlohmann::json::parse(in);
  auto verify = [&](const nlohmann::json& plan) {
    test::writeText(dir.file("tampered.json"), plan.dump());
    return run("verify " + dir.file("tampered.json") + " " + part + " --spec " + spec + " -q");
  };
  r = verify(planned);
  ASSERT_EQ(r.code, 0) << r.out;

  // A view registered to one with which it forms no registrable pair (the plan's own
  // pairs say which: neither enough markers shared nor a stable overlap).
  nlohmann::json lying = planned;
  const nlohmann::json& pairs = planned["registration"]["pairs"];
  std::map<std::pair<int, int>, bool> registrable;
  for (const nlohmann::json& p : pairs)
    registrable[{p["views"][0].get<int>(), p["views"][1].get<int>()}] = p["registrable"];
  bool tampered = false;
  for (nlohmann::json& view : lying["views"]) {
    const int id = view["id"];
    for (const nlohmann::json& other : planned["views"]) {
      const int to = other["id"];
      const auto found = registrable.find({std::min(id, to), std::max(id, to)});
      if (tampered || to == id || (found != registrable.end() && found->second) ||
          view["registration"]["method"] != "markers")
        continue;
      view["registration"]["to"] = to;
      tampered = true;
    }
  }
  ASSERT_TRUE(tampered) << "every pair of views registers: no false link to claim";
  r = verify(lying);
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("1 views registered otherwise than planned"), std::string::npos) << r.out;

  // The sequence with a view left out, and with one visited twice.
  nlohmann::json missing = planned;
  missing["sequence"].erase(missing["sequence"].size() - 1);
  r = verify(missing);
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("1 views missing or repeated"), std::string::npos) << r.out;
  nlohmann::json repeated = planned;
  repeated["sequence"].push_back(repeated["sequence"][0]);
  r = verify(repeated);
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("1 views missing or repeated"), std::string::npos) << r.out;

  // A view moved 2 m away measures none of what the plan says it measures.
  nlohmann::json moved = planned;
  nlohmann::json& pose = moved["views"][0]["camera_to_world"];
  pose[0][3] = pose[0][3].get<double>() + 2000;
  r = verify(moved);
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("samples measured otherwise than planned"), std::string::npos) << r.out;
}

// A part with nothing measurable: the plan is written, with no views and the reason per
// sample, and fails (exit 3); every command reads it, and verify fails it too.
TEST(Cli, APlanWithNoViewsIsWrittenAndFails) {
  test::TempDir dir;
  test::writeText(dir.file("down.off"),
                  "OFF\n4 2 0\n0 0 0\n100 0 0\n100 100 0\n0 100 0\n3 0 2 1\n3 0 3 2\n");
  CommandResult r = run("plan " + dir.file("down.off") + " -o " + dir.file("out") + " -q");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("no sample of the spec's tasks can be measured"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("occluded_by_working_plane"), std::string::npos) << r.out;
  const std::string plan = dir.file("out/plan.json");
  EXPECT_TRUE(readPlan(plan).views.empty());
  r = run("verify " + plan + " " + dir.file("down.off") + " -q");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("nothing: no view measures a sample"), std::string::npos) << r.out;
  EXPECT_EQ(run("report " + plan + " -q").code, 0);
  EXPECT_EQ(run("export " + plan + " --format glb -o " + dir.file("plan.glb") + " -q").code, 0);
  EXPECT_EQ(run("export " + plan + " --format csv -o " + dir.file("views.csv") + " -q").code, 0);
}

// A run that fails on its inputs leaves no output folder behind.
// An empty spec file name is refused, not read as no spec given.
TEST(Cli, AnEmptySpecFileNameIsRefused) {
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  for (const std::string& command : {"plan " + part, "sample " + part, "spec " + part}) {
    const CommandResult r = run(command + " --spec '' -q");
    EXPECT_EQ(r.code, 1) << command << "\n" << r.out;
    EXPECT_NE(r.out.find("--spec"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("the file name is empty"), std::string::npos) << r.out;
  }
}

TEST(Cli, AFailedPlanLeavesNoFolder) {
  test::TempDir dir;
  CommandResult r = run("plan " + dir.file("missing.stp") + " -o " + dir.file("out") + " -q");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("out")));
}

TEST(Cli, SurfacePlanOverEveryRestOrientationWritesPatchesAndVerifies) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  test::writeText(dir.file("spec.yaml"),
                  "part: {rest: all}\nregistration: {required: false}\n"
                  "tasks:\n  - {type: surface, faces: [1, 2, 3, 4, 5, 6, 7, 8]}\n");
  CommandResult r =
      run("plan " + part + " --spec " + dir.file("spec.yaml") + " -o " + dir.file("out") + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("rest orientations      1:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("measured samples       1348 (100.0%)"), std::string::npos) << r.out;
  // The flat sets' patches are written beside the plan and read back as faces.
  ASSERT_TRUE(std::filesystem::exists(dir.file("out/patch-1.step"))) << r.out;
  r = run("info " + dir.file("out/patch-1.step") + " -q");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("BSpline"), std::string::npos) << r.out;
  r = run("verify " + dir.file("out/plan.json") + " " + part + " --spec " + dir.file("spec.yaml") +
          " -q");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("coverage check         as planned"), std::string::npos) << r.out;
}

TEST(Cli, PlanWithNothingToPlanIsExitCodeThree) {
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"), "tasks:\n  - {type: trim}\n");
  CommandResult r = run("plan " + test::testData("nist_ftc_11_asme1_ap242-e1.stp") + " --spec " +
                        dir.file("spec.yaml") + " -o " + dir.file("out"));
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("error: " + dir.file("spec.yaml") + ": task 1 (trim) has no target faces"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("out/plan.json")));
}

TEST(Cli, InfoListsRestOrientations) {
  CommandResult r = run("info --rest " + test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("rest orientations: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("   1: down ("), std::string::npos) << r.out;
}

// Every command's help reads cleanly: no option shows a default like "{false}".
TEST(Cli, HelpIsExitCodeZeroAndFreeOfArtefacts) {
  CommandResult r = run("--help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("info"), std::string::npos);
  for (const char* command :
       {"info", "plan", "sample", "simulate", "verify", "report", "export", "scanners"}) {
    r = run(std::string(command) + " --help");
    EXPECT_EQ(r.code, 0) << command;
    EXPECT_EQ(r.out.find("{false}"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("{true}"), std::string::npos) << r.out;
  }
}

// scanplan spec writes the editor; bad inputs get their exit codes and no page.
TEST(Cli, SpecWritesTheEditorAndRefusesBadInput) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  CommandResult r = run("spec -q " + part + " -o " + dir.file("editor.html"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("editor.html"), std::string::npos) << r.out;
  EXPECT_GT(std::filesystem::file_size(dir.file("editor.html")), 400000u);
  r = run("spec -q /nonexistent/part.step -o " + dir.file("none.html"));
  EXPECT_EQ(r.code, 2) << r.out;
  test::writeText(dir.file("bad.yaml"), "tasks:\n  - {type: trim, faces: [100000]}\n");
  r = run("spec -q " + part + " --spec " + dir.file("bad.yaml") + " -o " + dir.file("none.html"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("bad.yaml"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("none.html")));
  r = run("spec -q " + part + " --spec " + dir.file("bad.yaml") + " -o " + dir.file("bad.yaml"));
  EXPECT_EQ(r.code, 4) << r.out;
  r = run("spec -q " + part + " -o " + dir.file("no/such/folder/editor.html"));
  EXPECT_EQ(r.code, 4) << r.out;
}

TEST(Cli, VersionAndScannerPresets) {
  CommandResult r = run("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out, "scanplan " + std::string(version()) + "\n");
  EXPECT_EQ(version(), "0.1.0");  // as CMakeLists.txt declares it
  r = run("scanners");
  ASSERT_EQ(r.code, 0) << r.out;
  // Each preset with its standoff, depth of field and field (data/scanners/).
  EXPECT_TRUE(
      std::regex_search(r.out, std::regex(R"(generic-structured-light +400 +200 +300 x 225)")))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(laser-line +150 +100 +100 x 60)"))) << r.out;
  // One camera each, and the acquisition: 10 patterns of 0.05 s; a 60 mm stroke at 100 mm/s.
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(generic-structured-light .* 1 +0\.50\n)")))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(laser-line .* 1 +0\.60 sweep\n)"))) << r.out;
}

// plan --scanner takes a preset or a scanner file, over the spec's scanner.
TEST(Cli, PlanWithAScannerPresetOrFile) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  auto scannerOf = [&](const std::string& scanner) {
    const CommandResult r = run("plan -q " + part + " --scanner " + scanner +
                                " --no-report --no-registration -o " + dir.file("out"));
    EXPECT_EQ(r.code, 0) << r.out;
    return readPlan(dir.file("out/plan.json")).scanner;
  };
  EXPECT_EQ(scannerOf("laser-line").name, "laser-line");
  test::writeText(dir.file("head.yaml"), "preset: laser-line\nstandoff: 170\n");
  EXPECT_EQ(scannerOf(dir.file("head.yaml")).standoff, 170);
  const CommandResult unknown =
      run("plan -q " + part + " --scanner hyperscan-9000 -o " + dir.file("other"));
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.out.find("unknown scanner preset (known: generic-structured-light, "
                             "laser-line)"),
            std::string::npos)
      << unknown.out;
}

// plan.json names its part relative to itself (and absolutely beside): a plan made with a
// relative part path reports from any folder, and moves with its part.
TEST(Cli, APlanFindsItsPartFromAnyFolder) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.file("job/parts"));
  std::filesystem::copy_file(test::testData("nist_ftc_11_asme1_ap242-e1.stp"),
                             dir.file("job/parts/disc.stp"));
  CommandResult r = run("-q plan parts/disc.stp --no-report -o out", dir.file("job"));
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json plan = nlohmann::json::parse(std::ifstream(dir.file("job/out/plan.json")));
  EXPECT_EQ(plan["part"]["file"], "../parts/disc.stp");
  EXPECT_EQ(plan["part"]["absolute_file"], dir.file("job/parts/disc.stp"));
  r = run("-q report job/out/plan.json -o report.html", dir.file(""));
  EXPECT_EQ(r.code, 0) << r.out;
  std::filesystem::rename(dir.file("job"), dir.file("moved"));
  r = run("-q report " + dir.file("moved/out/plan.json") + " -o " + dir.file("moved.html"));
  EXPECT_EQ(r.code, 0) << r.out;
  // verify and inspect find it as report does, given no part.
  const std::string moved_part = "part                   " + dir.file("moved/parts/disc.stp");
  r = run("-q verify " + dir.file("moved/out/plan.json"));
  EXPECT_PRED2(test::contains, r.out, moved_part);
  EXPECT_PRED2(test::contains, r.out, "coverage check         as planned");
  r = run("-q inspect " + dir.file("moved/out/plan.json") + " --runs 2");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_PRED2(test::contains, r.out, moved_part);
  // A plan naming no part needs one given.
  nlohmann::json nameless = nlohmann::json::parse(test::readText(dir.file("moved/out/plan.json")));
  nameless["part"]["file"] = "";
  nameless["part"]["absolute_file"] = nullptr;
  test::writeText(dir.file("nameless.json"), nameless.dump());
  for (const std::string command : {"verify", "inspect", "report"}) {
    r = run("-q " + command + " " + dir.file("nameless.json"));
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_PRED2(
        test::contains, r.out,
        dir.file("nameless.json") + ": names no part file; give the part on the command line");
  }
}

}  // namespace
}  // namespace scanplan

namespace scanplan {
namespace {

TEST(Cli, PlanWritesTheReportAndExportsReadBack) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  const std::string out = dir.file("out");
  CommandResult r = run("plan " + part + " -o " + out + " --png -q");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("report     " + out + "/report.html"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(out + "/report.html"));
  EXPECT_GT(readPng(out + "/plan.png").width, 0);
  const Plan plan = readPlan(out + "/plan.json");
  // A dimension not capable is printed by its nominal value and limits, a tolerance by its
  // zone, as the report gives them.
  std::size_t dimensions = 0;
  for (std::size_t i = 0; i < plan.characteristics.size(); ++i) {
    const Characteristic& c = plan.characteristics[i];
    if (plan.capabilities[i].verdict == Verdict::Capable ||
        plan.capabilities[i].verdict == Verdict::Untoleranced)
      continue;
    dimensions += c.dimension;
    char value[96];
    if (c.dimension)
      std::snprintf(value, sizeof value, " %.3f (%.3f to %.3f) ", c.value, c.lower, c.upper);
    else
      std::snprintf(value, sizeof value, " zone %.3f ", c.value);
    std::istringstream lines(r.out);
    bool printed = false;
    for (std::string line; std::getline(lines, line);)
      printed |= line.find(" " + c.kind + " ") != std::string::npos &&
                 line.find(value) != std::string::npos;
    EXPECT_TRUE(printed) << c.kind << value << r.out;
  }
  EXPECT_GT(dimensions, 0u);

  r = run("export " + out + "/plan.json --format csv -o " + dir.file("views.csv"));
  ASSERT_EQ(r.code, 0) << r.out;
  // In the order the cell takes them: the plan's sequence.
  const std::vector<View> in_order = readViewsCsv(dir.file("views.csv"));
  ASSERT_TRUE(plan.sequence);
  ASSERT_EQ(in_order.size(), plan.sequence->views.size());
  for (std::size_t k = 0; k < in_order.size(); ++k)
    EXPECT_EQ(in_order[k].id, plan.sequence->views[k]);
  std::ifstream csv(dir.file("views.csv"));
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.substr(0, 16), "sequence,id,m00,");
  r = run("export " + out + "/plan.json " + part + " --format samples-ply -o " +
          dir.file("samples.ply") + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(readPly(dir.file("samples.ply")).find("vertex")->count, plan.samples.size());
  // Without PART: the part file the plan names.
  r = run("export " + out + "/plan.json --format clouds-ply -o " + dir.file("clouds.ply") + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  const PlyData clouds = readPly(dir.file("clouds.ply"));
  std::set<double> views(plyColumn(clouds, "vertex", "scalar_view", "clouds").begin(),
                         plyColumn(clouds, "vertex", "scalar_view", "clouds").end());
  EXPECT_EQ(views.size(), plan.views.size());
  r = run("export " + out + "/plan.json --format glb -o " + dir.file("plan.glb") + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir.file("plan.glb")));
  r = run("report " + out + "/plan.json -o " + dir.file("again.html") + " --png " +
          dir.file("again.png") + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir.file("again.html")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("again.png")));

  // Bad input: an unknown format is a usage error, a missing plan an input error; neither
  // leaves a file behind.
  r = run("export " + out + "/plan.json --format obj -o " + dir.file("x.obj"));
  EXPECT_EQ(r.code, 1) << r.out;
  r = run("export " + dir.file("missing.json") + " --format csv -o " + dir.file("x.csv"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("missing.json"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.obj")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.csv")));
}

}  // namespace
}  // namespace scanplan

namespace scanplan {
namespace {

// Exports of a part placed by a turn and a shift (the spec's rest matrix M): in the CAD
// frame (the default) the samples are where `scanplan sample` puts them on the CAD model,
// which places nothing; in the world frame they and the views are M times the CAD frame's.
TEST(Cli, ExportsInTheCadFrameLandOnTheModel) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  test::writeText(dir.file("placed.yaml"),
                  "tasks: [{type: global}]\n"
                  "part: {rest: [[0, -1, 0, 30], [1, 0, 0, -20], [0, 0, 1, 5], [0, 0, 0, 1]]}\n");
  Eigen::Matrix4d m;
  m << 0, -1, 0, 30, 1, 0, 0, -20, 0, 0, 1, 5, 0, 0, 0, 1;
  const Pose placed(m);
  const std::string spec = " --spec " + dir.file("placed.yaml");
  CommandResult r =
      run("-q plan " + part + spec + " --no-report --no-registration -o " + dir.file("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  r = run("-q sample " + part + spec + " -o " + dir.file("samples.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string plan = dir.file("out/plan.json");
  for (const std::string frame : {"", " --frame world"}) {
    r = run("export " + plan + " --format samples-ply -o " + dir.file("s.ply") + frame);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find(frame.empty() ? "cad frame" : "world frame"), std::string::npos) << r.out;
    std::filesystem::rename(dir.file("s.ply"), dir.file(frame.empty() ? "cad.ply" : "world.ply"));
  }
  const PlyData cad = readPly(dir.file("cad.ply")), world = readPly(dir.file("world.ply"));
  auto point = [](const PlyData& ply, std::size_t i) {
    return Vec3(plyColumn(ply, "vertex", "x", "ply")[i], plyColumn(ply, "vertex", "y", "ply")[i],
                plyColumn(ply, "vertex", "z", "ply")[i]);
  };
  const nlohmann::json sampled = nlohmann::json::parse(std::ifstream(dir.file("samples.json")));
  ASSERT_EQ(cad.find("vertex")->count, sampled["samples"].size());
  for (std::size_t i = 0; i < sampled["samples"].size(); ++i) {
    const auto& p = sampled["samples"][i]["position"];
    double nearest = 1e9;  // to the sampled points: the same set, in any order
    for (std::size_t j = 0; j < cad.find("vertex")->count; ++j)
      nearest = std::min(nearest, (point(cad, j) - Vec3(p[0], p[1], p[2])).norm());
    EXPECT_LT(nearest, 1e-6) << i;
    EXPECT_LT((point(world, i) - placed * point(cad, i)).norm(), 1e-6) << i;
  }
  // The views: the world frame's matrices and targets are M times the CAD frame's.
  r = run("export " + plan + " --format csv -o " + dir.file("cad.csv"));
  ASSERT_EQ(r.code, 0) << r.out;
  r = run("export " + plan + " --format csv --frame world -o " + dir.file("world.csv"));
  ASSERT_EQ(r.code, 0) << r.out;
  const std::vector<View> cad_views = readViewsCsv(dir.file("cad.csv"));
  const std::vector<View> world_views = readViewsCsv(dir.file("world.csv"));
  ASSERT_EQ(cad_views.size(), world_views.size());
  ASSERT_FALSE(cad_views.empty());
  for (std::size_t v = 0; v < cad_views.size(); ++v) {
    EXPECT_TRUE((placed * cad_views[v].camera_to_world)
                    .matrix()
                    .isApprox(world_views[v].camera_to_world.matrix(), 1e-12));
    EXPECT_LT((placed * cad_views[v].target - world_views[v].target).norm(), 1e-9);
  }
  // --frame is for files of points and poses.
  r = run("export " + plan + " --format png --frame cad -o " + dir.file("x.png"));
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("--frame"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.png")));
}

// NIST FTC 11 planned in both its rest orientations in a cell: the part is turned by hand
// between the two setups, so each is a robot program of its own (--setup). Each holds the
// views of its setup, and its scanner poses in the part's frame are the views' poses taken
// back through that setup's placement of the part (plan.json's orientations).
TEST(Cli, EachSetupOfAPartTurnedOverIsARobotProgramOfItsOwn) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  test::writeText(dir.file("spec.yaml"),
                  "part: {rest: all}\ntasks: [{type: global}]\n"
                  "cell:\n  robot: {preset: abb-irb4600-60-205, base: {position: [-1000, 0, 0]}}\n"
                  "  mount: {position: [0, 0, 150]}\n");
  const std::string spec = " --spec " + dir.file("spec.yaml") + " -q";
  const std::string plan = dir.file("out/plan.json");
  CommandResult r = run("plan " + part + spec + " -o " + dir.file("out") + " --no-report");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json planned = nlohmann::json::parse(test::readText(plan));
  const nlohmann::json& setups = planned["orientations"];
  ASSERT_EQ(setups.size(), 2u);
  auto matrix = [](const nlohmann::json& rows) {
    Eigen::Matrix4d m;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) m(i, j) = rows[i][j].get<double>();
    return m;
  };
  std::map<int, Eigen::Matrix4d> camera;  // by view id, in the world of its setup
  for (const nlohmann::json& view : planned["views"])
    camera[view["id"].get<int>()] = matrix(view["camera_to_world"]);

  r = run("export " + plan + " --format rapid -o " + dir.file("all.mod") + spec);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_PRED2(test::contains, r.out, "--setup: the plan turns the part into 2 rest orientations");
  EXPECT_FALSE(std::filesystem::exists(dir.file("all.mod")));
  for (std::size_t k = 0; k < 2; ++k) {
    const std::string file = dir.file("setup" + std::to_string(k + 1) + ".json");
    r = run("export " + plan + " --format robot-json --setup " + std::to_string(k + 1) + " -o " +
            file + spec);
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json program = nlohmann::json::parse(test::readText(file));
    EXPECT_PRED2(test::contains, program["source"].get<std::string>(),
                 "setup " + std::to_string(k + 1) + " of 2");
    const Eigen::Matrix4d to_cad = matrix(setups[k]["part_to_world"]).inverse();
    std::set<int> views;
    for (const nlohmann::json& step : program["steps"]) {
      const int id = step["view"].get<int>();
      views.insert(id);
      EXPECT_TRUE(matrix(step["scanner"]).isApprox(to_cad * camera.at(id), 1e-6))
          << "setup " << k + 1 << ", view " << id;
    }
    EXPECT_EQ(views, setups[k]["views"].get<std::set<int>>()) << "setup " << k + 1;
  }
  r = run("export " + plan + " --format rapid --setup 3 -o " + dir.file("third.mod") + spec);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_PRED2(test::contains, r.out, "--setup: the plan has 2 setups, not 3");
  r = run("export " + plan + " --format csv --setup 1 -o " + dir.file("views.csv") + spec);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_PRED2(test::contains, r.out, "--setup: applies to robot programs");
}

TEST(Cli, PlanInACellAndExportItsRobotPrograms) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  test::writeText(dir.file("spec.yaml"),
                  "cell:\n  robot: {preset: kuka-kr16-r1610-2, base: {position: [-1000, 0, 0]}}\n"
                  "  mount: {position: [0, 0, 150]}\n");
  const std::string out = dir.file("out");
  CommandResult r =
      run("plan " + part + " --spec " + dir.file("spec.yaml") + " -o " + out + " --no-report -q");
  ASSERT_EQ(r.code, 0) << r.out;
  const Plan plan = readPlan(out + "/plan.json");
  std::ifstream in(out + "/plan.json");
  const std::string json{std::istreambuf_iterator<char>(in), {}};
  EXPECT_NE(json.find("\"robot\""), std::string::npos);
  const std::string spec = " --spec " + dir.file("spec.yaml") + " -q";
  for (const auto& [format, file] :
       {std::pair{"krl", "loop.src"}, std::pair{"robot-json", "loop.json"}}) {
    r = run("export " + out + "/plan.json --format " + format + " -o " + dir.file(file) + spec);
    ASSERT_EQ(r.code, 0) << format << ": " << r.out;
  }
  EXPECT_TRUE(std::filesystem::exists(dir.file("loop.dat")));  // KRL's points beside its .src
  // KRL is written as NAME.src (its points in NAME.dat): another extension is refused.
  r = run("export " + out + "/plan.json --format krl -o " + dir.file("loop.txt") + spec);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("give the file the extension .src"), std::string::npos) << r.out;
  // Each language runs on its maker's arms only: a usage error naming the format, nothing
  // written.
  for (const auto& [format, file] : {std::pair{"urscript", "x.script"}, std::pair{"rapid", "x.mod"},
                                     std::pair{"fanuc", "x.ls"}}) {
    r = run("export " + out + "/plan.json --format " + format + " -o " + dir.file(file) + spec);
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find(std::string("--format ") + format + ": kuka-kr16-r1610-2 is not one of"),
              std::string::npos)
        << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir.file(file)));
  }
  // The same plan in a FANUC cell (--spec): a TP program named as its file.
  test::writeText(dir.file("fanuc.yaml"),
                  "cell:\n  robot: {preset: fanuc-m20id-25, base: {position: [-1000, 0, 0]}}\n"
                  "  mount: {position: [0, 0, 150]}\n");
  r = run("export " + out + "/plan.json --format fanuc -o " + dir.file("scan_ftc11.ls") +
          " --spec " + dir.file("fanuc.yaml") + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream ls(dir.file("scan_ftc11.ls"));
  const std::string fanuc{std::istreambuf_iterator<char>(ls), {}};
  EXPECT_EQ(fanuc.rfind("/PROG  SCAN_FTC11\n", 0), 0u) << fanuc.substr(0, 40);
  EXPECT_NE(fanuc.find("/POS\n"), std::string::npos);
  // A home that puts the wrist into the floor (A2 20° below level, the forearm hanging
  // down): the move from it collides, so the program is refused naming the move, and is
  // written with the move marked only when the user allows it.
  test::writeText(dir.file("floor.yaml"),
                  "cell:\n  robot: {preset: kuka-kr16-r1610-2, base: {position: [-1000, 0, 0]}}\n"
                  "  mount: {position: [0, 0, 150]}\n  home: [0, 20, 90, 0, 0, 0]\n");
  const std::string floor = " --spec " + dir.file("floor.yaml") + " -q";
  r = run("export " + out + "/plan.json --format krl -o " + dir.file("floor.src") + floor);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("floor.src: the move home -> view "), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("floor.src")));
  r = run("export " + out + "/plan.json --format krl -o " + dir.file("floor.src") + floor +
          " --allow-collisions");
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream marked(dir.file("floor.src"));
  const std::string floor_krl{std::istreambuf_iterator<char>(marked), {}};
  EXPECT_NE(floor_krl.find("; WARNING: the move home -> view "), std::string::npos);
  r = run("export " + out + "/plan.json --format krl -o " + dir.file("cell_plan.src") + spec);
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream src(dir.file("cell_plan.src"));
  const std::string krl{std::istreambuf_iterator<char>(src), {}};
  EXPECT_NE(krl.find("DEF cell_plan()"), std::string::npos);  // named as its file
  auto count = [&](const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = krl.find(what); at != std::string::npos; at = krl.find(what, at + 1)) ++n;
    return n;
  };
  // A scan at every view; home, each view's approach and retract, and any via points.
  EXPECT_EQ(count("  SCAN("), plan.views.size());
  EXPECT_EQ(count("  PTP X"), 2 + plan.views.size() + count("; approach view") +
                                  count("; retract view") + count("; via"));
  EXPECT_EQ(count("; home"), 2u);
  EXPECT_EQ(count("could not be cleared"), 0u);
  // The plan's cycle moves the arm as long as the program's PTP moves take at the
  // preset's joint speeds and accelerations, each move's slowest joint stepped in time.
  ASSERT_TRUE(plan.cycle && plan.cell);
  std::ifstream dat(dir.file("cell_plan.dat"));
  const std::string points{std::istreambuf_iterator<char>(dat), {}};
  std::vector<Joints> moves;
  std::istringstream krl_lines(krl);
  for (std::string line; std::getline(krl_lines, line);) {
    if (line.rfind("  PTP X", 0) != 0) continue;
    const std::string name = line.substr(6);
    const std::size_t declared = points.find("DECL E6AXIS " + name + "={");
    ASSERT_NE(declared, std::string::npos) << name;
    Joints q{};
    for (int j = 0; j < 6; ++j) {
      const std::size_t axis = points.find("A" + std::to_string(j + 1) + " ", declared);
      q[j] = radians(std::stod(points.substr(axis + 3)));
    }
    moves.push_back(q);
  }
  double program_seconds = 0;
  for (std::size_t k = 1; k < moves.size(); ++k) {
    double slowest = 0;
    for (int j = 0; j < 6; ++j)
      slowest =
          std::max(slowest, test::steppedMoveSeconds(std::abs(moves[k][j] - moves[k - 1][j]),
                                                     plan.cell->robot.speeds[j],
                                                     plan.cell->robot.accelerations[j], 1e-4));
    program_seconds += slowest;
  }
  EXPECT_NEAR(plan.cycle->motion + plan.cycle->table, program_seconds, 0.01 * program_seconds);
  EXPECT_EQ(plan.cycle->views, plan.views.size());
  // The plan carries its cell: without --spec the program is the same.
  std::filesystem::create_directory(dir.file("again"));
  r = run("export " + out + "/plan.json --format krl -o " + dir.file("again/cell_plan.src") +
          " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream again(dir.file("again/cell_plan.src"));
  const std::string krl_again{std::istreambuf_iterator<char>(again), {}};
  EXPECT_EQ(krl_again.substr(krl_again.find("DEF ")), krl.substr(krl.find("DEF ")));
  // A plan made without a cell has no robot to write for.
  r = run("plan " + part + " -o " + dir.file("plain") + " --no-report --no-registration -q");
  ASSERT_EQ(r.code, 0) << r.out;
  r = run("export " + dir.file("plain/plan.json") + " --format rapid -o " + dir.file("x.mod") +
          " -q");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("cell"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.mod")));
}

// A UR10e with a rotary table: URScript drives the table only through the signals the
// spec gives it; without them the export is refused (exit 1) naming the format, with them
// the program turns the table before the views that need it.
TEST(Cli, UrScriptDrivesATableOnlyThroughItsSignals) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  const std::string cell =
      "cell:\n  robot: {preset: ur10e, base: {position: [-700, 0, 0]}}\n"
      "  table: {origin: [0, 0, 0]}\n";
  test::writeText(dir.file("spec.yaml"), cell);
  CommandResult r = run("plan " + part + " --spec " + dir.file("spec.yaml") + " -o " +
                        dir.file("out") + " --no-report -q");
  ASSERT_EQ(r.code, 0) << r.out;
  r = run("export " + dir.file("out/plan.json") + " --format urscript -o " + dir.file("ur.script") +
          " -q");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("--format urscript: URScript cannot drive the rotary table"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("ur.script")));
  test::writeText(dir.file("signals.yaml"),
                  cell + "  signals: {table: {angle: 0, move: 2, ready: 2}}\n");
  r = run("export " + dir.file("out/plan.json") + " --spec " + dir.file("signals.yaml") +
          " --format urscript -o " + dir.file("ur.script") + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(dir.file("ur.script"));
  const std::string script{std::istreambuf_iterator<char>(in), {}};
  EXPECT_NE(script.find("  turn_table("), std::string::npos);
  EXPECT_NE(script.find("set_tcp(p[0.000000, 0.000000, 0.150000,"), std::string::npos);
}

}  // namespace
}  // namespace scanplan

namespace scanplan {
namespace {

// --rest overrides the spec's part.rest: a spec planning every rest orientation, planned as
// drawn, has one placement that turns nothing; a word that is no orientation is a usage
// error and a face the part lacks an input error.
TEST(Cli, RestOverridesTheSpecsPlacement) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  test::writeText(dir.file("all.yaml"), "part: {rest: all}\n");
  CommandResult r = run("-q plan " + part + " --spec " + dir.file("all.yaml") +
                        " --rest drawn --no-registration --no-report -o " + dir.file("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Plan plan = readPlan(dir.file("out/plan.json"));
  EXPECT_TRUE(plan.orientations.empty());
  EXPECT_TRUE(plan.part_to_world.linear().isIdentity(1e-12));
  r = run("-q plan " + part + " --rest sideways -o " + dir.file("bad"));
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("--rest: expected auto, all, drawn or a face id"), std::string::npos);
  r = run("-q plan " + part + " --rest 999 -o " + dir.file("bad"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("unknown face id 999"), std::string::npos) << r.out;
  // A face the part cannot stand on (FTC 11's face 3 is curved) is named as --rest gave it,
  // also beside a spec that says nothing of it.
  for (const std::string& spec : {std::string(), " --spec " + dir.file("all.yaml")}) {
    r = run("-q plan " + part + spec + " --rest 3 -o " + dir.file("bad"));
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_EQ(r.out.rfind("error: --rest: face 3 is not flat", 0), 0u) << r.out;
  }
}

// --aim characteristics: planned for its GD&T alone (gdt: from-file leaves the dimensioned
// faces out), FTC 11's linear distance is not targeted; aimed at characteristics its faces
// are, and each characteristic's inspected U in plan.json is what `scanplan inspect` finds
// of the same plan with the same seed.
TEST(Cli, AimAtCharacteristicsTargetsTheirFacesAndInspectsThePlan) {
  test::TempDir dir;
  const std::string part = test::testData("nist_ftc_11_asme1_ap242-e1.stp");
  test::writeText(dir.file("gdt.yaml"), "gdt: from-file\ntasks: [{type: gdt}]\n");
  const std::string plan =
      "-q plan " + part + " --spec " + dir.file("gdt.yaml") + " --no-registration --no-report -o ";
  ASSERT_EQ(run(plan + dir.file("samples")).code, 0);
  const CommandResult r = run(plan + dir.file("aimed") + " --aim characteristics");
  ASSERT_EQ(r.code, 0) << r.out;
  const Plan samples = readPlan(dir.file("samples/plan.json"));
  const Plan aimed = readPlan(dir.file("aimed/plan.json"));
  ASSERT_EQ(samples.capabilities.size(), aimed.capabilities.size());
  std::size_t untargeted = 0, inspected = 0;
  for (std::size_t k = 0; k < samples.capabilities.size(); ++k) {
    if (samples.capabilities[k].limit != Limit::NotTargeted) continue;
    ++untargeted;
    EXPECT_NE(aimed.capabilities[k].limit, Limit::NotTargeted) << k;
  }
  EXPECT_GT(untargeted, 0u);
  ASSERT_EQ(run("-q inspect " + dir.file("aimed/plan.json") + " " + part + " --spec " +
                dir.file("gdt.yaml") + " -o " + dir.file("inspection.json"))
                .code,
            0);
  const nlohmann::json inspection =
      nlohmann::json::parse(std::ifstream(dir.file("inspection.json")));
  for (const nlohmann::json& c : inspection.at("characteristics")) {
    const auto k =
        std::find_if(aimed.capabilities.begin(), aimed.capabilities.end(),
                     [&](const Capability& x) { return x.characteristic == c.at("id"); });
    ASSERT_NE(k, aimed.capabilities.end());
    if (!c.at("evaluated").get<bool>()) continue;
    ++inspected;
    ASSERT_TRUE(k->inspected_uncertainty.has_value()) << c.at("id");
    EXPECT_NEAR(*k->inspected_uncertainty, c.at("uncertainty").get<double>(), 1e-9);
  }
  EXPECT_GT(inspected, 0u);
}

}  // namespace
}  // namespace scanplan
