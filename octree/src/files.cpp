#include "svo/octree/files.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <system_error>
#include <utility>
#include <vector>

namespace svo::files {

namespace fs = std::filesystem;

std::string file_kind(fs::file_type type) {
  switch (type) {
    case fs::file_type::directory:
      return "a directory";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

std::string file_kind_of_mode(unsigned mode) {
  if (S_ISDIR(mode)) return file_kind(fs::file_type::directory);
  if (S_ISFIFO(mode)) return file_kind(fs::file_type::fifo);
  if (S_ISCHR(mode)) return file_kind(fs::file_type::character);
  if (S_ISBLK(mode)) return file_kind(fs::file_type::block);
  if (S_ISSOCK(mode)) return file_kind(fs::file_type::socket);
  return file_kind(fs::file_type::unknown);
}

uintmax_t require_regular_file(const std::string& path, const std::string& what) {
  if (path.empty()) throw FileError("an empty file name, expected " + what);
  std::error_code ec;
  fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) throw FileError(path + ": does not exist");
  if (ec) throw FileError(path + ": " + ec.message());
  if (!fs::is_regular_file(status)) throw FileError(path + ": is " + file_kind(status.type()) + ", expected " + what);
  uintmax_t size = fs::file_size(path, ec);
  if (ec) throw FileError(path + ": " + ec.message());
  return size;
}

std::string read_bounded(const std::string& path, uintmax_t limit, const std::string& what) {
  uintmax_t size = require_regular_file(path, what);
  auto too_big = [&](uintmax_t bytes) {
    return FileError(path + ": " + std::to_string(bytes) + " bytes, more than the limit of " + std::to_string(limit) +
                     " for " + what);
  };
  if (size > limit) throw too_big(size);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path + ": cannot open: " + std::strerror(errno));
  // Read up to the limit plus one byte, in pieces: a file that grew after
  // the check (or a size that lied) stops at the bound.
  std::string text;
  char piece[65536];
  while (in && text.size() <= limit) {
    in.read(piece, std::streamsize(std::min<uintmax_t>(sizeof piece, limit + 1 - text.size())));
    text.append(piece, size_t(in.gcount()));
  }
  if (in.bad()) throw FileError(path + ": cannot read: " + std::strerror(errno));
  if (text.size() > limit) throw too_big(text.size());
  return text;
}

namespace {

std::string parent_of(const fs::path& file) {
  fs::path dir = file.parent_path();
  return dir.empty() ? std::string(".") : dir.string();
}

// True when `name` is `prefix` + "<pid>-..." and that process is gone.
bool stale(const std::string& name, const std::string& prefix) {
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return false;
  const char* first = name.data() + prefix.size();
  const char* last = name.data() + name.size();
  long pid = 0;
  auto [end, ec] = std::from_chars(first, last, pid);
  if (ec != std::errc() || end == first || end == last || *end != '-' || pid <= 0) return false;
  if (pid == long(::getpid())) return false;
  return ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
}

}  // namespace

std::string resolve_output(const std::string& path) {
  if (path.empty()) throw FileError("an empty output file name");
  struct stat link {};
  std::string target = path;
  if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
    std::error_code ec;
    fs::path resolved = fs::canonical(path, ec);
    if (ec) throw FileError(path + ": a symbolic link to a missing file (" + ec.message() + "); not written");
    target = resolved.string();
  }
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0) {
    if (!S_ISREG(st.st_mode)) {
      throw FileError(path + ": is " + file_kind_of_mode(st.st_mode) + "; outputs replace only regular files");
    }
    if ((st.st_mode & 0222) == 0) {
      throw FileError(path + ": is read-only; make it writable (chmod u+w) or remove it to replace it");
    }
  } else if (errno != ENOENT && errno != ENOTDIR) {  // ENOTDIR: said below
    throw FileError(path + ": " + std::strerror(errno));
  }
  std::error_code ec;
  const std::string dir = fs::absolute(target, ec).parent_path().string();
  if (ec) throw FileError(path + ": " + ec.message());
  struct stat d {};
  if (::stat(dir.c_str(), &d) != 0) throw FileError(path + ": directory " + dir + " does not exist");
  if (!S_ISDIR(d.st_mode)) throw FileError(path + ": " + dir + " is not a directory");
  if (::access(dir.c_str(), W_OK | X_OK) != 0) throw FileError(path + ": directory " + dir + " is not writable");
  return target;
}

size_t remove_stale_temporaries(const fs::path& dir, const std::string& prefix) {
  size_t removed = 0;
  std::error_code ec;
  for (fs::directory_iterator it(dir.empty() ? fs::path(".") : dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!stale(it->path().filename().string(), prefix)) continue;
    std::error_code ignored;
    if (fs::remove_all(it->path(), ignored) > 0) ++removed;
  }
  return removed;
}

