// scanplan study: many plans as one study (docs/study.md), each planned by this program in
// a process of its own, on this machine or on a Dask cluster, and tabled together.

#include "commands.h"
#include "terminal.h"

#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/study_yaml.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

extern char** environ;

namespace scanplan::cli {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

struct StudyCommand {
  std::string file;
  std::string out = "study-out";
  int jobs = 0;  // plans at a time; 0: one per core
  std::string dask;
};

// A row's plan: its folder, the command that plans it, and how it went.
struct RowRun {
  const StudyRow* row = nullptr;
  fs::path folder;
  std::vector<std::string> command;
  bool reused = false;
  int code = -1;  // the plan command's exit code; -1: not run
  std::string error;
};

// The plan command of `row` into `folder`, for this program at `self`.
std::vector<std::string> planCommand(const std::string& self, const Study& study,
                                     const StudyRow& row, const fs::path& folder, int threads) {
  std::vector<std::string> argv = {self,   "-q",     "-j", std::to_string(threads),
                                   "plan", row.part, "-o", folder.string()};
  auto add = [&](const char* option, const std::string& value) {
    if (!value.empty()) argv.insert(argv.end(), {option, value});
  };
  add("--spec", row.spec);
  add("--scanner", row.scanner);
  add("--rest", row.rest);
  if (row.coverage) add("--coverage", fmt::format("{:.17g}", *row.coverage));
  if (!study.registration) argv.push_back("--no-registration");
  return argv;
}

// A plan done before with the same command: its row.json says so.
bool doneBefore(const RowRun& run) {
  std::ifstream in(run.folder / "row.json");
  if (!in) return false;
  try {
    const json done = json::parse(in);
    return done.value("command", json()) == json(run.command) &&
           fs::exists(run.folder / "plan.json");
  } catch (const json::exception&) {
    return false;
  }
}

// Starts `argv` with its output into `log`; the child's pid.
pid_t start(const std::vector<std::string>& argv, const fs::path& log) {
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int failed = posix_spawn(&pid, argv[0].c_str(), &files, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  if (failed) throw OutputError(argv[0], "cannot start a plan: " + std::string(strerror(failed)));
  return pid;
}

// The exit code of a status from waitpid: a signal as 128 + its number, as shells give it.
int exitCode(int status) {
  return WIFEXITED(status) ? WEXITSTATUS(status)
                           : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

// Runs the rows' commands here, `jobs` at a time.
void runHere(std::vector<RowRun*>& todo, int jobs, const Progress& progress, std::size_t total,
             std::size_t& done) {
  std::map<pid_t, RowRun*> running;
  std::size_t next = 0;
  while (next < todo.size() || !running.empty()) {
    while (next < todo.size() && static_cast<int>(running.size()) < jobs) {
      RowRun* run = todo[next++];
      running[start(run->command, run->folder / "log.txt")] = run;
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0)
      throw OutputError("", "lost the plans' processes: " + std::string(strerror(errno)));
    if (auto it = running.find(pid); it != running.end()) {
      it->second->code = exitCode(status);
      running.erase(it);
      report(progress, "study", static_cast<double>(++done) / static_cast<double>(total));
    }
  }
}

// What each Dask worker runs: the plan command, its output into the row's log.
constexpr const char* kDaskRunner = R"(import json, subprocess, sys
from distributed import Client

def plan(argv, log):
    with open(log, "w") as out:
        return subprocess.run(argv, stdout=out, stderr=subprocess.STDOUT).returncode

address, rows_file, codes_file = sys.argv[1:4]
with open(rows_file) as f:
    rows = json.load(f)
with Client(address, timeout="30s") as client:
    futures = [client.submit(plan, r["argv"], r["log"], key="scanplan-" + r["name"], pure=False)
               for r in rows]
    codes = client.gather(futures)
with open(codes_file, "w") as f:
    json.dump(dict(zip([r["name"] for r in rows], codes)), f)
)";

// Runs the rows' commands on the Dask cluster at `address`, through Python with
// dask.distributed ($SCANPLAN_PYTHON, else python3 on the PATH): the workers must reach
// this program and the study's files at the same paths.
void runOnDask(std::vector<RowRun*>& todo, const std::string& address, const fs::path& out) {
  json rows = json::array();
  for (const RowRun* run : todo)
    rows.push_back({{"name", run->row->name},
                    {"argv", run->command},
                    {"log", (run->folder / "log.txt").string()}});
  const fs::path rows_file = out / "dask-rows.json", codes_file = out / "dask-codes.json";
  writeFileAtomically(rows_file.string(), [&](std::ostream& o) { o << rows.dump(1) << '\n'; });
  fs::remove(codes_file);
  const char* python = std::getenv("SCANPLAN_PYTHON");
  const std::vector<std::string> argv = {"/usr/bin/env",
                                         python && *python ? python : "python3",
                                         "-c",
                                         kDaskRunner,
                                         address,
                                         rows_file.string(),
                                         codes_file.string()};
  int status = 0;
  waitpid(start(argv, out / "dask.log"), &status, 0);
  std::ifstream in(codes_file);
  if (exitCode(status) != 0 || !in)
    throw UsageError("--dask", "the Dask cluster at " + address +
                                   " did not run the plans (Python with dask.distributed, "
                                   "Debian's python3-distributed, as $SCANPLAN_PYTHON or "
                                   "python3): see " +
                                   (out / "dask.log").string());
  const json codes = json::parse(in);
  for (RowRun* run : todo) run->code = codes.value(run->row->name, -1);
}

// Why a plan failed: the last error line of its log, else its exit code.
std::string failure(const RowRun& run) {
  std::ifstream log(run.folder / "log.txt");
  std::string line, error;
  while (std::getline(log, line))
    if (line.rfind("error: ", 0) == 0) error = line.substr(7);
  return !error.empty()   ? error
         : run.code > 128 ? fmt::format("the plan stopped on signal {}", run.code - 128)
                          : fmt::format("the plan exited with code {}", run.code);
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string htmlText(const std::string& text) {
  std::string escaped;
  for (char c : text) {
    switch (c) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '>': escaped += "&gt;"; break;
      case '"': escaped += "&quot;"; break;
      default: escaped += c;
    }
  }
  return escaped;
}

const std::vector<std::string> kColumns = {
    "plan",    "part",   "scanner",    "spec",       "orientation", "coverage target",
    "status",  "views",  "registered", "measured %", "capable",     "characteristics",
    "cycle s", "plan s", "error"};

// A row of the table: the settings, then the plan's figures from its plan.json.
std::vector<std::string> tableRow(const RowRun& run) {
  const StudyRow& row = *run.row;
  auto file = [](const std::string& path) { return fs::path(path).filename().string(); };
  std::vector<std::string> cells = {row.name,
                                    file(row.part),
                                    row.scanner.empty() ? "(spec)" : file(row.scanner),
                                    row.spec.empty() ? "(none)" : file(row.spec),
                                    row.rest.empty() ? "(spec)" : row.rest,
                                    row.coverage ? fmt::format("{:g}", *row.coverage) : "(spec)",
                                    run.error.empty() ? "ok" : "failed"};
  if (!run.error.empty()) {
    cells.resize(kColumns.size() - 1);
    cells.push_back(run.error);
    return cells;
  }
  std::ifstream in(run.folder / "plan.json");
  const json s = json::parse(in).at("summary");
  // A figure of the summary, or an empty cell where the plan has none (null: not made).
  auto figure = [&](const json& at, const char* key, const char* format, double scale = 1) {
    const json value = at.is_object() ? at.value(key, json()) : json();
    return value.is_number() ? fmt::format(fmt::runtime(format), scale * value.get<double>())
                             : std::string();
  };
  std::size_t capable = 0, characteristics = 0;
  const json verdicts = s.value("characteristics", json::object());
  for (const auto& [verdict, n] : verdicts.items()) {
    characteristics += n.get<std::size_t>();
    if (verdict == "capable") capable += n.get<std::size_t>();
  }
  cells.insert(cells.end(), {figure(s, "views", "{:.0f}"), figure(s, "registrable_views", "{:.0f}"),
                             figure(s, "measured_share", "{:.1f}", 100), std::to_string(capable),
                             std::to_string(characteristics),
                             figure(s.value("cycle", json()), "seconds", "{:.0f}"),
                             figure(s, "seconds", "{:.1f}"), ""});
  return cells;
}

void writeTables(const std::vector<RowRun>& runs, const fs::path& out) {
  std::vector<std::vector<std::string>> table;
  for (const RowRun& run : runs) table.push_back(tableRow(run));
  writeFileAtomically((out / "study.csv").string(), [&](std::ostream& o) {
    for (std::size_t c = 0; c < kColumns.size(); ++c) o << (c ? "," : "") << kColumns[c];
    o << '\n';
    for (const auto& cells : table) {
      for (std::size_t c = 0; c < cells.size(); ++c) o << (c ? "," : "") << csvField(cells[c]);
      o << '\n';
    }
  });
  writeFileAtomically((out / "study.html").string(), [&](std::ostream& o) {
    o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>scanplan "
         "study</title><style>body{font:14px sans-serif}table{border-collapse:collapse}"
         "td,th{border:1px solid #ccc;padding:3px 6px}td.failed{color:#b00}</style></head>"
         "<body><h1>scanplan study</h1>\n<table><tr>";
    for (const std::string& c : kColumns) o << "<th>" << htmlText(c) << "</th>";
    o << "</tr>\n";
    for (std::size_t r = 0; r < runs.size(); ++r) {
      const bool report = runs[r].error.empty() && fs::exists(runs[r].folder / "report.html");
      o << "<tr>";
      for (std::size_t c = 0; c < table[r].size(); ++c) {
        const std::string text = htmlText(table[r][c]);
        o << (c == 6 && !runs[r].error.empty() ? "<td class=\"failed\">" : "<td>");
        if (c == 0 && report)
          o << "<a href=\"plans/" << text << "/report.html\">" << text << "</a>";
        else
          o << text;
        o << "</td>";
      }
      o << "</tr>\n";
    }
    o << "</table></body></html>\n";
  });
}

int runStudy(const StudyCommand& options, const GlobalOptions& global) {
  const Study study = loadStudy(options.file);
  const fs::path out = fs::absolute(options.out);
  std::error_code ec;
  fs::create_directories(out / "plans", ec);
  if (ec) throw OutputError(options.out, "cannot create the folder: " + ec.message());
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int jobs = options.jobs > 0 ? options.jobs : cores;
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  std::vector<RowRun> runs(study.rows.size());
  std::vector<RowRun*> todo;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    RowRun& run = runs[r];
    run.row = &study.rows[r];
    run.folder = out / "plans" / run.row->name;
    run.command = planCommand(self, study, *run.row, run.folder, std::max(1, cores / jobs));
    run.reused = doneBefore(run);
    if (run.reused) continue;
    fs::create_directories(run.folder, ec);
    fs::remove(run.folder / "row.json", ec);
    todo.push_back(&run);
  }
  Progress progress = terminalProgress(global);
  std::size_t done = runs.size() - todo.size();
  report(progress, "study", static_cast<double>(done) / static_cast<double>(runs.size()));
  if (options.dask.empty())
    runHere(todo, jobs, progress, runs.size(), done);
  else
    runOnDask(todo, options.dask, out);
  clearProgress();
  std::size_t failed = 0;
  for (RowRun* run : todo) {
    if (run->code == 0) {
      writeFileAtomically((run->folder / "row.json").string(), [&](std::ostream& o) {
        o << json{{"command", run->command}}.dump() << '\n';
      });
    } else {
      run->error = failure(*run);
      ++failed;
    }
  }
  writeTables(runs, out);
  fmt::print("study      {} plans: {} planned, {} reused, {} failed\n", runs.size(),
             todo.size() - failed, runs.size() - todo.size(), failed);
  fmt::print("table      {}\n", (out / "study.html").string());
  return failed ? kExitPlanning : kExitOk;
}

}  // namespace

void addStudyCommand(CLI::App& app, const GlobalOptions& global, Action& selected) {
  auto options = std::make_shared<StudyCommand>();
  CLI::App* command = app.add_subcommand(
      "study",
      "Plan parts x scanners x specs x orientations as one study, in parallel, and table "
      "the plans");
  command->add_option("study", options->file, "Study file (YAML)")->required()->check(kNamedFile);
  command->add_option("-o,--out", options->out,
                      "Output folder: plans/<name>/ per plan, study.csv and study.html (default: "
                      "study-out)");
  command
      ->add_option("--jobs", options->jobs,
                   "Plans at a time on this machine (default: one per core)")
      ->check(CLI::Range(1, 1024));
  command->add_option("--dask", options->dask,
                      "Run the plans on the Dask cluster at this scheduler address "
                      "(tcp://HOST:PORT) instead");
  command->callback([options, &global, &selected] {
    selected = [options, &global] { return runStudy(*options, global); };
  });
}

}  // namespace scanplan::cli
