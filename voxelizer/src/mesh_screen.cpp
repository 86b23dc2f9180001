// Screening of mesh files before OpenMesh reads them (mesh_screen.h).
#include "mesh_screen.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "svo/octree/files.h"
#include "svo/voxelizer/mesh.h"

namespace svo::voxelizer::screen {

namespace {

const std::string kCorners = std::to_string(kMaxPolygonCorners);
const std::string kTriangles = std::to_string(int64_t(kMaxMeshTriangles));

// ---- PLY. Every element needs at least one byte: a count above the file's
// size is refused before any reader reserves memory for it. OpenMesh loops
// over a list's count as read, so a count of garbage made it push gigabytes
// of handles (found by the mesh_file fuzz target; a binary count of -1 ran
// 95 s to 4.2 GB): both bodies are walked, every list count checked.

struct Property {
  std::string name;
  bool list = false;
  std::string count_type, type;  // count_type: lists only
};
struct Element {
  std::string name;
  int64_t count = 0;
  std::vector<Property> properties;
};

size_t type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "double" || t == "float64") return 8;
  return 4;
}
bool is_integer_type(const std::string& t) { return t != "float" && t != "float32" && t != "double" && t != "float64"; }
bool is_signed_type(const std::string& t) {
  return t == "char" || t == "int8" || t == "short" || t == "int16" || t == "int" || t == "int32";
}
// The list OpenMesh reads a face's corners from.
bool is_face_corners(const Element& e, const Property& p) {
  return e.name == "face" && p.list && (p.name == "vertex_indices" || p.name == "vertex_index");
}

// The body of an ASCII PLY, one line per element. Each line: one number
// per scalar property, for a list a count from 0 to kMaxPolygonCorners then
// that many numbers; a face's corners: 3 or more vertex indices below
// `vertices`; nothing else.
std::string screen_ply_ascii_body(std::istream& in, const std::vector<Element>& declared, int header_lines,
                                  int64_t vertices, double& triangles, FilePolygons* polygons) {
  std::string line;
  size_t number = size_t(header_lines);
  auto is_number = [](const std::string& t) {
    char* end = nullptr;
    std::strtod(t.c_str(), &end);
    return !t.empty() && end == t.c_str() + t.size();
  };
  for (const Element& e : declared) {
    for (int64_t i = 0; i < e.count; ++i) {
      if (!std::getline(in, line)) return "PLY file ends before its elements";
      ++number;
      std::istringstream words(line);
      std::vector<std::string> w;
      for (std::string word; words >> word;) w.push_back(word);
      const std::string where = "PLY line " + std::to_string(number) + ": ";
      size_t at = 0;
      for (const Property& p : e.properties) {
        if (at >= w.size()) return where + "fewer values than the element's properties";
        if (!p.list) {
          if (!is_number(w[at])) return where + "'" + w[at].substr(0, 40) + "' is not a number";
          ++at;
          continue;
        }
        const std::string& c = w[at];
        if (c.empty() || c.size() > 4 || c.find_first_not_of("0123456789") != std::string::npos ||
            std::stoi(c) > kMaxPolygonCorners) {
          return where + "a list count '" + c.substr(0, 40) + "' is not an integer from 0 to " + kCorners;
        }
        const size_t k = size_t(std::stoi(c));
        at += 1 + k;
        if (at > w.size()) return where + "fewer list values than its count";
        const bool corners = is_face_corners(e, p);
        if (corners && k < 3) return where + "a face of " + c + " corners (at least 3)";
        for (size_t j = at - k; j < at; ++j) {
          if (!is_number(w[j])) return where + "'" + w[j].substr(0, 40) + "' is not a number";
          if (!corners) continue;
          if (w[j].size() > 12 || w[j].find_first_not_of("0123456789") != std::string::npos) {
            return where + "corner '" + w[j].substr(0, 40) + "' is not a vertex index";
          }
          if (std::stoll(w[j]) >= vertices) {
            return where + "a face refers to vertex " + w[j] + ", but the file has " + std::to_string(vertices) +
                   " vertices";
          }
        }
        if (!corners) continue;
        if ((triangles += double(k) - 2) > kMaxMeshTriangles) {
          return where + "more than " + kTriangles + " triangles (the limit of the mesh readers)";
        }
        if (polygons && k > 3) {
          std::vector<int> c(k);
          for (size_t j = 0; j < k; ++j) c[j] = int(std::stoll(w[at - k + j]));
          polygons->add(std::move(c), {});
        } else if (polygons) {
          polygons->add_triangle();
        }
      }
      if (at != w.size()) return where + "more values than the element's properties";
    }
  }
  return "";
}