// --- Temporaries removed on SIGINT, SIGTERM and SIGHUP.
//
// A fixed table of slots (no allocation, no lock in the handler). A slot's
// `state` is 0 free, 1 being filled or emptied, 2 a file, 3 a directory; its
// `generation` grows at every change, so that the handler, which copies a
// path and then checks that the generation did not move, never acts on a
// path torn by a concurrent change. A table full (more than kSlots live
// temporaries) leaves the extra ones to the next run's stale cleanup.
namespace {

constexpr size_t kSlots = 256;
// The manifest of a set being published, in its staging directory.
constexpr const char* kManifest = ".set";
constexpr size_t kPathBytes = 4096;

struct Slot {
  std::atomic<uint32_t> state{0};
  std::atomic<uint32_t> generation{0};
  char path[kPathBytes];
};

Slot g_slots[kSlots];
bool g_stderr_tty = false;
// The program's own handlers take precedence: cleanup is installed only over
// the default disposition (an ignored SIGINT, as in a background job, stays
// ignored).
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

static_assert(std::atomic<uint32_t>::is_always_lock_free, "the signal handler reads the slots");

// Async-signal-safe helpers: no allocation, no locks, no stdio.
void copy_path(char* to, const char* from) {
  size_t i = 0;
  for (; i + 1 < kPathBytes && from[i]; ++i) to[i] = from[i];
  to[i] = '\0';
}

size_t length(const char* s) {
  size_t n = 0;
  while (s[n]) ++n;
  return n;
}

void say(const char* text) {
  size_t n = length(text);
  while (n > 0) {
    ssize_t w = ::write(STDERR_FILENO, text, n);
    if (w <= 0) return;
    text += w, n -= size_t(w);
  }
}

// Removes the plain entries of `dir` (getdents64 and unlinkat are system
// calls, safe in a handler; opendir/readdir are not), then the directory.
// A staging directory that holds a set's manifest is being published: its
// files are half moved, and the next run completes the move from it
// (publish_set), so it stays. That check is what protects a publish from a
// signal another thread takes (publish_set holds the signals in its own).
void remove_directory_now(const char* dir) {
  int fd = ::open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC | O_NOFOLLOW);
  struct stat manifest;
  if (fd >= 0 && ::fstatat(fd, kManifest, &manifest, AT_SYMLINK_NOFOLLOW) == 0) {
    ::close(fd);
    return;
  }
  if (fd >= 0) {
    struct Entry {
      uint64_t ino;
      int64_t off;
      unsigned short reclen;
      unsigned char type;
      char name[1];
    };
    alignas(8) char buffer[4096];
    // Unlinking while listing may skip entries: list again until a pass
    // removes nothing (bounded).
    for (int pass = 0; pass < 16; ++pass) {
      bool removed = false;
      ::lseek(fd, 0, SEEK_SET);
      for (;;) {
        long n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
        if (n <= 0) break;
        for (long at = 0; at < n;) {
          const Entry* e = reinterpret_cast<const Entry*>(buffer + at);
          at += e->reclen;
          const char* name = e->name;
          if (name[0] == '.' && (name[1] == '\0' || (name[1] == '.' && name[2] == '\0'))) continue;
          if (::unlinkat(fd, name, 0) == 0) removed = true;
        }
      }
      if (!removed) break;
    }
    ::close(fd);
  }
  ::rmdir(dir);
}

void remove_registered_now() {
  char path[kPathBytes];
  for (Slot& slot : g_slots) {
    const uint32_t generation = slot.generation.load(std::memory_order_acquire);
    const uint32_t state = slot.state.load(std::memory_order_acquire);
    if (state < 2) continue;
    for (size_t i = 0; i < kPathBytes; ++i) {
      path[i] = slot.path[i];
      if (!path[i]) break;
    }
    path[kPathBytes - 1] = '\0';
    if (slot.generation.load(std::memory_order_acquire) != generation) continue;  // changed meanwhile
    if (state == 2) ::unlink(path);
    if (state == 3) remove_directory_now(path);
  }
}

void on_fatal_signal(int sig) {
  const int saved = errno;
  remove_registered_now();
  // A progress bar may hold the line.
  if (g_stderr_tty) say("\n");
  say(sig == SIGINT    ? "svo: interrupted (SIGINT); temporary files removed\n"
      : sig == SIGTERM ? "svo: terminated (SIGTERM); temporary files removed\n"
                       : "svo: hung up (SIGHUP); temporary files removed\n");
  // Die of the same signal, so that the parent sees it (a shell: 128 + sig).
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  ::sigemptyset(&dfl.sa_mask);
  ::sigaction(sig, &dfl, nullptr);
  sigset_t unblock;
  ::sigemptyset(&unblock);
  ::sigaddset(&unblock, sig);
  ::pthread_sigmask(SIG_UNBLOCK, &unblock, nullptr);
  ::raise(sig);
  errno = saved;
}

