#pragma once
// Running a reader that a hostile file could crash, hang or blow up, in a child process
// bounded in time and memory, so that its failure becomes an error instead of the end of
// the program. POSIX (fork); the child hands back its result as bytes through a pipe.

#include <cstddef>
#include <functional>
#include <string>

namespace scanplan {

struct IsolationLimits {
  double seconds = 60;    // wall time the child may take
  std::size_t bytes = 0;  // address space the child may add to the parent's; 0: no limit
};

// The limits for reading a file of `file_bytes`: 30 s plus 10 s per MB, and 4 GiB plus
// 400 bytes per byte of the file (imports of files in use take up to 3.6 s per MB and
// about 60 bytes per byte; docs/import.md). No memory limit in sanitizer builds, whose
// shadow memory an address-space limit would refuse.
IsolationLimits readerLimits(std::size_t file_bytes);

// Runs `work` in a child process within `limits` and returns the bytes it returned. When
// it threw a scanplan::Error, the same reason is rethrown as an InputError naming `file`;
// when it threw anything else, crashed on a signal, ran out of memory or of time, an
// InputError naming `file` says so and names `what` (for instance "the IGES reader").
// `work` must not call back into the parent's threads (a progress callback of Python, say);
// what it prints on stdout is discarded.
std::string runIsolated(const std::string& file, const std::string& what,
                        const IsolationLimits& limits, const std::function<std::string()>& work);

}  // namespace scanplan
