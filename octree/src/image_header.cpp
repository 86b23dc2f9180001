#include "svo/octree/image_header.h"

#include <cstring>
#include <fstream>
#include <utility>
#include <vector>

namespace svo::octree {

namespace {

int32_t le32(const uint8_t* p) {
  uint32_t v = uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
  int32_t s;
  std::memcpy(&s, &v, 4);
  return s;
}

// OpenEXR reads an attribute of a fixed-size type by its type, whatever
// size the file states, and loses its place when the two differ: a
// lineOrder stated as 0 bytes had the next attribute's bytes read as its
// value, and then a string attribute's "size" from the middle of a name
// (1.85 GB allocated for a 358-byte map, found by the environment fuzz
// target). The sizes of OpenEXR 3.1's fixed types.
int32_t fixed_size_of(const std::string& type) {
  static const std::pair<const char*, int32_t> kSizes[] = {{"box2i", 16},
                                                           {"box2f", 16},
                                                           {"chromaticities", 32},
                                                           {"compression", 1},
                                                           {"deepImageState", 1},
                                                           {"double", 8},
                                                           {"envmap", 1},
                                                           {"float", 4},
                                                           {"int", 4},
                                                           {"keycode", 28},
                                                           {"lineOrder", 1},
                                                           {"m33f", 36},
                                                           {"m33d", 72},
                                                           {"m44f", 64},
                                                           {"m44d", 128},
                                                           {"rational", 8},
                                                           {"tiledesc", 9},
                                                           {"timecode", 8},
                                                           {"v2i", 8},
                                                           {"v2f", 8},
                                                           {"v2d", 16},
                                                           {"v3i", 12},
                                                           {"v3f", 12},
                                                           {"v3d", 24}};
  for (const auto& [name, size] : kSizes) {
    if (type == name) return size;
  }
  return -1;
}

// A name from the file for a one-line message: printable ASCII, at most 64 characters.
std::string printable(const std::string& text) {
  std::string out = text.substr(0, 64);
  for (char& c : out) {
    if (c < 0x20 || c > 0x7e) c = '?';
  }
  return out;
}

}  // namespace

std::string check_exr_header(const std::string& path, double max_pixels) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";  // the image library reports it
  // Headers are small; 1 MiB covers any that OpenEXR itself accepts in practice.
  std::vector<uint8_t> b(size_t(1) << 20);
  in.read(reinterpret_cast<char*>(b.data()), std::streamsize(b.size()));
  b.resize(size_t(in.gcount()));
  if (b.size() < 8 || b[0] != 0x76 || b[1] != 0x2f || b[2] != 0x31 || b[3] != 0x01) return "";
  const bool multipart = (b[5] & 0x10) != 0;  // flag bit 12 of the version field
  const std::string malformed = "OpenEXR header truncated or malformed";
  size_t at = 8;
  auto text = [&](std::string& out) {
    const void* end = std::memchr(b.data() + at, 0, b.size() - at);
    if (!end) return false;
    const size_t n = size_t(static_cast<const uint8_t*>(end) - (b.data() + at));
    out.assign(reinterpret_cast<const char*>(b.data() + at), n);
    at += n + 1;
    return true;
  };
  for (int part = 0;; ++part) {
    if (at >= b.size()) return malformed;
    if (multipart && part > 0 && b[at] == 0) return "";  // the empty header ends the list of parts
    bool window = false;
    for (;;) {
      std::string name, type;
      if (!text(name)) return malformed;
      if (name.empty()) break;  // end of this header
      if (!text(type) || at + 4 > b.size()) return malformed;
      const int32_t size = le32(b.data() + at);
      at += 4;
      if (size < 0 || size_t(size) > b.size() - at) return malformed;
      if (const int32_t fixed = fixed_size_of(type); fixed >= 0 && size != fixed) {
        return "OpenEXR attribute '" + printable(name) + "' of type " + type + " states " + std::to_string(size) +
               " bytes; the type has " + std::to_string(fixed);
      }
      if (name == "channels" && type != "chlist") return malformed;
      if (type == "chlist") {
        // Per channel NAME\0, 16 bytes of type and sampling; a final \0,
        // which must be the value's last byte: OpenEXR reads channels up to
        // that \0 whatever size the file states, and one that is missing
        // had it read on into the next attributes (an unknown attribute's
        // stated size, 1.66 GB, then allocated: the environment target).
        int channels = 0;
        size_t c = at;
        for (; c < at + size_t(size) && b[c] != 0; ++channels) {
          const void* end = std::memchr(b.data() + c, 0, at + size_t(size) - c);
          if (!end) return malformed;
          c = size_t(static_cast<const uint8_t*>(end) - b.data()) + 1 + 16;
          if (c > at + size_t(size)) return malformed;
        }
        if (c + 1 != at + size_t(size)) {
          return "OpenEXR attribute '" + printable(name) +
                 "' of type chlist: its channel list does not end where its " + std::to_string(size) + " bytes do";
        }
        if (name == "channels" && channels > kMaxExrChannels) {
          return "OpenEXR image of " + std::to_string(channels) + " channels, more than the limit of " +
                 std::to_string(kMaxExrChannels);
        }
      }
      if (name == "dataWindow") {
        if (type != "box2i" || size != 16) return malformed;
        const int64_t x0 = le32(b.data() + at), y0 = le32(b.data() + at + 4), x1 = le32(b.data() + at + 8),
                      y1 = le32(b.data() + at + 12);
        const int64_t w = x1 - x0 + 1, h = y1 - y0 + 1;
        if (w <= 0 || h <= 0) return "OpenEXR data window is empty";
        // OpenEXR allocates a block of up to 256 whole lines before reading
        // one: the width alone is bounded too.
        if (w > kMaxExrEdge || h > kMaxExrEdge || double(w) * double(h) > max_pixels) {
          return "OpenEXR data window of " + std::to_string(w) + "x" + std::to_string(h) +
                 " pixels, more than the limit of " + std::to_string(kMaxExrEdge) + " a side and " +
                 std::to_string(int64_t(max_pixels)) + " in all";
        }
        window = true;
      }
      at += size_t(size);
    }
    if (!window) return malformed;
    if (!multipart) return "";
  }
}

std::string check_png_chunks(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  static const uint8_t kMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  uint8_t head[8] = {};
  in.read(reinterpret_cast<char*>(head), 8);
  if (in.gcount() != 8 || std::memcmp(head, kMagic, 8) != 0) return "";
  in.seekg(0, std::ios::end);
  const uint64_t bytes = uint64_t(in.tellg());
  uint64_t at = 8;
  for (int chunk = 0; chunk < 1000000; ++chunk) {
    uint8_t h[8];
    in.seekg(std::streamoff(at));
    in.read(reinterpret_cast<char*>(h), 8);
    if (in.gcount() != 8) return "PNG truncated: no IEND chunk";
    const uint64_t length = uint64_t(h[0]) << 24 | uint64_t(h[1]) << 16 | uint64_t(h[2]) << 8 | h[3];
    if (at + 12 + length > bytes) return "PNG truncated in chunk " + std::to_string(chunk + 1);
    if (std::memcmp(h + 4, "IEND", 4) == 0) return "";
    at += 12 + length;
  }
  return "PNG with more than a million chunks";
}

}  // namespace svo::octree