size_t register_temporary(const std::string& path, uint32_t kind) {
  install_interrupt_cleanup();
  if (path.size() + 1 > kPathBytes) return kSlots;
  for (size_t i = 0; i < kSlots; ++i) {
    uint32_t expected = 0;
    if (!g_slots[i].state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) continue;
    g_slots[i].generation.fetch_add(1, std::memory_order_acq_rel);
    copy_path(g_slots[i].path, path.c_str());
    g_slots[i].generation.fetch_add(1, std::memory_order_acq_rel);
    g_slots[i].state.store(kind, std::memory_order_release);
    return i;
  }
  return kSlots;
}

void unregister_temporary(size_t slot) {
  if (slot >= kSlots) return;
  g_slots[slot].state.store(1, std::memory_order_release);
  g_slots[slot].generation.fetch_add(1, std::memory_order_acq_rel);
  g_slots[slot].state.store(0, std::memory_order_release);
}

}  // namespace

void install_interrupt_cleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    g_stderr_tty = ::isatty(STDERR_FILENO) == 1;
    struct sigaction action {};
    action.sa_handler = on_fatal_signal;
    ::sigemptyset(&action.sa_mask);
    for (int s : kSignals) ::sigaddset(&action.sa_mask, s);
    for (int s : kSignals) {
      struct sigaction old {};
      if (::sigaction(s, nullptr, &old) != 0) continue;
      if (!(old.sa_flags & SA_SIGINFO) && old.sa_handler == SIG_DFL) ::sigaction(s, &action, nullptr);
    }
  });
}

size_t live_temporaries() {
  size_t n = 0;
  for (const Slot& slot : g_slots) n += slot.state.load(std::memory_order_acquire) >= 2;
  return n;
}

void remove_live_temporaries_for_test() { remove_registered_now(); }

OutputFile::OutputFile(const std::string& path) : path_(path), target_(resolve_output(path)) {
  const fs::path target(target_);
  remove_stale_temporaries(target.parent_path(), target.filename().string() + ".tmp-");
  struct stat st {};
  const bool existing = ::stat(target_.c_str(), &st) == 0;
  static std::atomic<unsigned> counter{0};
  // A name taken (by a planted link, say) is skipped, never opened. A new
  // file gets 0666 less the umask, as any created file.
  for (int attempt = 0; attempt < 64 && fd_ < 0; ++attempt) {
    temporary_ = target_ + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd_ < 0 && errno != EEXIST) fail("creating " + temporary_, errno);
  }
  if (fd_ < 0) fail("creating " + temporary_, EEXIST);
  slot_ = register_temporary(temporary_, 2);
  // The replaced file's mode is kept.
  if (existing && ::fchmod(fd_, st.st_mode & 07777) != 0) {
    int err = errno;
    ::close(std::exchange(fd_, -1));
    ::unlink(temporary_.c_str());
    unregister_temporary(std::exchange(slot_, kNoSlot));
    fail("setting the mode of " + temporary_, err);
  }
}

OutputFile::~OutputFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && !temporary_.empty()) ::unlink(temporary_.c_str());
  unregister_temporary(slot_);
}

void OutputFile::fail(const std::string& step, int err) const {
  throw FileError(path_ + ": cannot write: " + step + ": " + std::strerror(err));
}

void OutputFile::write(const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    ssize_t w = ::write(fd_, p, size);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0) fail("writing " + temporary_, errno);
    if (w == 0) fail("writing " + temporary_, ENOSPC);
    p += w, size -= size_t(w);
  }
}

void OutputFile::write_at(const void* data, size_t size, uint64_t offset) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    ssize_t w = ::pwrite(fd_, p, size, off_t(offset));
    if (w < 0 && errno == EINTR) continue;
    if (w < 0) fail("writing " + temporary_, errno);
    if (w == 0) fail("writing " + temporary_, ENOSPC);
    p += w, size -= size_t(w), offset += uint64_t(w);
  }
}

