#include <scanplan/errors.h>
#include <scanplan/io/atomic_file.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace scanplan {

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary);
    if (!out) throw OutputError(path, "cannot be written");
    write(out);
    if (!out.good()) {
      out.close();
      std::remove(temporary.c_str());
      throw OutputError(path, "write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::remove(temporary.c_str());
    throw OutputError(path, "cannot be written: " + ec.message());
  }
}

}  // namespace scanplan
