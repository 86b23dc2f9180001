// Atomic replacement of an output file: the bytes go to a temporary file in
// the same directory, which is flushed to disk and renamed over the final
// name, so that a crash or an error never leaves a partial file under that
// name nor destroys the file that was there. Internal to svo_render.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

namespace svo::render::detail {

// Calls `write(temporary)`, which must create and fully write the file named
// `temporary` (`path` + ".tmp-<pid>-<n>", in the same directory) and close
// it; then fsyncs it, renames it over `path` and fsyncs the directory (best
// effort). Whatever `write` throws, or any failure after it, removes the
// temporary and leaves `path` as it was.
// @throw std::runtime_error "<path>: cannot write: <step>: <reason>" for the
//        steps done here; exceptions of `write` pass through unchanged.
void write_atomically(const std::string& path, const std::function<void(const std::string& temporary)>& write);

// write_atomically of `size` bytes at `data`.
// @throw std::runtime_error "<path>: cannot write <temporary>: <reason>", or
//        write_atomically's
void write_bytes_atomically(const std::string& path, const void* data, size_t size);

// What a path that is not a regular file is, for messages: "a directory",
// "a FIFO", "a character device", "a block device", "a socket", or "not a
// regular file".
std::string file_kind(std::filesystem::file_type type);

}  // namespace svo::render::detail