void OutputFile::commit() {
  // Test hook (tests/reliability/kill_test.cpp): with SVO_TEST_STALL_WRITE
  // set, stop here, the temporary written and not renamed, announced on
  // stderr, for up to 60 s, so that a test can kill the process mid-write.
  if (std::getenv("SVO_TEST_STALL_WRITE")) {
    std::fprintf(stderr, "svo: test hook: stalled writing %s\n", temporary_.c_str());
    std::fflush(stderr);
    for (int i = 0; i < 600; ++i) ::usleep(100000);
  }
  if (::fsync(fd_) != 0) fail("fsync " + temporary_, errno);
  if (::close(std::exchange(fd_, -1)) != 0) fail("closing " + temporary_, errno);
  if (::rename(temporary_.c_str(), target_.c_str()) != 0) fail("renaming " + temporary_, errno);
  committed_ = true;
  unregister_temporary(std::exchange(slot_, kNoSlot));
  // The rename made durable (best effort: some file systems refuse).
  int dfd = ::open(parent_of(target_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

void write_file(const std::string& path, const void* data, size_t size) {
  OutputFile out(path);
  out.write(data, size);
  out.commit();
}

// --- A run's set of outputs, published together.
namespace {

// Moves the set named in `stage`'s manifest into `dir`; see publish_set.
void move_set(const fs::path& stage, const fs::path& dir, const std::function<bool(const std::string&)>& ours) {
  const std::string manifest = read_bounded((stage / kManifest).string(), 1u << 24, "a set's manifest");
  std::set<std::string> names;
  std::istringstream lines(manifest);
  // Only names of the run's outputs, in DIR itself: a manifest planted in
  // a staging directory cannot move a file out of DIR ("../x").
  for (std::string name; std::getline(lines, name);)
    if (!name.empty() && name.find('/') == std::string::npos && ours(name)) names.insert(name);
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (ours(name) && !names.count(name) && e.is_regular_file()) fs::remove(e.path());
  }
  // Test hook (tests/reliability/kill_test.cpp): with SVO_TEST_STALL_PUBLISH
  // set to N, stop after the first move, announced on stderr, for N seconds
  // (at most 60), so that a test can kill the process half-way through.
  const char* stall = std::getenv("SVO_TEST_STALL_PUBLISH");
  bool first = true;
  for (const std::string& name : names) {
    const fs::path from = stage / name;
    if (!fs::exists(fs::symlink_status(from))) continue;  // moved before the interruption
    fs::rename(from, dir / name);
    if (std::exchange(first, false) && stall) {
      std::fprintf(stderr, "svo: test hook: stalled publishing %s\n", stage.c_str());
      std::fflush(stderr);
      const int tenths = 10 * std::clamp(std::atoi(stall), 0, 60);
      for (int i = 0; i < tenths; ++i) ::usleep(100000);
    }
  }
  int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
  fs::remove(stage / kManifest);
}

}  // namespace

void publish_set(const fs::path& stage, const fs::path& dir, const std::function<bool(const std::string&)>& ours) {
  std::string manifest;
  for (const auto& e : fs::directory_iterator(stage)) {
    const std::string name = e.path().filename().string();
    if (name == kManifest || !e.is_regular_file()) continue;
    if (!ours(name)) throw FileError((stage / name).string() + ": not one of the run's outputs; not published");
    manifest += name + "\n";
  }
  write_file((stage / kManifest).string(), manifest);
  // The moves with the cleanup signals held in this thread (until the end
  // of the scope, a throw included): the handler would otherwise remove the
  // staging directory's files, half of a set already moved.
  struct HeldSignals {
    sigset_t before;
    HeldSignals() {
      sigset_t held;
      sigemptyset(&held);
      for (int s : kSignals) sigaddset(&held, s);
      pthread_sigmask(SIG_BLOCK, &held, &before);
    }
    ~HeldSignals() { pthread_sigmask(SIG_SETMASK, &before, nullptr); }
  } held;
  move_set(stage, dir, ours);
}

size_t finish_interrupted_sets(const fs::path& dir, const std::string& prefix,
                               const std::function<bool(const std::string&)>& ours) {
  std::vector<fs::path> sets;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (stale(name, prefix) && fs::is_regular_file(it->path() / kManifest)) sets.push_back(it->path());
  }
  // Each run completes an interrupted set before it stages its own, so there
  // is one at most, unless runs into the same DIR overlapped.
  std::sort(sets.begin(), sets.end());
  for (const fs::path& stage : sets) move_set(stage, dir, ours);
  return sets.size();
}

StagingDirectory::StagingDirectory(const fs::path& dir, const std::string& prefix) {
  remove_stale_temporaries(dir, prefix);
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 64; ++attempt) {
    fs::path candidate = dir / (prefix + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    if (::mkdir(candidate.c_str(), 0777) == 0) {
      path_ = candidate;
      slot_ = register_temporary(path_.string(), 3);
      return;
    }
    if (errno != EEXIST) throw FileError(candidate.string() + ": cannot create: " + std::strerror(errno));
  }
  throw FileError(dir.string() + ": cannot create a staging directory " + prefix + "...");
}

StagingDirectory::~StagingDirectory() {
  std::error_code ignored;
  // A publish that failed half-way keeps its manifest: the next run retries it.
  if (!path_.empty() && !fs::exists(path_ / kManifest, ignored)) fs::remove_all(path_, ignored);
  unregister_temporary(slot_);
}

}  // namespace svo::files
