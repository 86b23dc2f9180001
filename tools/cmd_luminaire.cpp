// svo luminaire: light-field luminaires (DESIGN 10.4, docs/luminaire.md).
// make writes a procedural emitter as a .lfl file, info prints what one
// holds, sheet lays its images out as a contact sheet, import bins an IES
// TM-25 ray file into one.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>

#include "cli_hint.h"
#include "commands.h"
#include "svo/render/image_io.h"
#include "svo/render/luminaire.h"

namespace svo::tools {

namespace {

namespace fs = std::filesystem;

// Refuses an output before any work: it must be named .lfl, its folder
// writable (render::check_writable_output), and a file already there must
// be a light field (the magic), so that a typo never replaces a file of
// another kind.
void check_lfl_output(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext != ".lfl") {
    throw std::invalid_argument(path + ": a light field is written as .lfl, not '" +
                                fs::path(path).extension().string() + "'");
  }
  render::check_writable_output(path);
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) return;
  if (!fs::is_regular_file(status)) throw std::invalid_argument(path + ": exists and is not a regular file");
  char magic[8] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(magic, sizeof magic);
  if (in.gcount() != 8 || std::memcmp(magic, "SVOLFL\0\0", 8) != 0) {
    throw std::invalid_argument(path + ": exists and is not a light field (.lfl): refusing to replace it");
  }
}

struct MakeArgs {
  std::string kind, output;
  uint32_t resolution = 128, grid = 5, checks = 4;
  float radiance = 1000.0f, beam = 0.08f, focus = 0.5f, die = 0.015f;
  uint32_t leds = 3;
};

struct Stats {
  double min = 0, max = 0, mean = 0;  // luminance over every texel of every image
  uint64_t texels = 0;
};

Stats luminance_stats(const render::LightField& f) {
  Stats s;
  s.min = std::numeric_limits<double>::infinity();
  double sum = 0;
  for (const auto& image : f.images) {
    for (size_t t = 0; t < image.size(); t += 3) {
      const double y = 0.2126 * image[t] + 0.7152 * image[t + 1] + 0.0722 * image[t + 2];
      s.min = std::min(s.min, y);
      s.max = std::max(s.max, y);
      sum += y;
      ++s.texels;
    }
  }
  s.mean = s.texels > 0 ? sum / double(s.texels) : 0.0;
  return s;
}

// light_field_flux's samples per texel: 2 x 2 up to a million texels, one
// above (its cost grows with texels x basis support).
uint32_t flux_samples(uint64_t texels) { return texels <= (1u << 20) ? 2 : 1; }

void run_info(const std::string& input, bool json) {
  const render::LightField f = render::load_light_field(input);
  const uint64_t bytes = fs::file_size(input);
  const Stats s = luminance_stats(f);
  const double flux = render::light_field_flux(f, flux_samples(s.texels));
  if (json) {
    nlohmann::json out = {{"file", input},
                          {"bytes", bytes},
                          {"version", render::LightField::kVersion},
                          {"source", f.source},
                          {"units", f.units},
                          {"metres_per_unit", f.metres_per_unit},
                          {"delta", f.delta},
                          {"extent", {f.extent.x, f.extent.y}},
                          {"images", f.image_count()},
                          {"grid", {f.grid_w, f.grid_h}},
                          {"basis", render::luminaire_basis_name(f.basis)},
                          {"spacing", f.spacing},
                          {"resolution", {f.width, f.height}},
                          {"texels", s.texels},
                          {"pose",
                           {{"at", {f.pose.at.x, f.pose.at.y, f.pose.at.z}},
                            {"aim", {f.pose.aim.x, f.pose.aim.y, f.pose.aim.z}},
                            {"size", f.pose.size}}},
                          {"luminance", {{"min", s.min}, {"max", s.max}, {"mean", s.mean}}},
                          {"flux", flux}};
    std::cout << out.dump() << "\n";
    return;
  }
  auto row = [](const char* key) -> std::ostream& { return std::cout << std::left << std::setw(12) << key; };
  row("file") << input << "\n";
  row("bytes") << bytes << "\n";
  row("version") << render::LightField::kVersion << "\n";
  row("source") << (f.source.empty() ? "(none)" : f.source) << "\n";
  row("units") << f.units << " (" << f.metres_per_unit << " m each)\n";
  row("delta") << f.delta << " (from U to S)\n";
  row("extent") << f.extent.x << " x " << f.extent.y << " (plane S)\n";
  row("images") << f.image_count() << "\n";
  row("grid") << f.grid_w << " x " << f.grid_h << " (basis functions on U)\n";
  row("basis") << render::luminaire_basis_name(f.basis) << ", spacing " << f.spacing << "\n";
  row("resolution") << f.width << " x " << f.height << " (texels per image)\n";
  row("texels") << s.texels << " (all images)\n";
  row("pose") << "at " << f.pose.at.x << " " << f.pose.at.y << " " << f.pose.at.z << ", aim " << f.pose.aim.x << " "
              << f.pose.aim.y << " " << f.pose.aim.z << ", size " << f.pose.size << "\n";
  row("luminance") << "min " << s.min << ", max " << s.max << ", mean " << s.mean << "\n";
  row("flux") << flux << " (luminance x " << f.units << "^2, leaving S)\n";
}

