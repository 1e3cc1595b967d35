#pragma once
// Outputs are never half-written (docs/design.md §8): written to `<path>.tmp`, then renamed
// into place.

#include <functional>
#include <ostream>
#include <string>

namespace scanplan {

// Calls `write` on a binary stream for `<path>.tmp` and renames it to `path`; on any
// failure, an exception from `write` included, the temporary is removed. A link at `path`
// is kept and its target replaced. \throw OutputError naming `path`, also when it is a
// directory or a device rather than a file.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// The same for writers that take a file name: `write_file` writes the temporary it is
// given, and throws (an OutputError naming `path`) when it cannot.
void writeFileAtomically(const std::string& path,
                         const std::function<void(const std::string&)>& write_file);

// Removes the temporaries of the writes under way (up to 16 at once). Async-signal-safe:
// for a handler of SIGINT and SIGTERM, so that an interrupted run leaves none behind.
void removeTemporaries() noexcept;

}  // namespace scanplan