// A binary PLY body read through a buffer, in the file's byte order; never
// past the `left` bytes the file holds after its header.
class BinaryBody {
 public:
  BinaryBody(std::istream& in, uint64_t left, bool big_endian) : in_(in), left_(left), big_(big_endian) {}

  // False when the file ends first.
  bool skip(uint64_t n) {
    const uint64_t buffered = end_ - at_;
    if (n <= buffered) {
      at_ += size_t(n);
      return true;
    }
    n -= buffered;
    at_ = end_ = 0;
    if (n > left_) return false;
    in_.seekg(std::streamoff(n), std::ios::cur);
    left_ -= n;
    return bool(in_);
  }

  // An integer of PLY type `type`; false when the file ends first.
  bool integer(const std::string& type, int64_t& value) {
    const size_t size = type_size(type);
    if (end_ - at_ < size && !refill(size)) return false;
    const unsigned char* p = buffer_.data() + at_;
    at_ += size;
    uint64_t u = 0;
    for (size_t i = 0; i < size; ++i) u |= uint64_t(p[i]) << (8 * (big_ ? size - 1 - i : i));
    if (is_signed_type(type) && size < 8 && ((u >> (8 * size - 1)) & 1)) u |= ~uint64_t(0) << (8 * size);
    value = int64_t(u);
    return true;
  }

 private:
  bool refill(size_t need) {
    std::memmove(buffer_.data(), buffer_.data() + at_, end_ - at_);
    end_ -= at_;
    at_ = 0;
    const size_t want = size_t(std::min<uint64_t>(buffer_.size() - end_, left_));
    in_.read(reinterpret_cast<char*>(buffer_.data() + end_), std::streamsize(want));
    const size_t got = size_t(std::max<std::streamsize>(0, in_.gcount()));
    end_ += got;
    left_ -= got;
    return end_ >= need;
  }

  std::istream& in_;
  uint64_t left_;
  bool big_;
  std::vector<unsigned char> buffer_ = std::vector<unsigned char>(size_t(1) << 16);
  size_t at_ = 0, end_ = 0;
};