// The M images as laid out on U: basis (i, j) in column i and row j from
// the bottom, each image with +y up, 2-pixel gaps; one exposure for all
// (the largest value of any texel maps to 1, so that images compare).
void run_sheet(const std::string& input, const std::string& output) {
  render::image_format(output);
  render::check_writable_output(output);
  const render::LightField f = render::load_light_field(input);
  constexpr uint32_t kGap = 2;
  render::Frame sheet;
  sheet.width = f.grid_w * f.width + (f.grid_w - 1) * kGap;
  sheet.height = f.grid_h * f.height + (f.grid_h - 1) * kGap;
  sheet.colour.assign(size_t(sheet.width) * sheet.height, glm::vec4(0.18f, 0.18f, 0.18f, 1.0f));
  float peak = 0.0f;
  for (const auto& image : f.images) {
    for (float v : image) peak = std::max(peak, v);
  }
  const float exposure = peak > 0.0f ? 1.0f / peak : 1.0f;
  for (uint32_t m = 0; m < f.image_count(); ++m) {
    const uint32_t i = m % f.grid_w, j = m / f.grid_w;
    const uint32_t x0 = i * (f.width + kGap), y0 = (f.grid_h - 1 - j) * (f.height + kGap);
    for (uint32_t y = 0; y < f.height; ++y) {
      for (uint32_t x = 0; x < f.width; ++x) {
        const float* t = &f.images[m][3 * (size_t(y) * f.width + x)];
        sheet.colour[size_t(y0 + f.height - 1 - y) * sheet.width + x0 + x] =
            glm::vec4(t[0] * exposure, t[1] * exposure, t[2] * exposure, 1.0f);
      }
    }
  }
  render::write_colour(output, sheet);
  std::cout << "wrote " << output << " (" << sheet.width << " x " << sheet.height << ", " << f.image_count()
            << " images, exposure 1/" << peak << ")\n";
}

}  // namespace

