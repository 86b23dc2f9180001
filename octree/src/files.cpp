#include "svo/octree/files.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

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

}  // namespace svo::files
