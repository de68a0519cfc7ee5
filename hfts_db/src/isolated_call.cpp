#include "hfts_db/isolated_call.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

namespace hfts {
namespace {

constexpr char kResult = 'R';  // first byte: the rest is work()'s result
constexpr char kThrew = 'E';   // first byte: the rest is the exception's message

bool writeAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

// GCC 12's AddressSanitizer allocator has no fork handlers (a child forked
// while another thread holds its lock waits forever); clang's fuzz build,
// whose libFuzzer threads hardly allocate, forks without trouble.
#if defined(__SANITIZE_ADDRESS__) && !defined(__clang__)
constexpr bool kForkUnsafeAllocator = true;
#else
constexpr bool kForkUnsafeAllocator = false;
#endif

/// Threads of this process (/proc/self/status), 0 if unknown.
int threadCount() {
  int threads = 0;
  if (FILE* status = std::fopen("/proc/self/status", "r")) {
    char line[256];
    while (std::fgets(line, sizeof line, status) != nullptr)
      if (std::sscanf(line, "Threads: %d", &threads) == 1) break;
    std::fclose(status);
  }
  return threads;
}

/// Reads the process's address space size (bytes), 0 if unknown.
std::size_t addressSpaceBytes() {
  long pages = 0;
  if (FILE* statm = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(statm, "%ld", &pages) != 1) pages = 0;
    std::fclose(statm);
  }
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

[[noreturn]] void runChild(const std::function<std::string()>& work, const IsolationLimits& limits,
                           pid_t parent, int fd) {
  // A crash in third-party code ends the child; no handler of the parent's
  // (a sanitizer's report, a fuzzer's crash file) runs for it.
  for (const int signal : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGPIPE})
    std::signal(signal, SIG_DFL);
  if (limits.extra_memory_bytes > 0) {
    const rlim_t cap = addressSpaceBytes() + limits.extra_memory_bytes;
    const rlimit limit{cap, cap};
    ::setrlimit(RLIMIT_AS, &limit);
  }
  // Die with the parent: nobody would read the result or wait for us.
  // (Compared with the parent's pid, not with 1: the parent may be init,
  // e.g. a server that is a container's entry point.)
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(1);
  std::string out;
  try {
    out = kResult + work();
  } catch (const std::exception& e) {
    out = kThrew + std::string(e.what());
  } catch (...) {
    out = kThrew + std::string("unknown exception");
  }
  // _exit: no atexit handlers or static destructors of the parent's state.
  ::_exit(writeAll(fd, out.data(), out.size()) ? 0 : 1);
}

int waitForChild(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

std::string seconds(std::chrono::milliseconds time) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", static_cast<double>(time.count()) / 1e3);
  return text;
}

std::string describe(int status) {
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    const char* name = ::strsignal(signal);
    return "it crashed (signal " + std::to_string(signal) + ", " +
           (name != nullptr ? name : "unknown") + ")";
  }
  if (WIFEXITED(status))
    return "it stopped with exit status " + std::to_string(WEXITSTATUS(status));
  return "it stopped unexpectedly";
}

}  // namespace

std::string runIsolated(const std::function<std::string()>& work, const IsolationLimits& limits) {
  if (kForkUnsafeAllocator && threadCount() > 1) {
    // Not isolated in a GCC AddressSanitizer build of a threaded program
    // (kForkUnsafeAllocator): `work` runs in this process.
    try {
      return work();
    } catch (const std::exception& e) {
      throw IsolatedCallError(IsolatedCallError::Kind::kThrew, e.what());
    }
  }
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int error = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error(std::string("cannot start a process: ") + std::strerror(error));
  }
  if (pid == 0) {
    ::close(fds[0]);
    runChild(work, limits, parent, fds[1]);
  }
  ::close(fds[1]);

  std::string bytes;
  const auto deadline = std::chrono::steady_clock::now() + limits.time;
  bool timedOut = false, pollFailed = false;
  char buffer[1 << 16];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timedOut = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
    if (ready < 0 && errno != EINTR) {
      pollFailed = true;
      break;
    }
    if (ready <= 0) continue;
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // end of file: the child is done (or died)
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  if (timedOut || pollFailed) ::kill(pid, SIGKILL);  // waitpid must not wait for a hang
  const int status = waitForChild(pid);

  using Kind = IsolatedCallError::Kind;
  if (timedOut)
    throw IsolatedCallError(Kind::kTimedOut,
                            "it did not finish within " + seconds(limits.time) + " s");
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.empty())
    throw IsolatedCallError(Kind::kCrashed, describe(status));
  if (bytes[0] == kThrew) throw IsolatedCallError(Kind::kThrew, bytes.substr(1));
  bytes.erase(0, 1);
  return bytes;
}

}  // namespace hfts
