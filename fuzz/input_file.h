#pragma once
// The fuzzers' common part: each input is written to a file and read by the library's own
// reader, which must either read it or throw a scanplan::Error. Anything else (a crash, a
// sanitizer report, another exception) is a finding.

#include <scanplan/core/errors.h>

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

namespace scanplan::fuzz {

// `data` written to a file of this process named with `extension` (".stl", ...).
inline std::string inputFile(const std::uint8_t* data, std::size_t size,
                             const std::string& extension) {
  const std::string path = "/tmp/scanplan-fuzz-" + std::to_string(::getpid()) + extension;
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

// Runs `read` on the input; scanplan::Error is the expected way to refuse it.
template <class Read>
int readOrRefuse(const std::uint8_t* data, std::size_t size, const std::string& extension,
                 Read read) {
  const std::string path = inputFile(data, size, extension);
  try {
    read(path);
  } catch (const Error&) {
  }
  ::unlink(path.c_str());
  return 0;
}

}  // namespace scanplan::fuzz