// The body of a binary PLY, walked with its property sizes: elements
// without lists are skipped whole; in the others, every list count from 0
// to kMaxPolygonCorners, a face's corners 3 or more vertex indices below
// `vertices`, and the bytes there.
std::string screen_ply_binary_body(std::istream& in, const std::vector<Element>& declared, bool big_endian,
                                   uintmax_t file_bytes, int64_t vertices, double& triangles, FilePolygons* polygons) {
  const std::streamoff start = in.tellg();
  if (start < 0 || uintmax_t(start) > file_bytes) return "PLY file ends in its header";
  BinaryBody body(in, file_bytes - uintmax_t(start), big_endian);
  std::vector<int> corners;
  for (const Element& e : declared) {
    const std::string ends = "PLY file ends inside " + e.name.substr(0, 40) + " ";
    uint64_t row = 0;
    bool lists = false;
    for (const Property& p : e.properties) lists = lists || p.list, row += p.list ? 0 : type_size(p.type);
    if (!lists) {
      if (!body.skip(row * uint64_t(e.count))) {
        return "PLY file ends inside its " + e.name.substr(0, 40) + " elements (" + std::to_string(e.count) + " of " +
               std::to_string(row) + " bytes)";
      }
      continue;
    }
    for (int64_t i = 0; i < e.count; ++i) {
      const std::string where = "PLY " + e.name.substr(0, 40) + " " + std::to_string(i) + ": ";
      for (const Property& p : e.properties) {
        if (!p.list) {
          if (!body.skip(type_size(p.type))) return ends + std::to_string(i);
          continue;
        }
        int64_t k = 0;
        if (!body.integer(p.count_type, k)) return ends + std::to_string(i);
        if (k < 0 || k > kMaxPolygonCorners) {
          return where + "a list count of " + std::to_string(k) + " (from 0 to " + kCorners + ")";
        }
        if (!is_face_corners(e, p)) {
          if (!body.skip(uint64_t(k) * type_size(p.type))) return ends + std::to_string(i);
          continue;
        }
        if (k < 3) return where + "a face of " + std::to_string(k) + " corners (at least 3)";
        corners.clear();
        for (int64_t j = 0; j < k; ++j) {
          int64_t v = 0;
          if (!body.integer(p.type, v)) return ends + std::to_string(i);
          if (v < 0 || v >= vertices) {
            return where + "refers to vertex " + std::to_string(v) + ", but the file has " + std::to_string(vertices) +
                   " vertices";
          }
          if (polygons && k > 3) corners.push_back(int(v));
        }
        if ((triangles += double(k) - 2) > kMaxMeshTriangles) {
          return where + "more than " + kTriangles + " triangles (the limit of the mesh readers)";
        }
        if (polygons && k > 3) {
          polygons->add(corners, {});
        } else if (polygons) {
          polygons->add_triangle();
        }
      }
    }
  }
  return "";
}

// "" when the PLY header and body are ones OpenMesh can be given, else the
// problem.
std::string screen_ply(std::istream& in, uintmax_t file_bytes, double& triangles, FilePolygons* polygons) {
  static const std::set<std::string> kTypes = {"char",  "uchar",  "short",   "ushort", "int",   "uint",
                                               "float", "double", "int8",    "uint8",  "int16", "uint16",
                                               "int32", "uint32", "float32", "float64"};
  std::string line;
  bool elements = false, ascii = false, big_endian = false;
  std::vector<Element> declared;
  for (int number = 1; number <= 1000 && std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = "PLY header line " + std::to_string(number) + ": ";
    for (char c : line) {
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t') return where + "a control character";
    }
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string word; words >> word;) w.push_back(word);
    if (number == 1) {
      if (w.size() != 1 || w[0] != "ply") return "not a PLY file (no 'ply' line)";
      continue;
    }
    if (number == 2) {
      if (w.size() != 3 || w[0] != "format" ||
          (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") || w[2] != "1.0") {
        return where + "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'";
      }
      ascii = w[1] == "ascii";
      big_endian = w[1] == "binary_big_endian";
      continue;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      if (!elements) return where + "no element";
      int64_t vertices = 0;
      for (const Element& e : declared) {
        if (e.name == "vertex") vertices = e.count;
      }
      return ascii ? screen_ply_ascii_body(in, declared, number, vertices, triangles, polygons)
                   : screen_ply_binary_body(in, declared, big_endian, file_bytes, vertices, triangles, polygons);
    }
    if (w[0] == "element") {
      if (w.size() != 3 || w[2].empty() || w[2].size() > 12 ||
          w[2].find_first_not_of("0123456789") != std::string::npos) {
        return where + "expected 'element NAME COUNT'";
      }
      if (std::stod(w[2]) > double(file_bytes)) {
        return where + "element " + w[1] + " claims " + w[2] + " entries, more than the file's " +
               std::to_string(file_bytes) + " bytes can hold";
      }
      elements = true;
      declared.push_back({w[1], int64_t(std::stod(w[2])), {}});
      continue;
    }
    if (w[0] == "property") {
      if (!elements) return where + "a property before any element";
      const bool scalar = w.size() == 3 && kTypes.count(w[1]);
      const bool list = w.size() == 5 && w[1] == "list" && kTypes.count(w[2]) && kTypes.count(w[3]);
      if (!scalar && !list) return where + "expected 'property TYPE NAME' or 'property list TYPE TYPE NAME'";
      Property p = list ? Property{w[4], true, w[2], w[3]} : Property{w[2], false, "", w[1]};
      if (list && !is_integer_type(p.count_type)) return where + "a list's count must be of an integer type";
      if (is_face_corners(declared.back(), p) && !is_integer_type(p.type)) {
        return where + "a face's vertex indices must be of an integer type";
      }
      declared.back().properties.push_back(p);
      continue;
    }
    return where + "unknown keyword '" + w[0].substr(0, 40) + "'";
  }
  return "PLY header without end_header in its first 1000 lines";
}

