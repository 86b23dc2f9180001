// Files the engine opens and writes, for every library and command: inputs
// checked to be regular files before any library sees them (a FIFO, a
// device or a directory named as an input would hang or eat memory), text
// read with a bound, and outputs replaced atomically (see OutputFile).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

namespace svo::files {

// One-line error about a file: "<path>: <what is wrong>".
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a path that is not a regular file is, for messages: "a directory",
// "a FIFO", "a character device", "a block device", "a socket", or "not a
// regular file".
std::string file_kind(std::filesystem::file_type type);
// The same from a stat() mode (st_mode), for a file already opened.
std::string file_kind_of_mode(unsigned mode);

// Checks that `path` names a regular file (a symlink to one is fine) before
// anything opens it; returns its size in bytes.
// @param what  what was expected, for the message ("a mesh", "a texture").
// @throw FileError "<path>: does not exist", "<path>: is a FIFO, expected
//        <what>", or "<path>: <system error>".
uintmax_t require_regular_file(const std::string& path, const std::string& what);

// The whole of a regular file of at most `limit` bytes, read with that bound
// (a file that grows while read is cut off and refused, too).
// @throw FileError as require_regular_file, or "<path>: <size> bytes, more
//        than the limit of <limit> for <what>", or a read error.
std::string read_bounded(const std::string& path, uintmax_t limit, const std::string& what);

}  // namespace svo::files

namespace svo::files {

// An output file replaced atomically: the bytes go to a temporary in the
// final file's directory, created exclusively (O_CREAT | O_EXCL |
// O_NOFOLLOW: a planted link or file at its name is never written through),
// every write checked, then fsync, close and rename over the final name,
// and the directory fsynced. Until commit() nothing under the final name
// changes; destroying an uncommitted OutputFile removes its temporary.
//
// What is at the final name decides the target (resolve_output):
// - nothing or a regular file: that name; an existing file's mode is kept;
// - a symbolic link: written through to the file it points to (the link
//   stays a link; the target keeps its mode); a dangling link is refused;
// - a read-only file (no write bit at all, for anyone): refused, even for
//   root, so that `chmod a-w` protects a result;
// - a directory, FIFO, device or socket: refused.
// Temporaries are named "<target>.tmp-<pid>-<n>"; those left by processes
// that no longer run (killed with SIGKILL) are removed when the same target
// is written again. While it lives, the temporary is registered for removal
// on SIGINT, SIGTERM or SIGHUP (install_interrupt_cleanup).
class OutputFile {
 public:
  // Resolves and checks the target, removes stale temporaries, creates the
  // temporary. @throw FileError "<path>: ..." one line.
  explicit OutputFile(const std::string& path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // Appends all `size` bytes at the current offset. @throw FileError.
  void write(const void* data, size_t size);
  // Writes all `size` bytes at `offset` (the file offset of write() is not
  // moved). @throw FileError.
  void write_at(const void* data, size_t size, uint64_t offset);
  // Test hook, fsync, close, rename over the target, fsync the directory.
  // @throw FileError; the temporary is then removed by the destructor.
  void commit();

  int fd() const { return fd_; }
  // The temporary's name, for a program that writes it by name (ffmpeg):
  // it is a regular file this process created exclusively.
  const std::string& temporary() const { return temporary_; }
  // The name the user gave, for messages.
  const std::string& path() const { return path_; }
  // The file that commit() replaces (the link's target for a link).
  const std::string& target() const { return target_; }

 private:
  static constexpr size_t kNoSlot = ~size_t(0);
  [[noreturn]] void fail(const std::string& step, int err) const;
  std::string path_, target_, temporary_;
  int fd_ = -1;
  bool committed_ = false;
  size_t slot_ = kNoSlot;  // in the table of temporaries removed on a signal
};

// The file an output at `path` replaces, after the checks of OutputFile
// (link followed, read-only and non-regular refused, the directory present
// and writable): for a command to check its outputs before any work.
// @throw FileError "<path>: ..." one line.
std::string resolve_output(const std::string& path);

// Writes `size` bytes at `data` to `path` through an OutputFile.
void write_file(const std::string& path, const void* data, size_t size);
inline void write_file(const std::string& path, const std::string& text) { write_file(path, text.data(), text.size()); }

// Removes the entries of `dir` named `prefix` + "<pid>-<anything>" whose
// process no longer runs (files or directories left by a killed run of this
// engine). Returns how many were removed.
size_t remove_stale_temporaries(const std::filesystem::path& dir, const std::string& prefix);

// A fresh directory "<dir>/<prefix><pid>-<n>" for a run's set of outputs,
// removed with what is left in it on destruction, or on SIGINT, SIGTERM or
// SIGHUP (its plain files, then itself); stale ones of dead processes are
// removed first.
class StagingDirectory {
 public:
  StagingDirectory(const std::filesystem::path& dir, const std::string& prefix);
  ~StagingDirectory();
  StagingDirectory(const StagingDirectory&) = delete;
  StagingDirectory& operator=(const StagingDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  size_t slot_ = ~size_t(0);
};

// Publishes a run's set of outputs: the plain files of `stage` (a
// StagingDirectory inside `dir`) replace, as one set, the files of `dir` that
// `ours` claims by name; those of `dir` that the set lacks are removed. A
// manifest of the set (`stage`/.set, made durable) is written first and the
// moves are idempotent, so a publish stopped half-way by SIGKILL or a power
// loss rolls forward: finish_interrupted_sets, called by the next run before
// it makes its staging directory, completes it. SIGINT, SIGTERM and SIGHUP
// are held in this thread for the moves (they take milliseconds); taken by
// another thread, the cleanup handler leaves a staging directory holding a
// manifest, as does ~StagingDirectory after a publish that threw, and the
// next run completes the move.
void publish_set(const std::filesystem::path& stage, const std::filesystem::path& dir,
                 const std::function<bool(const std::string&)>& ours);

// Completes the publish of every staging directory of `dir` named `prefix` +
// "<pid>-..." whose process no longer runs and that holds a manifest (a run
// killed while publishing). Directories without one (killed before) are left
// to remove_stale_temporaries. Returns how many sets it completed.
size_t finish_interrupted_sets(const std::filesystem::path& dir, const std::string& prefix,
                               const std::function<bool(const std::string&)>& ours);

// Installs, once per process, handlers for SIGINT, SIGTERM and SIGHUP that
// remove every live OutputFile temporary and StagingDirectory (with
// async-signal-safe calls only: unlink, unlinkat, getdents64, rmdir on names
// recorded beforehand), print one line on stderr, and then die of the same
// signal with its default action (a shell sees 130, 143 or 129). A signal
// already ignored (a background job's SIGINT) or handled by the program is
// left as it is. Called by the first OutputFile or StagingDirectory; a
// command may call it earlier. Thread-safe.
void install_interrupt_cleanup();

// How many temporaries (files and staging directories) are registered now,
// for tests.
size_t live_temporaries();
// What the signal handler does before it re-raises: removes every registered
// temporary now (the registrations stay). For tests only.
void remove_live_temporaries_for_test();

}  // namespace svo::files
