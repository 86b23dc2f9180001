// svo info: what a .svo file holds (levels, nodes, bricks, voxels, bytes per
// voxel, channels, bounds), after validating all of it. A bad file is one
// line on stderr and exit code 1 (FileError reaches main()).
#include <charconv>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "svo/octree/svo_file.h"

namespace svo::tools {

namespace {

struct InfoOptions {
  std::string path;
  bool json = false;
};

struct Level {
  uint32_t resolution = 0;
  float voxel_size = 0;
  uint64_t nodes = 0, bricks = 0;
};

std::vector<Level> levels_of(const octree::SvoView& svo) {
  const octree::Octree& shape = svo.shape();
  std::vector<Level> levels(shape.depth_count);
  for (uint32_t d = 0; d < shape.depth_count; ++d) {
    Level& l = levels[d];
    l.resolution = shape.brick_size << d;
    l.voxel_size = shape.voxel_size(d);
    auto nodes =
        svo.nodes().subspan(shape.depth_first_node[d], shape.depth_first_node[d + 1] - shape.depth_first_node[d]);
    l.nodes = nodes.size();
    for (const octree::Node& n : nodes) l.bricks += n.brick != octree::kNone;
  }
  return levels;
}

// A float as the shortest decimal that reads back as the same float, so that
// JSON shows 0.2 rather than 0.20000000298023224.
double json_float(float v) {
  char text[32];
  auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::strtod(std::string(text, end).c_str(), nullptr);
}

std::string bytes_text(uint64_t bytes) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(1);
  if (bytes < 1024) return std::to_string(bytes) + " B";
  if (bytes < (uint64_t(1) << 20)) return (s << bytes / 1024.0 << " KiB", s.str());
  if (bytes < (uint64_t(1) << 30)) return (s << bytes / 1048576.0 << " MiB", s.str());
  return (s << bytes / 1073741824.0 << " GiB", s.str());
}

void print_json(const octree::SvoView& svo, const std::vector<Level>& levels) {
  const octree::Octree& shape = svo.shape();
  nlohmann::json channels = nlohmann::json::array();
  for (size_t c = 0; c < shape.channels.size(); ++c) {
    const auto& info = shape.channels[c];
    channels.push_back({{"name", octree::channel_name(info.channel)},
                        {"encoding", octree::encoding_name(info.encoding)},
                        {"bytes_per_sample", octree::encoding_bytes(info.encoding)},
                        {"bytes", svo.brick_data(c).size()}});
  }
  nlohmann::json per_level = nlohmann::json::array();
  for (size_t d = 0; d < levels.size(); ++d) {
    per_level.push_back({{"depth", d},
                         {"resolution", levels[d].resolution},
                         {"voxel_size", json_float(levels[d].voxel_size)},
                         {"nodes", levels[d].nodes},
                         {"bricks", levels[d].bricks}});
  }
  const uint64_t voxels = svo.voxel_count();
  nlohmann::json out{
      {"file", svo.name()},
      {"version", svo.version()},
      {"levels", shape.depth_count},
      {"brick_size", shape.brick_size},
      {"resolution", shape.finest_resolution()},
      {"origin", {json_float(shape.origin.x), json_float(shape.origin.y), json_float(shape.origin.z)}},
      {"size", json_float(shape.size)},
      {"sigma_rho2", json_float(shape.sigma_rho2)},
      {"constant_colour",
       {json_float(shape.constant_colour.x), json_float(shape.constant_colour.y), json_float(shape.constant_colour.z)}},
      {"nodes", svo.nodes().size()},
      {"bricks", svo.brick_count()},
      {"shells", shape.shell_count},
      {"voxels", voxels},
      {"bytes", svo.file_bytes()},
      {"bytes_per_voxel", nullptr},
      {"channels", channels},
      {"per_level", per_level},
      {"materials", shape.materials},
      {"source", nullptr},
      {"detail", nullptr}};
  if (!shape.source.empty()) {
    // The voxelizer's JSON; a text that is not JSON (the file may come from
    // anywhere) is shown as it is.
    nlohmann::json source = nlohmann::json::parse(shape.source, nullptr, false);
    out["source"] = source.is_discarded() ? nlohmann::json(shape.source) : source;
  }
  if (const octree::Detail& d = shape.detail; d.octaves > 0) {
    out["detail"] = {
        {"octaves", d.octaves},
        {"seed", d.seed},
        {"amplitude", json_float(d.amplitude)},
        {"wavelength", json_float(d.wavelength)},
        {"gain", json_float(d.gain)},
        {"colour_slope", {json_float(d.colour_slope.x), json_float(d.colour_slope.y), json_float(d.colour_slope.z)}}};
  }
  if (voxels > 0) out["bytes_per_voxel"] = double(svo.file_bytes()) / double(voxels);
  // Texts from the file (materials, source) may hold any bytes: invalid
  // UTF-8 is replaced, not thrown on.
  std::cout << out.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
}

// Control characters of a text from the file as '?', so that it cannot
// drive the terminal.
std::string printable(std::string s) {
  for (char& c : s)
    if ((unsigned char)c < 0x20 || c == 0x7f) c = '?';
  return s;
}

// Where the octree came from (the voxelizer's JSON: input and settings, and
// what it decided about the surface); a text that is not that JSON as it is.
template <class Row>
void print_source(const std::string& text, Row& row) {
  if (text.empty()) {
    row("source") << "not recorded (written before svo recorded it, or not by svo voxelize)\n";
    return;
  }
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object() || !j.contains("input") || !j["input"].is_string()) {
    row("source") << printable(text) << "\n";
    return;
  }
  row("source") << printable(j["input"].get<std::string>());
  if (j.contains("resolution") && j["resolution"].is_number()) std::cout << " at " << j["resolution"].dump() << "^3";
  std::cout << "\n";
  if (j.contains("surface") && j["surface"].is_string()) {
    row("surface") << printable(j["surface"].get<std::string>()) << "\n";
  }
}

