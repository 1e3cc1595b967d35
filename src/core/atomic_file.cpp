#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <vector>

namespace scanplan {

namespace {

// The temporaries being written, for removeTemporaries(): fixed slots that a signal handler
// may read without allocating.
constexpr std::size_t kSlots = 64, kLongestPath = 4096;
char g_temporaries[kSlots][kLongestPath];
std::mutex g_slots;

// Holds `temporary` in a slot while it lives (none when the slots are full or the path
// too long: then it is only removed by the usual paths).
class RegisteredTemporary {
 public:
  explicit RegisteredTemporary(const std::string& temporary) {
    if (temporary.size() >= kLongestPath) return;
    const std::lock_guard lock(g_slots);
    for (std::size_t k = 0; k < kSlots; ++k)
      if (g_temporaries[k][0] == '\0') {
        std::memcpy(g_temporaries[k], temporary.c_str(), temporary.size() + 1);
        slot_ = k;
        return;
      }
  }
  ~RegisteredTemporary() {
    if (slot_ == kSlots) return;
    const std::lock_guard lock(g_slots);
    g_temporaries[slot_][0] = '\0';
  }
  RegisteredTemporary(const RegisteredTemporary&) = delete;
  RegisteredTemporary& operator=(const RegisteredTemporary&) = delete;

 private:
  std::size_t slot_ = kSlots;
};

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

// A new, empty file beside `target` for writing it: named after it with `kind`, this
// process and a count, its extension kept (some writers go by it), and created
// exclusively, so that neither another run nor a link planted at that name is written
// through. \throw OutputError naming `path` when it cannot be created.
std::filesystem::path newTemporary(const std::filesystem::path& target, const char* kind,
                                   const std::string& path) {
  static std::atomic<unsigned> count{0};
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::filesystem::path temporary = target;
    temporary.replace_filename(target.stem().string() + "." + kind + "-" +
                               std::to_string(::getpid()) + "-" + std::to_string(count++) +
                               target.extension().string());
    const int fd =
        ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return temporary;
    }
    if (errno != EEXIST)
      throw OutputError(path, std::string("cannot be written: ") + std::strerror(errno));
  }
  throw OutputError(path, "cannot be written: no free temporary name beside it");
}

// Renames `temporary` to `target`, which keeps the permissions of the file it replaces.
void replace(const std::filesystem::path& temporary, const std::filesystem::path& target,
             std::error_code& ec) {
  struct stat replaced {};
  if (::stat(target.c_str(), &replaced) == 0) ::chmod(temporary.c_str(), replaced.st_mode & 07777);
  std::filesystem::rename(temporary, target, ec);
}

}  // namespace

void writeFileAtomically(const std::string& path,
                         const std::function<void(const std::string&)>& write_file) {
  const std::filesystem::path target = destination(path);
  const std::string temporary = newTemporary(target, "tmp", path).string();
  const RegisteredTemporary registered(temporary);
  try {
    write_file(temporary);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  std::error_code ec;
  replace(temporary, target, ec);
  if (ec) {
    std::remove(temporary.c_str());
    throw OutputError(path, "cannot be written: " + ec.message());
  }
}

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  writeFileAtomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    if (!out) throw OutputError(path, "cannot be written");
    write(out);
    out.flush();
    if (!out.good()) throw OutputError(path, "write failed");
  });
}

struct FileSet::Impl {
  struct Staged {
    std::string path;
    std::filesystem::path target, temporary;
    std::unique_ptr<RegisteredTemporary> registered;
  };
  std::vector<Staged> staged;
  std::vector<std::string> dropped;
  bool committed = false;
};

FileSet::FileSet() : impl_(std::make_unique<Impl>()) {}

FileSet::~FileSet() {
  if (impl_->committed) return;
  for (const Impl::Staged& s : impl_->staged) std::remove(s.temporary.c_str());
}

std::string FileSet::stage(const std::string& path) {
  Impl::Staged s{path, destination(path), {}, {}};
  s.temporary = newTemporary(s.target, "staged", path);
  s.registered = std::make_unique<RegisteredTemporary>(s.temporary.string());
  impl_->staged.push_back(std::move(s));
  return impl_->staged.back().temporary.string();
}

void FileSet::drop(const std::string& path) { impl_->dropped.push_back(path); }

void FileSet::commit() {
  for (const Impl::Staged& s : impl_->staged) {
    std::error_code ec;
    replace(s.temporary, s.target, ec);
    if (ec) throw OutputError(s.path, "cannot be written: " + ec.message());
  }
  impl_->committed = true;
  for (const std::string& path : impl_->dropped) std::remove(path.c_str());
}

void removeTemporaries() noexcept {
  for (const char* temporary : g_temporaries)
    if (temporary[0] != '\0') ::unlink(temporary);
}

}  // namespace scanplan
