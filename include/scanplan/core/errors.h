#pragma once
// The library's error policy: every failure a user can cause is one of these typed
// exceptions. The CLI catches them once, prints `error: <file>: <reason>` and exits with
// the class's code (docs/design.md §8). Internal invariants use assertions, not exceptions.

#include <cstddef>
#include <stdexcept>
#include <string>

namespace scanplan {

// Exit codes of the command-line tool, one per error class.
enum ExitCode : int {
  kExitOk = 0,
  kExitUsage = 1,     // bad command line
  kExitInput = 2,     // unreadable or invalid input (file, spec, parameter)
  kExitPlanning = 3,  // planning failed
  kExitOutput = 4,    // an output could not be written
};

// `text` to print on one line: every control byte (a line break, a terminal escape)
// becomes '?'. Names taken from the inputs (a file's, a robot's) may hold them.
std::string printable(std::string text);

// `reason` fit to print on one line: printable, and each excerpt of a user's file quoted in it
// ('...') longer than kQuotedBytes is cut there and ends in "...": a line of a binary file, or a
// whole YAML map, would otherwise drown the message. A quote within a word (the apostrophe of "the
// part's") neither opens nor closes an excerpt.
inline constexpr std::size_t kQuotedBytes = 80;
std::string briefReason(std::string reason);

// Base of all scanplan errors. `file()` names the input or output concerned (may be
// empty), `reason()` says what is wrong with it (briefReason); `what()` is
// "<file>: <reason>".
class Error : public std::runtime_error {
 public:
  Error(std::string file, std::string reason)
      : Error(std::move(file), briefReason(std::move(reason)), Brief{}) {}
  const std::string& file() const noexcept { return file_; }
  const std::string& reason() const noexcept { return reason_; }
  virtual ExitCode exitCode() const noexcept = 0;

 private:
  struct Brief {};  // the reason is brief already
  Error(std::string file, std::string brief, Brief)
      : std::runtime_error(file.empty() ? brief : file + ": " + brief),
        file_(std::move(file)),
        reason_(std::move(brief)) {}

  std::string file_;
  std::string reason_;
};

// A request that does not fit the rest of the command line: a robot program format the
// cell's robot does not run. `file()` names the option.
class UsageError : public Error {
 public:
  using Error::Error;
  ExitCode exitCode() const noexcept override { return kExitUsage; }
};

// A missing, unreadable or invalid input: CAD file, mesh, spec, parameter, face id.
class InputError : public Error {
 public:
  using Error::Error;
  ExitCode exitCode() const noexcept override { return kExitInput; }
};

// The planner could not produce a result from valid input.
class PlanningError : public Error {
 public:
  using Error::Error;
  ExitCode exitCode() const noexcept override { return kExitPlanning; }
};

// An output file could not be written.
class OutputError : public Error {
 public:
  using Error::Error;
  ExitCode exitCode() const noexcept override { return kExitOutput; }
};

// A failure inside a third-party library (OCCT, Embree) that is not the input's fault.
class LibraryError : public Error {
 public:
  using Error::Error;
  ExitCode exitCode() const noexcept override { return kExitPlanning; }
};

}  // namespace scanplan