void print_text(const octree::SvoView& svo, const std::vector<Level>& levels) {
  const octree::Octree& shape = svo.shape();
  const uint64_t voxels = svo.voxel_count();
  const glm::vec3 lo = shape.origin, hi = shape.origin + glm::vec3(shape.size);
  auto row = [](const char* key) -> std::ostream& { return std::cout << std::left << std::setw(17) << key; };
  row("levels") << shape.depth_count << "\n";
  row("brick_size") << shape.brick_size << " (" << shape.samples_per_edge() << "^3 samples per brick)\n";
  row("resolution") << shape.finest_resolution() << "^3 at the finest level\n";
  row("bounds") << "[" << lo.x << ", " << lo.y << ", " << lo.z << "] to [" << hi.x << ", " << hi.y << ", " << hi.z
                << "] (size " << shape.size << ")\n";
  row("nodes") << svo.nodes().size() << "\n";
  row("bricks") << svo.brick_count() << " (" << shape.shell_count << " on the domain's upper boundary, with shells)\n";
  row("voxels") << voxels << "\n";
  row("bytes") << svo.file_bytes() << " (" << bytes_text(svo.file_bytes()) << ")\n";
  std::ostringstream per_voxel;
  per_voxel << std::fixed << std::setprecision(3) << double(svo.file_bytes()) / double(voxels);
  row("bytes_per_voxel") << (voxels > 0 ? per_voxel.str() : "n/a (no voxels)") << "\n";
  row("sigma_rho2") << shape.sigma_rho2 << "\n";
  if (const octree::Detail& d = shape.detail; d.octaves > 0) {
    row("detail") << d.octaves << " octaves of wavelength " << d.wavelength << " / 2^k, amplitude " << d.amplitude
                  << " x " << d.gain << "^k, seed " << d.seed << "; colour per unit height " << d.colour_slope.x << ", "
                  << d.colour_slope.y << ", " << d.colour_slope.z << "\n";
  } else {
    row("detail") << "none\n";
  }
  row("materials") << (shape.materials.empty() ? std::string("none (the renderer's --material or built-in one)")
                                               : std::to_string(shape.materials.size()))
                   << "\n";
  for (const std::string& m : shape.materials) std::cout << "  " << m << "\n";
  print_source(shape.source, row);
  row("channels") << shape.channels.size() << "\n";
  for (size_t c = 0; c < shape.channels.size(); ++c) {
    const auto& info = shape.channels[c];
    std::cout << "  " << std::left << std::setw(15) << octree::channel_name(info.channel) << std::setw(17)
              << octree::encoding_name(info.encoding) << octree::encoding_bytes(info.encoding) << " B/sample, "
              << bytes_text(svo.brick_data(c).size()) << "\n";
  }
  std::cout << std::right << "level  resolution   voxel_size        nodes       bricks\n";
  for (size_t d = 0; d < levels.size(); ++d) {
    std::cout << std::setw(5) << d << std::setw(12) << levels[d].resolution << std::setw(13) << levels[d].voxel_size
              << std::setw(13) << levels[d].nodes << std::setw(13) << levels[d].bricks << "\n";
  }
}

}  // namespace

void add_info_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "info",
      "Describe a .svo file: levels, nodes and bricks per level, voxels, bytes per voxel, channels, bounds.\n"
      "The whole file is validated first (checksums, counts, offsets, tree links)");
  auto opt = std::make_shared<InfoOptions>();
  cmd->add_option("FILE", opt->path, "The .svo file to describe")->required();
  cmd->add_flag("--json", opt->json, "Print one JSON object on stdout");
  cmd->callback([opt, &exit_code] {
    octree::MappedSvo svo(opt->path);
    std::vector<Level> levels = levels_of(svo.view());
    if (opt->json) {
      print_json(svo.view(), levels);
    } else {
      print_text(svo.view(), levels);
    }
    exit_code = 0;
  });
}

}  // namespace svo::tools
