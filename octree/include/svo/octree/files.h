// Files the engine opens and writes, for every library and command: inputs
// checked to be regular files before any library sees them (a FIFO, a
// device or a directory named as an input would hang or eat memory), text
// read with a bound, and outputs replaced atomically (see OutputFile).
#pragma once

#include <cstdint>
#include <filesystem>
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
