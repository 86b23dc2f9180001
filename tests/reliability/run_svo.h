// Running the `svo` executable (SVO_EXE) from the command-line reliability
// tests: its stderr read through a pipe, optional limits (a file size limit
// as a full disk, a stall hook, a time limit), and what the run cost (exit
// status, seconds, peak resident memory from wait4), so that a test can
// assert "exit 1 with one line, within a few seconds and a bounded memory".
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace svo::testing {

inline std::vector<char> bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The names in `dir` that start with `prefix`, sorted.
inline std::vector<std::string> entries(const std::filesystem::path& dir, const std::string& prefix) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    std::string n = e.path().filename().string();
    if (n.rfind(prefix, 0) == 0) out.push_back(n);
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct Limits {
  bool stall = false;                                    // SVO_TEST_STALL_WRITE=1: stop before the rename
  rlim_t file_size = RLIM_INFINITY;                      // RLIMIT_FSIZE in bytes (SIGXFSZ ignored): a full disk
  double seconds = 120;                                  // killed with SIGKILL past this (finish reports 128 + 9)
  std::vector<std::pair<std::string, std::string>> env;  // set in the child
  // Called in the child after fork, before exec (same PID as the svo run):
  // e.g. to plant a link at the name of its temporary.
  std::function<void()> before_exec;
};

// A running `svo`.
struct Child {
  pid_t pid = -1;
  int err = -1;  // its stderr
  std::chrono::steady_clock::time_point started;
  double seconds_limit = 120;
};

// What a finished run cost.
struct Outcome {
  int status = -1;     // exit status, or 128 + signal
  std::string err;     // all of stderr
  double seconds = 0;  // wall time
  long peak_kib = 0;   // peak resident set (ru_maxrss)
  int lines() const { return int(std::count(err.begin(), err.end(), '\n')); }
};

inline Child start(const std::vector<std::string>& args, const Limits& limits = {}) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe failed");
  Child c;
  c.started = std::chrono::steady_clock::now();
  c.seconds_limit = limits.seconds;
  c.pid = ::fork();
  if (c.pid < 0) throw std::runtime_error("fork failed");
  if (c.pid == 0) {
    ::dup2(fds[1], 2);
    int null = ::open("/dev/null", O_RDWR);
    ::dup2(null, 1);
    ::dup2(null, 0);
    ::close(fds[0]);
    ::close(fds[1]);
    if (limits.stall) ::setenv("SVO_TEST_STALL_WRITE", "1", 1);
    for (const auto& [name, value] : limits.env) ::setenv(name.c_str(), value.c_str(), 1);
    if (limits.before_exec) limits.before_exec();
    if (limits.file_size != RLIM_INFINITY) {
      ::signal(SIGXFSZ, SIG_IGN);
      rlimit r{limits.file_size, limits.file_size};
      ::setrlimit(RLIMIT_FSIZE, &r);
    }
    std::vector<char*> argv{const_cast<char*>(SVO_EXE)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(SVO_EXE, argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  c.err = fds[0];
  return c;
}

// Reads the child's stderr until `needle` appears (true) or it ends or the
// time runs out (false).
inline bool wait_for(const Child& c, const std::string& needle, std::string& seen, double seconds) {
  auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    pollfd p{c.err, POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    char buffer[512];
    ssize_t n = ::read(c.err, buffer, sizeof buffer);
    if (n <= 0) return seen.find(needle) != std::string::npos;
    seen.append(buffer, size_t(n));
    if (seen.find(needle) != std::string::npos) return true;
  }
  return false;
}

// Reads the rest of stderr and waits for the child, killing it past its time
// limit.
inline Outcome finish(Child& c, std::string already = {}) {
  Outcome o;
  o.err = std::move(already);
  using namespace std::chrono;
  const auto deadline = c.started + duration_cast<steady_clock::duration>(duration<double>(c.seconds_limit));
  bool killed = false;
  for (;;) {
    const auto left = duration_cast<milliseconds>(deadline - steady_clock::now()).count();
    if (left <= 0 && !killed) {
      ::kill(c.pid, SIGKILL);
      killed = true;
    }
    pollfd p{c.err, POLLIN, 0};
    if (::poll(&p, 1, killed ? 1000 : int(std::min<long long>(left, 200))) <= 0) {
      if (killed) break;
      continue;
    }
    char buffer[4096];
    ssize_t n = ::read(c.err, buffer, sizeof buffer);
    if (n <= 0) break;
    o.err.append(buffer, size_t(n));
  }
  ::close(c.err);
  int status = 0;
  rusage usage{};
  ::wait4(c.pid, &status, 0, &usage);
  o.seconds = duration<double>(steady_clock::now() - c.started).count();
  o.peak_kib = usage.ru_maxrss;
  o.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return o;
}

inline Outcome run_svo(const std::vector<std::string>& args, const Limits& limits = {}) {
  Child c = start(args, limits);
  return finish(c);
}

// The peak resident memory of `svo --version`: what the executable costs
// just to start (its shared libraries: about 137 MB in Release, 315 MB under
// ASan), the floor under which no run can go. Bounds on a refusal's memory
// are this plus an allowance.
inline long startup_peak_kib() {
  static const long kib = run_svo({"--version"}).peak_kib;
  return kib;
}

}  // namespace svo::testing
