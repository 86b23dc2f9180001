#include "atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace svo::render::detail {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& step, int err) {
  throw std::runtime_error(path + ": cannot write: " + step + ": " + std::strerror(err));
}

// Removes the temporary on scope exit unless it was renamed.
struct Temporary {
  std::string name;
  bool committed = false;
  ~Temporary() {
    if (!committed) ::unlink(name.c_str());
  }
};

}  // namespace

void write_atomically(const std::string& path, const std::function<void(const std::string& temporary)>& write) {
  static std::atomic<unsigned> counter{0};
  Temporary tmp{path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++)};
  write(tmp.name);
  // Test hook (tests/reliability/kill_test.cpp): with SVO_TEST_STALL_WRITE
  // set, stop here, the temporary written and not renamed, announced on
  // stderr, for up to 60 s, so that a test can kill the process mid-write.
  if (std::getenv("SVO_TEST_STALL_WRITE")) {
    std::fprintf(stderr, "svo: test hook: stalled writing %s\n", tmp.name.c_str());
    std::fflush(stderr);
    for (int i = 0; i < 600; ++i) ::usleep(100000);
  }
  int fd = ::open(tmp.name.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail(path, "opening " + tmp.name, errno);
  if (::fsync(fd) != 0) {
    int err = errno;
    ::close(fd);
    fail(path, "fsync " + tmp.name, err);
  }
  ::close(fd);
  if (::rename(tmp.name.c_str(), path.c_str()) != 0) fail(path, "renaming " + tmp.name, errno);
  tmp.committed = true;
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

void write_bytes_atomically(const std::string& path, const void* data, size_t size) {
  write_atomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(static_cast<const char*>(data), std::streamsize(size));
    out.close();
    if (!out) throw std::runtime_error(path + ": cannot write " + temporary + ": " + std::strerror(errno));
  });
}

std::string file_kind(std::filesystem::file_type type) {
  switch (type) {
    case std::filesystem::file_type::directory:
      return "a directory";
    case std::filesystem::file_type::fifo:
      return "a FIFO";
    case std::filesystem::file_type::character:
      return "a character device";
    case std::filesystem::file_type::block:
      return "a block device";
    case std::filesystem::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

}  // namespace svo::render::detail