// OFF: a first line OpenMesh reads as it means it ([ST][C][N][4][n]OFF and
// nothing else), and counts that are plain non-negative integers no larger
// than the file: OpenMesh reads "-5" into an unsigned count and reserves
// memory for it (16 GiB, found by the mesh_file fuzz target). Binary OFF is
// refused (its counts' byte order is OpenMesh's guess).
std::string screen_off(std::istream& in, uintmax_t file_bytes, double& triangles, std::string& own_reader,
                       bool& polygons) {
  // Comment and blank lines may come before the keyword (CGAL writes them).
  std::string first;
  size_t skipped = 0;
  while (std::getline(in, first)) {
    if (!first.empty() && first.back() == '\r') first.pop_back();
    const size_t text = first.find_first_not_of(" \t");
    if (text != std::string::npos && first[text] != '#') break;
    ++skipped;
    first.clear();
  }
  size_t at = 0;
  for (const char* prefix : {"ST", "C", "N", "4", "n"}) {
    if (first.compare(at, std::strlen(prefix), prefix) == 0) at += std::strlen(prefix);
  }
  if (first.compare(at, 3, "OFF") != 0) return "";  // not OFF: OpenMesh's OFF reader will not take it
  const std::string rest = first.substr(at + 3);
  if (rest.find("BINARY") != std::string::npos) return "binary OFF is not supported (use ASCII OFF, PLY or OBJ)";
  if (rest.find_first_not_of(" \t") != std::string::npos) return "OFF header: unexpected text after the keyword";
  double counts[3] = {0, 0, 0};
  for (double& c : counts) {
    std::string word;
    // Comments may sit between the keyword and the counts.
    while (in >> word && word[0] == '#') in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    if (word.empty() || word.size() > 12 || word.find_first_not_of("0123456789") != std::string::npos) {
      return "OFF header: expected the vertex, face and edge counts as non-negative integers";
    }
    c = std::stod(word);
  }
  if (counts[0] + counts[1] > double(file_bytes)) {
    return "OFF header claims " + std::to_string(int64_t(counts[0])) + " vertices and " +
           std::to_string(int64_t(counts[1])) + " faces, more than the file's " + std::to_string(file_bytes) +
           " bytes can hold";
  }
  // The body, line by line: OpenMesh loops over a face's corner count as
  // read, so "111...1" (an overflow: 2^32 - 1) made it push 4 GiB of
  // handles (found by the mesh_file fuzz target). Vertex lines: 3 or more
  // numbers; face lines: a count K in [1, 1000], then K indices in
  // [0, vertices), then at most 4 colour numbers; blank and # lines skipped.
  in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  const int64_t vertices = int64_t(counts[0]), faces = int64_t(counts[1]);
  std::string line;
  int64_t seen_vertices = 0, seen_faces = 0;
  for (size_t number = 3 + skipped; seen_faces < faces && std::getline(in, line); ++number) {
    // A comment runs from # to the end of the line, also where it follows a
    // number without a space ("0.9 0 0#red", which OpenMesh would misread:
    // such a file goes to svo's own reader).
    if (const size_t hash = line.find('#'); hash != std::string::npos) {
      if (hash > 0 && !std::isspace(static_cast<unsigned char>(line[hash - 1])) && own_reader.empty()) {
        own_reader = "comments glued to numbers";
      }
      line.erase(hash);
    }
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string word; words >> word && word[0] != '#';) w.push_back(word);
    if (w.empty()) continue;
    const std::string where = "OFF line " + std::to_string(number) + ": ";
    auto is_number = [](const std::string& t) {
      char* end = nullptr;
      std::strtod(t.c_str(), &end);
      return end == t.c_str() + t.size();
    };
    auto is_index = [](const std::string& t, int64_t below) {
      return !t.empty() && t.size() <= 10 && t.find_first_not_of("0123456789") == std::string::npos &&
             std::stoll(t) < below;
    };
    if (seen_vertices < vertices) {
      if (w.size() < 3) return where + "a vertex needs 3 coordinates";
      for (const auto& t : w) {
        if (!is_number(t)) return where + "'" + t.substr(0, 40) + "' is not a number";
      }
      ++seen_vertices;
      continue;
    }
    if (!is_index(w[0], kMaxPolygonCorners + 1) || w[0] == "0") {
      return where + "a face starts with its corner count, 1 to " + kCorners;
    }
    const size_t k = size_t(std::stoll(w[0]));
    if (w.size() < 1 + k || w.size() > 1 + k + 4)
      return where + "expected " + w[0] + " corners (and up to 4 colour numbers)";
    for (size_t i = 1; i <= k; ++i) {
      if (!is_index(w[i], vertices)) return where + "corner '" + w[i].substr(0, 40) + "' is not a vertex index";
    }
    for (size_t i = k + 1; i < w.size(); ++i) {
      if (!is_number(w[i])) return where + "'" + w[i].substr(0, 40) + "' is not a number";
    }
    if (w.size() > 1 + k) own_reader = "faces with colours";
    polygons = polygons || k > 3;
    if ((triangles += double(k) - 2) > kMaxMeshTriangles) {
      return where + "more than " + kTriangles + " triangles (the limit of the mesh readers)";
    }
    ++seen_faces;
  }
  if (seen_vertices < vertices || seen_faces < faces) return "OFF file ends before its vertices and faces";
  if (skipped > 0 && own_reader.empty()) own_reader = "comment lines before the OFF keyword";
  return "";
}

