#include <scanplan/core/errors.h>
#include <scanplan/core/isolated.h>

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <new>

#if defined(__SANITIZE_ADDRESS__)
#define SCANPLAN_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SCANPLAN_SANITIZED 1
#endif
#endif

namespace scanplan {

IsolationLimits readerLimits(std::size_t file_bytes) {
  IsolationLimits limits;
  limits.seconds = 30 + 10 * static_cast<double>(file_bytes) / 1e6;
#ifndef SCANPLAN_SANITIZED
  limits.bytes = (std::size_t{4} << 30) + 400 * file_bytes;
#endif
  return limits;
}

namespace {

// Exit codes of the child, besides 0 (the work returned).
constexpr int kChildError = 2;      // a scanplan::Error; its reason, not the result, is sent
constexpr int kChildNoMemory = 3;   // std::bad_alloc
constexpr int kChildException = 4;  // any other exception; its what() follows

// The address space the process holds now, bytes (0 when /proc cannot tell).
std::size_t addressSpace() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0;
  statm >> pages;
  return pages * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

[[noreturn]] void runChild(int fd, const IsolationLimits& limits,
                           const std::function<std::string()>& work) {
  // The parent's handlers are not the child's: a crash ends the child by its signal, for
  // the parent to report (not through a sanitizer's or fuzzer's handler), and an interrupt
  // does not remove the parent's temporaries from here.
  for (const int signal : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGINT, SIGTERM, SIGHUP,
                           SIGQUIT, SIGPIPE, SIGXCPU, SIGXFSZ, SIGALRM})
    std::signal(signal, SIG_DFL);
  if (limits.bytes > 0) {
    const rlim_t cap = addressSpace() + limits.bytes;
    rlimit limit{cap, cap};
    setrlimit(RLIMIT_AS, &limit);
  }
  // The child speaks through the pipe only: what a reader prints (OCCT's BREP reader
  // writes to std::cout) would end up in the program's output. (What the parent left in
  // its buffer is copied here too: it must not be flushed twice, so to nowhere.)
  if (const int null = ::open("/dev/null", O_WRONLY); null >= 0) ::dup2(null, STDOUT_FILENO);
  // Should the parent die, the child does not outlive its time.
  alarm(static_cast<unsigned>(std::ceil(limits.seconds)) + 5);
  int code = 0;
  std::string output;
  try {
    output = work();
  } catch (const Error& error) {
    code = kChildError;
    output = error.reason();
  } catch (const std::bad_alloc&) {
    code = kChildNoMemory;
  } catch (const std::exception& error) {
    code = kChildException;
    output = error.what();
  } catch (...) {
    code = kChildException;
  }
  if (code != 0) output.resize(std::min<std::size_t>(output.size(), 4000));
  for (std::size_t sent = 0; sent < output.size();) {
    const ssize_t n = write(fd, output.data() + sent, output.size() - sent);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    sent += static_cast<std::size_t>(n);
  }
  _exit(code);
}

// Reads what the child writes until it closes the pipe or the deadline passes; false
// when the deadline passed first.
bool readUntilClosed(int fd, double seconds, std::string& output) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
  char buffer[4096];
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    pollfd entry{fd, POLLIN, 0};
    const int ready = poll(&entry, 1, static_cast<int>(std::min<long long>(left, 1000)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return true;
    output.append(buffer, static_cast<std::size_t>(n));
  }
}

int waitFor(pid_t child) {
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

}  // namespace

std::string runIsolated(const std::string& file, const std::string& what,
                        const IsolationLimits& limits, const std::function<std::string()>& work) {
  int fds[2];
  if (pipe(fds) != 0) throw InputError(file, what + " could not be started: no pipe");
  const pid_t child = fork();
  if (child < 0) {
    close(fds[0]);
    close(fds[1]);
    throw InputError(file, what + " could not be started: " + std::strerror(errno));
  }
  if (child == 0) {
    close(fds[0]);
    runChild(fds[1], limits, work);
  }
  close(fds[1]);
  std::string output;
  const bool finished = readUntilClosed(fds[0], limits.seconds, output);
  close(fds[0]);
  if (!finished) {
    kill(child, SIGKILL);
    waitFor(child);
    throw InputError(file, fmt::format("{} did not finish within {:g} s: the file makes it "
                                       "loop or work out of proportion to its size",
                                       what, limits.seconds));
  }
  const int status = waitFor(child);
  if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGALRM || WTERMSIG(status) == SIGKILL))
    throw InputError(file, what +
                               " was stopped before it finished: the file makes it work out "
                               "of proportion to its size");
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == 0) return output;
  output.resize(std::min<std::size_t>(output.size(), 4000));
  if (code == kChildError) throw InputError(file, output);
  if (code == kChildNoMemory)
    throw InputError(file, fmt::format("{} ran out of memory on it (more than {:.1f} GiB for a "
                                       "file of this size): the file announces more than it holds",
                                       what, static_cast<double>(limits.bytes) / (1u << 30)));
  if (code == kChildException)
    throw InputError(file, what + " failed on it" + (output.empty() ? "" : ": " + output));
  // A signal, or an exit on its own (a sanitizer's report) while it was working.
  const std::string how =
      WIFSIGNALED(status) ? strsignal(WTERMSIG(status)) : "exit code " + std::to_string(code);
  throw InputError(file, what + " crashed on it (" + how +
                             "): the file is corrupt or holds entities it cannot read");
}

}  // namespace scanplan
