#include <scanplan/errors.h>
#include <scanplan/io/atomic_file.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace scanplan {

namespace {

// Where `path` leads: the target of a link (which is kept, and its target replaced), else
// the path itself. \throw OutputError when that is something other than a regular file.
std::filesystem::path destination(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path target = path;
  for (int links = 0; links < 40 && fs::is_symlink(fs::symlink_status(target, ec)); ++links) {
    const fs::path next = fs::read_symlink(target, ec);
    if (ec) break;
    target = next.is_absolute() ? next : target.parent_path() / next;
  }
  const fs::file_status status = fs::status(target, ec);
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw OutputError(path, fs::is_directory(status) ? "is a directory, not a file"
                                                     : "is not a regular file (a device?)");
  return target;
}

}  // namespace

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::filesystem::path target = destination(path);
  const std::string temporary = target.string() + ".tmp";
  try {
    std::ofstream out(temporary, std::ios::binary);
    if (!out) throw OutputError(path, "cannot be written");
    write(out);
    out.flush();
    if (!out.good()) throw OutputError(path, "write failed");
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(temporary, target, ec);
  if (ec) {
    std::remove(temporary.c_str());
    throw OutputError(path, "cannot be written: " + ec.message());
  }
}

}  // namespace scanplan