void add_luminaire_command(CLI::App& app, int& exit_code) {
  CLI::App* cmd = app.add_subcommand(
      "luminaire",
      "Light-field luminaires (Lu et al. 2015, docs/luminaire.md): make a procedural one, print what a .lfl file "
      "holds, lay its images out as a contact sheet, import an IES TM-25 ray file");
  cmd->require_subcommand(1);

  auto m = std::make_shared<MakeArgs>();
  CLI::App* make = cmd->add_subcommand(
      "make",
      "Write a procedural light field whose radiance is known: panel, a Lambertian textured plane (a checker, every "
      "image the same); headlight, a narrow beam converging to a hot spot (each image a spot seen from its basis "
      "function); led, an LED headlight: an array of small dies whose beams converge to foci spread across the road "
      "(each image a sharp spot per die, mostly dark). Plane S is 0.1 m across, 0.05 m from U");
  make->add_option("KIND", m->kind, "panel, headlight or led")
      ->required()
      ->check(CLI::IsMember({"panel", "headlight", "led"}));
  make->add_option("-o,--output", m->output, "The .lfl file (written to a temporary name, then renamed)")
      ->required()
      ->group("Output");
  make->add_option("--resolution", m->resolution,
                   "Texels per image side, 1 to 1024 (all images together at most "
                   "67108864 texels)")
      ->default_val(128)
      ->check(CLI::Range(1u, render::LightField::kMaxImageSide))
      ->group("Light field");
  make->add_option("--grid", m->grid, "Basis functions per side on U (M = grid^2 images), 1 to 16")
      ->default_val(5)
      ->check(CLI::Range(1u, render::LightField::kMaxGridSide))
      ->group("Light field");
  make->add_option("--radiance", m->radiance, "Peak radiance (W m^-2 sr^-1 per channel), > 0")
      ->default_val(1000.0f)
      ->check(positive_number())
      ->group("Light field");
  auto* beam = make->add_option("--beam", m->beam, "headlight: the spot's width, a fraction of S's extent, > 0")
                   ->default_val(0.08f)
                   ->check(positive_number())
                   ->group("Headlight");
  auto* focus = make->add_option("--focus", m->focus,
                                 "headlight, led: where the beams converge, metres beyond S, > 0 (default: headlight "
                                 "0.5, led 0.12)")
                    ->check(positive_number())
                    ->group("Headlight");
  auto* leds = make->add_option("--leds", m->leds, "led: dies per side, 1 to 8")
                   ->default_val(3)
                   ->check(CLI::Range(1u, 8u))
                   ->group("LED");
  auto* die = make->add_option("--die", m->die, "led: each die's spot width, a fraction of S's extent, > 0")
                  ->default_val(0.015f)
                  ->check(positive_number())
                  ->group("LED");
  auto* checks = make->add_option("--checks", m->checks, "panel: checker squares per side, 1 to 1024")
                     ->default_val(4)
                     ->check(CLI::Range(1u, 1024u))
                     ->group("Panel");
  make->callback([m, beam, focus, checks, leds, die, &exit_code] {
    for (const auto& [option, kinds] : {std::pair{beam, "headlight"}, std::pair{focus, "headlight led"},
                                        std::pair{checks, "panel"}, std::pair{leds, "led"}, std::pair{die, "led"}}) {
      if (option->count() > 0 && std::string(kinds).find(m->kind) == std::string::npos) {
        throw std::invalid_argument(option->get_name() + " is an option of make " + kinds + ", not of make " + m->kind);
      }
    }
    check_lfl_output(m->output);
    const float f_focus = focus->count() > 0 ? m->focus : (m->kind == "led" ? 0.12f : 0.5f);
    const render::LightField f =
        m->kind == "panel" ? render::make_panel_luminaire(m->resolution, m->grid, m->radiance, m->checks)
        : m->kind == "headlight"
            ? render::make_headlight_luminaire(m->resolution, m->grid, m->radiance, m->beam, f_focus)
            : render::make_led_luminaire(m->resolution, m->grid, m->radiance, m->leds, m->die, f_focus);
    render::save_light_field(f, m->output);
    std::cout << "wrote " << m->output << " (" << m->kind << ", " << f.image_count() << " images of " << f.width
              << " x " << f.height << ", " << fs::file_size(m->output) << " bytes)\n";
    exit_code = 0;
  });

  auto info_input = std::make_shared<std::string>();
  auto info_json = std::make_shared<bool>(false);
  CLI::App* info = cmd->add_subcommand(
      "info",
      "Check a .lfl file and print its header, M, its texels, its flux (light_field_flux) and the min, max "
      "and mean luminance of its texels");
  info->add_option("FILE", *info_input, "The light field (.lfl)")->required();
  info->add_flag("--json", *info_json, "Print one JSON object");
  info->callback([info_input, info_json, &exit_code] {
    run_info(*info_input, *info_json);
    exit_code = 0;
  });

  auto sheet_input = std::make_shared<std::string>();
  auto sheet_output = std::make_shared<std::string>();
  CLI::App* sheet = cmd->add_subcommand(
      "sheet",
      "Write a contact sheet of a .lfl file's images, laid out as their basis functions lie on U (+y up), "
      "2-pixel gaps, one exposure for all (the brightest texel is white)");
  sheet->add_option("FILE", *sheet_input, "The light field (.lfl)")->required();
  sheet->add_option("-o,--output", *sheet_output, "The sheet (.png, 8-bit sRGB, or .exr, linear)")->required();
  sheet->callback([sheet_input, sheet_output, &exit_code] {
    run_sheet(*sheet_input, *sheet_output);
    exit_code = 0;
  });

  struct ImportArgs {
    std::string input, output;
    uint32_t grid = 5, resolution = 128;
  };
  auto im = std::make_shared<ImportArgs>();
  CLI::App* import =
      cmd->add_subcommand("import",
                          "Bin the rays of an IES TM-25 ray file into a light field of grid x grid basis functions and "
                          "resolution x resolution images, flux conserved (docs/luminaire.md)");
  import->add_option("FILE", im->input, "The ray file (.tm25ray)")->required();
  import->add_option("-o,--output", im->output, "The .lfl file (written to a temporary name, then renamed)")
      ->required();
  import->add_option("--grid", im->grid, "Basis functions per side on U, 1 to 16")
      ->default_val(5)
      ->check(CLI::Range(1u, render::LightField::kMaxGridSide));
  import->add_option("--resolution", im->resolution, "Texels per image side, 1 to 1024")
      ->default_val(128)
      ->check(CLI::Range(1u, render::LightField::kMaxImageSide));
  import->callback([im, &exit_code] {
    check_lfl_output(im->output);
  const render::LightField f = render::import_tm25(im->input, im->grid, im->resolution);
  render::save_light_field(f, im->output);
  std::cout << "wrote " << im->output << " (" << f.image_count() << " images of " << f.width << " x " << f.height
            << ", " << fs::file_size(im->output) << " bytes)\n";
  exit_code = 0;
});
}  // namespace svo::tools

}  // namespace svo::tools
