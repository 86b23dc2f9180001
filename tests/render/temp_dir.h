// A fresh directory for a test under the system temporary directory,
// removed with its contents on destruction (the octree and render tests).
#pragma once

#include <stdlib.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace svo::testing {

class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "svo-test-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed for " + pattern);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    ::chmod(path_.c_str(), 0755);  // a test may have made it read-only
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// A mesh of libcgal-demo (scripts/setup.sh installs it), data/meshes/NAME,
// extracted into `dir`: its path.
// @throw std::runtime_error when the archive is missing or tar fails.
inline std::string extract_cgal_mesh(const TempDir& dir, const std::string& name) {
  const std::string archive = "/usr/share/doc/libcgal-dev/data.tar.gz";
  if (!std::filesystem::exists(archive)) {
    throw std::runtime_error(archive + " missing: scripts/setup.sh installs libcgal-demo");
  }
  const std::string command = "tar xzf " + archive + " -C " + dir.path().string() + " data/meshes/" + name;
  if (std::system(command.c_str()) != 0) throw std::runtime_error(command + " failed");
  return (dir.path() / "data/meshes" / name).string();
}

// The Stanford bunny of libcgal-demo: the path of data/meshes/bunny00.off.
inline std::string extract_bunny(const TempDir& dir) { return extract_cgal_mesh(dir, "bunny00.off"); }

// While alive, files this process writes may not grow beyond `bytes`: a
// write past it fails with EFBIG (SIGXFSZ ignored) instead of killing the
// test. Restores the limit and the signal handler on destruction.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    if (::getrlimit(RLIMIT_FSIZE, &saved_) != 0) throw std::runtime_error("getrlimit failed");
    handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit small = saved_;
    small.rlim_cur = bytes;
    if (::setrlimit(RLIMIT_FSIZE, &small) != 0) throw std::runtime_error("setrlimit failed");
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  void (*handler_)(int) = SIG_DFL;
};

// The names of the entries of `dir`, sorted (to check that nothing else was left there).
inline std::vector<std::string> names_in(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace svo::testing

namespace svo::render::testing {
using svo::testing::FileSizeLimit;
using svo::testing::names_in;
using svo::testing::TempDir;
}  // namespace svo::render::testing