// ---- OBJ. OpenMesh 9.0 asserts (aborts) on a face line whose corners it
// cannot parse (found by the mesh_file fuzz target), drops a vertex whose
// coordinates its `stream >> float` cannot read ("nan", "inf", 1e39) and
// with it every face that names a later vertex, drops faces whose indices
// name no vertex, all without a word, and spends time quadratic in a face's
// corners (100k corners: 21 s).

// [-]DIGITS at t[at] into `value` (0 when absent): false when absent
// (unless optional), zero or longer than 9 digits.
bool obj_index(const std::string& t, size_t& at, bool optional, long& value) {
  value = 0;
  const size_t start = at;
  if (at < t.size() && t[at] == '-') ++at;
  const size_t digits = at;
  while (at < t.size() && std::isdigit(static_cast<unsigned char>(t[at]))) ++at;
  const size_t n = at - digits;
  if (n == 0) return optional && at == start;
  if (n > 9) return false;
  value = std::stol(t.substr(digits, n));
  if (start != digits) value = -value;
  return value != 0;
}

// Vertex lines: three numbers OpenMesh reads. Face lines: 3 to kMaxPolygonCorners
// corners V, V/T, V//N or V/T/N with V and T non-zero integers naming a
// vertex and a texture coordinate of the file (negative: counted back from
// the line). "vc" lines are refused (below).
std::string screen_obj(std::istream& in, double& triangles, bool& polygons) {
  // First pass: the vertices and texture coordinates a positive index may name.
  long vertices = 0, uvs = 0;
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword) || (keyword != "v" && keyword != "vt")) continue;
    // Read as OpenMesh reads them (`stream >> float`, which stops at a
    // character that cannot continue a number: "0.5/1" reads as 0.5). It
    // drops a vertex whose coordinates fail ("nan", "inf", 1e39), and
    // every face naming a later vertex then names the wrong one.
    const int needed = keyword == "v" ? 3 : 2;
    for (int k = 0; k < needed; ++k) {
      const std::streampos at = words.tellg();
      float value = 0;
      if (words >> value) continue;
      words.clear();
      words.seekg(at);
      std::string t;
      if (!(words >> t)) {
        return "OBJ line " + std::to_string(number) + ": " +
               (keyword == "v" ? "a vertex needs 3 coordinates" : "a texture coordinate needs 2 numbers");
      }
      return "OBJ line " + std::to_string(number) + ": " + (keyword == "v" ? "vertex" : "texture") + " coordinate '" +
             t.substr(0, 40) + "' is not a finite number";
    }
    ++(keyword == "v" ? vertices : uvs);
  }
  in.clear();
  in.seekg(0);
  long seen_vertices = 0, seen_uvs = 0;
  for (size_t number = 1; std::getline(in, line); ++number) {
    // OpenMesh reads the keyword as the first word, whatever space precedes it.
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword)) continue;
    const std::string where = "OBJ line " + std::to_string(number) + ": ";
    // OpenMesh's non-standard "vc" line colours the last vertex it read,
    // whether or not there is one (a null reference, found by the
    // mesh_file fuzz target): refused.
    if (keyword == "vc") return where + "'vc' vertex colour lines are not supported (give colours as 'v X Y Z R G B')";
    if (keyword == "v") ++seen_vertices;
    if (keyword == "vt") ++seen_uvs;
    if (keyword != "f") continue;
    // A corner's index into `count` items, `seen` of them before this line.
    auto names = [&](long index, long count, long seen, const char* what, const char* whats,
                     const std::string& t) -> std::string {
      if (index > 0 && index > count) {
        return where + "face corner '" + t.substr(0, 40) + "' refers to " + what + " " + std::to_string(index) +
               ", but the file has " + std::to_string(count) + " " + whats + " (counted from 1)";
      }
      if (index < 0 && -index > seen) {
        return where + "face corner '" + t.substr(0, 40) + "' refers to " + what + " " + std::to_string(index) +
               ", but " + std::to_string(seen) + " " + whats + " precede the line";
      }
      return "";
    };
    int corners = 0;
    for (std::string t; words >> t; ++corners) {
      if (t[0] == '#') break;  // a comment ends the line
      if (corners >= kMaxPolygonCorners) {
        return where + "a face of more than " + kCorners + " corners (the limit of the mesh readers)";
      }
      size_t at = 0;
      long v = 0, uv = 0, normal = 0;
      bool ok = obj_index(t, at, false, v);
      if (ok && at < t.size() && t[at] == '/') {
        ++at;
        ok = obj_index(t, at, true, uv);
        if (ok && at < t.size() && t[at] == '/') ++at, ok = obj_index(t, at, true, normal);
      }
      if (!ok || at != t.size()) return where + "face corner '" + t.substr(0, 40) + "' is not V, V/T, V//N or V/T/N";
      if (std::string why = names(v, vertices, seen_vertices, "vertex", "vertices", t); !why.empty()) return why;
      // (Without "vt" lines OpenMesh reads no texture coordinates at all.)
      if (std::string why = names(uvs ? uv : 0, uvs, seen_uvs, "texture coordinate", "texture coordinates", t);
          !why.empty())
        return why;
    }
    if (corners < 3) return where + "a face needs 3 corners";
    polygons = polygons || corners > 3;
    if ((triangles += corners - 2) > kMaxMeshTriangles) {
      return where + "more than " + kTriangles + " triangles (the limit of the mesh readers)";
    }
  }
  return "";
}

