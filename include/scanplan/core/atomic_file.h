#pragma once
// Outputs are never half-written (docs/design.md §8): written to a temporary beside the
// path (`<stem>.tmp-<pid>-<n><ext>`, created exclusively, never through a link), then
// renamed into place, keeping the permissions of the file replaced.

#include <functional>
#include <memory>
#include <ostream>
#include <string>

namespace scanplan {

// Calls `write` on a binary stream for a temporary and renames it to `path`; on any
// failure, an exception from `write` included, the temporary is removed. A link at `path`
// is kept and its target replaced. \throw OutputError naming `path`, also when it is a
// directory or a device rather than a file.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// The same for writers that take a file name: `write_file` writes the temporary it is
// given, and throws (an OutputError naming `path`) when it cannot.
void writeFileAtomically(const std::string& path,
                         const std::function<void(const std::string&)>& write_file);

// The files of one run, written as a set: each is written to a temporary beside its path,
// and all are renamed into place by commit(). Until then a failure, or a signal
// (removeTemporaries), leaves none of them, and no file of the set beside another run's.
class FileSet {
 public:
  FileSet();
  ~FileSet();  // without commit(): removes the temporaries
  FileSet(const FileSet&) = delete;
  FileSet& operator=(const FileSet&) = delete;

  // The file to write `path` to (with any writer, itself atomic): a temporary until
  // commit(). \throw OutputError when `path` is a directory or a device.
  std::string stage(const std::string& path);
  // `path` belongs to the set but this run does not write it: commit() removes an earlier
  // run's file there.
  void drop(const std::string& path);
  // Renames every staged file into place and removes the dropped ones.
  // \throw OutputError naming the file that could not be renamed.
  void commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Removes the temporaries of the writes under way (up to 64 at once). Async-signal-safe:
// for a handler of the signals that end a run, so that it leaves none behind.
void removeTemporaries() noexcept;

}  // namespace scanplan