// ---- STL. Binary when the file is exactly 84 + 50 n bytes for the count n
// in bytes 80-83 (OpenMesh's own test), else ASCII: its "facet" keywords
// counted. A binary file of more triangles than the budget would make
// OpenMesh reserve them all before reading one.
std::string screen_stl(std::istream& in, uintmax_t file_bytes, double& triangles) {
  if (file_bytes >= 84) {
    char header[84];
    if (in.read(header, 84)) {
      uint32_t n = 0;
      std::memcpy(&n, header + 80, 4);  // little-endian, as the format says (and this host)
      if (84 + 50 * uintmax_t(n) == file_bytes) {
        triangles = double(n);
        return double(n) > kMaxMeshTriangles ? "binary STL of " + std::to_string(n) + " triangles, more than " +
                                                   kTriangles + " (the limit of the mesh readers)"
                                             : "";
      }
    }
    in.clear();
    in.seekg(0);
  }
  for (std::string word; in >> word;) {
    if (word == "facet" && ++triangles > kMaxMeshTriangles) {
      return "ASCII STL of more than " + kTriangles + " triangles (the limit of the mesh readers)";
    }
  }
  return "";
}

}  // namespace

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string screen_mesh_file(const std::string& path, double* triangles, std::string* own_reader, bool* polygons,
                             FilePolygons* ply_polygons) {
  if (triangles) *triangles = -1;
  if (polygons) *polygons = false;
  if (own_reader) own_reader->clear();
  const std::string ext = lower_extension(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";  // OpenMesh reports it
  std::error_code error;
  const uintmax_t bytes = std::filesystem::file_size(path, error);
  if (error) return "";
  double counted = 0;
  std::string own;
  bool any_polygon = false;
  std::string why;
  if (ext == ".ply") {
    FilePolygons found;
    why = screen_ply(in, bytes, counted, ply_polygons ? &found : nullptr);
    if (ply_polygons && why.empty()) *ply_polygons = std::move(found);
  } else if (ext == ".off") {
    why = screen_off(in, bytes, counted, own, any_polygon);
  } else if (ext == ".obj") {
    why = screen_obj(in, counted, any_polygon);
  } else if (ext == ".stl") {
    why = screen_stl(in, bytes, counted);
  } else {
    return "";
  }
  if (triangles && why.empty()) *triangles = counted;
  if (own_reader && why.empty()) *own_reader = own;
  if (polygons && why.empty()) *polygons = any_polygon;
  return why;
}

void check_obj_material_files(const std::string& path, const std::function<void(const std::string&)>& warning) {
  namespace fs = std::filesystem;
  // OpenMesh opens the rest of the line after its directory's text (up to
  // the last '/'); read_mtl_materials each word relative to the OBJ.
  const size_t slash = path.rfind('/');
  const std::string openmesh_dir = slash == std::string::npos ? "./" : path.substr(0, slash + 1);
  const fs::path dir = fs::path(path).parent_path();
  std::set<std::string> checked;
  auto check = [&](const std::string& file, bool ours) {
    if (!checked.insert(file).second) return;
    std::error_code error;
    if (fs::status(file, error).type() == fs::file_type::not_found) {
      if (ours && warning) warning(path + ": mtllib " + file + " does not exist: its materials are not used");
      return;
    }
    uintmax_t bytes = 0;
    try {
      bytes = files::require_regular_file(file, "an MTL material file");
    } catch (const files::FileError& e) {
      throw std::runtime_error(path + ": mtllib " + e.what());
    }
    if (bytes > kMaxMtlBytes) {
      throw std::runtime_error(path + ": mtllib " + file + ": " + std::to_string(bytes) +
                               " bytes, more than the limit of 16 MiB for an MTL material file");
    }
  };
  std::ifstream in(path, std::ios::binary);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword) || keyword != "mtllib") continue;
    std::string rest;
    std::getline(words, rest);
    const size_t first = rest.find_first_not_of(" \t\r\n"), last = rest.find_last_not_of(" \t\r\n");
    if (first == std::string::npos) continue;
    std::istringstream names(rest);
    for (std::string name; names >> name;) check((dir / name).string(), true);
    check(openmesh_dir + rest.substr(first, last - first + 1), false);
  }
}

}  // namespace svo::voxelizer::screen
