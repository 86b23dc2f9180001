// svo bench fig4, fig11, fig12: the paper's comparisons (Heitz & Neyret
// Figs. 4, 11 and 12) as bench cases. Each renders the engine's modes and
// the ground truth (svo reference, from the source geometry) of a few
// configurations, and writes table.md, results.csv, results.json and strips
// of images side by side (PNG) to its output directory.
#include "cmd_bench_figures.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <tuple>

#include "bench_util.h"
#include "commands.h"
#include "progress.h"
#include "svo/octree/files.h"
#include "svo/reference/compare.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/fine_bumpy_sphere.h"
#include "svo/voxelizer/scenes.h"

namespace svo::tools {

namespace {

namespace fs = std::filesystem;
using bench::fmt;
using bench::sci;

// What every figure takes.
struct FigureArgs {
  uint32_t resolution = 256;
  uint32_t size = 96;
  uint32_t spp = 64;
  std::vector<float> frequency{120.0f, 200.0f};  // fig11, fig12: bump frequencies (per radian)
  std::string device;
  std::string out;
};

void add_figure_options(CLI::App& cmd, FigureArgs& a, uint32_t resolution, uint32_t size, const std::string& out,
                        bool bumps) {
  a.resolution = resolution;
  a.size = size;
  a.out = out;
  cmd.add_option("--resolution", a.resolution, "Finest lattice cells per axis of the octree")
      ->default_val(resolution)
      ->check(CLI::Range(16u, 2048u));
  cmd.add_option("--size", a.size, "Image width and height, pixels")->default_val(size)->check(CLI::Range(8u, 2048u));
  cmd.add_option("--spp", a.spp, "Samples per pixel of the ground truth")
      ->default_val(64)
      ->check(CLI::Range(1u, 65536u));
  if (bumps) {
    cmd.add_option("--frequency", a.frequency,
                   "MIN,MAX: frequencies of the sphere's bumps per radian of arc (wavelength 2 pi 0.7 / frequency); "
                   "the octree must resolve them")
        ->delimiter(',')
        ->expected(2)
        ->default_str("120,200")
        ->check(CLI::Range(1.0f, 2000.0f));
  }
  cmd.add_option("--device", a.device, kDeviceHelp);
  cmd.add_option("-o,--out", a.out, "Output directory (created)")->default_val(out);
}

// The octree, the ground truth's geometry and the GPU tracer of one scene.
struct Setup {
  std::unique_ptr<reference::Geometry> geometry;
  octree::Octree tree;
  std::unique_ptr<render::Renderer> gpu;
};

Setup make_setup(voxelizer::AnalyticScene& scene, const FigureArgs& a, ProgressBar& bar) {
  Setup s;
  voxelizer::VoxelizeOptions vo;
  vo.resolution = a.resolution;
  vo.progress = [&](const std::string& stage, double f) { bar.update("voxelize " + stage, f); };
  s.tree = voxelizer::voxelize(scene, vo);
  s.geometry = reference::scene_geometry(scene);
  s.gpu = render::make_renderer(s.tree, {a.device});
  return s;
}

render::Frame reference_frame(const Setup& s, const render::RenderSettings& rs, uint32_t spp, ProgressBar& bar,
                              const std::string& stage) {
  reference::ReferenceSettings r;
  r.render = rs;
  r.spp = spp;
  r.progress = [&, rows = uint64_t(rs.height)](double f) {
    bar.update(stage, uint64_t(f * double(rows) + 0.5), rows, "rows");
  };
  return reference::render_reference(*s.geometry, r);
}

// A camera on +z looking at the origin from `distance`, the vertical field
// of view making a sphere of `radius` span `pixels` of `size`.
render::Camera sphere_camera(float radius, float pixels, uint32_t size, float distance) {
  render::Camera c;
  c.eye = glm::vec3(0, 0, distance);
  c.target = glm::vec3(0);
  c.up = glm::vec3(0, 1, 0);
  const float half = radius * float(size) / pixels;  // half the image height at the sphere, scene units
  c.fov_deg = glm::degrees(2.0f * std::atan(half / distance));
  return c;
}

// The unit direction of pixel (x, y)'s centre ray (the tracer's convention).
glm::vec3 pixel_ray(const render::Camera& c, uint32_t w, uint32_t h, uint32_t x, uint32_t y) {
  glm::vec3 fwd = glm::normalize(c.target - c.eye);
  glm::vec3 right = glm::normalize(glm::cross(fwd, c.up));
  glm::vec3 up = glm::cross(right, fwd);
  float t = std::tan(glm::radians(c.fov_deg) * 0.5f);
  float ndc_x = (2.0f * (float(x) + 0.5f) / float(w) - 1.0f) * t * float(w) / float(h);
  float ndc_y = (1.0f - 2.0f * (float(y) + 0.5f) / float(h)) * t;
  return glm::normalize(fwd + ndc_x * right + ndc_y * up);
}

// The outward normal where the ray from `eye` along d meets the sphere of
// `radius` at the origin, or nullopt.
std::optional<glm::vec3> sphere_normal(glm::vec3 eye, glm::vec3 d, float radius) {
  float b = glm::dot(eye, d), c = glm::dot(eye, eye) - radius * radius, disc = b * b - c;
  if (disc < 0) return std::nullopt;
  float t = -b - std::sqrt(disc);
  if (t < 0) return std::nullopt;
  return glm::normalize(eye + t * d);
}

float luminance(glm::vec4 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// relMSE (pbrt-v4's MRSE, as reference::compare_images) over the pixels of `mask`.
double relmse_over(const render::Frame& f, const render::Frame& truth, const std::vector<uint8_t>& mask) {
  double sum = 0;
  uint64_t n = 0;
  for (size_t i = 0; i < f.colour.size(); ++i) {
    if (!mask[i]) continue;
    for (int c = 0; c < 3; ++c) {
      double d = f.colour[i][c] - truth.colour[i][c], r = truth.colour[i][c] + 0.01;
      sum += d * d / (r * r);
    }
    n += 3;
  }
  return n ? sum / double(n) : 0.0;
}

glm::dvec3 mean_over(const render::Frame& f, const std::vector<uint8_t>& mask) {
  glm::dvec3 sum(0);
  uint64_t n = 0;
  for (size_t i = 0; i < f.colour.size(); ++i) {
    if (mask[i]) sum += glm::dvec3(glm::vec3(f.colour[i])), ++n;
  }
  return n ? sum / double(n) : sum;
}

// Largest relative per-channel difference.
double relative(glm::dvec3 x, glm::dvec3 t) {
  glm::dvec3 e = glm::abs(x - t) / glm::max(t, glm::dvec3(1e-6));
  return std::max(e.x, std::max(e.y, e.z));
}

// Largest per-channel difference of chromaticities c / (r + g + b): the hue
// shift, whatever the brightness.
double chroma_error(glm::dvec3 x, glm::dvec3 t) {
  const double sx = x.x + x.y + x.z, st = t.x + t.y + t.z;
  if (!(sx > 0) || !(st > 0)) return 0.0;
  glm::dvec3 e = glm::abs(x / sx - t / st);
  return std::max(e.x, std::max(e.y, e.z));
}

nlohmann::json rgb_json(glm::dvec3 c) { return nlohmann::json::array({c.x, c.y, c.z}); }
std::string rgb_text(glm::dvec3 c) { return fmt(c.x, 3) + " " + fmt(c.y, 3) + " " + fmt(c.z, 3); }

void write_json(const fs::path& dir, const nlohmann::json& j) {
  files::write_file((dir / "results.json").string(), j.dump(2) + "\n");
}

// ---------------------------------------------------------------------------
// Fig. 11: light- and view-dependent colour at grazing angles.

void run_fig11(const FigureArgs& a, float sphere_pixels) {
  fs::path dir(a.out);
  fs::create_directories(dir);
  render::check_writable_output((dir / "results.csv").string());
  ProgressBar bar("bench fig11");
  voxelizer::FineBumpySphere::Options so;
  so.min_frequency = a.frequency[0];
  so.max_frequency = a.frequency[1];
  voxelizer::FineBumpySphere scene(so);
  Setup setup = make_setup(scene, a, bar);
  const float distance = 8.0f;
  const render::Camera camera = sphere_camera(scene.radius(), sphere_pixels, a.size, distance);
  struct Case {
    std::string name;
    glm::vec3 light;
  };
  // Front light: grazing view at the limb. Side light: grazing light along
  // the terminator, which crosses the middle of the disc.
  const std::vector<Case> cases = {{"front-light", glm::normalize(glm::vec3(0.25f, 0.35f, 1.0f))},
                                   {"side-light", glm::normalize(glm::vec3(1.0f, 0.1f, 0.12f))}};
  const float grazing = 0.5f;  // cosine of 60 degrees
  struct Region {
    std::string name;
    std::function<bool(float cos_v, float cos_l)> inside;
  };
  const std::vector<Region> regions = {
      {"all", [](float, float) { return true; }},
      {"grazing-view", [&](float cv, float) { return cv < grazing; }},
      {"grazing-light", [&](float cv, float cl) { return cl > 0 && cl < grazing && cv >= grazing; }},
      {"facing", [&](float cv, float cl) { return cv >= grazing && cl >= grazing; }}};
  nlohmann::json jrows = nlohmann::json::array();
  nlohmann::json claims = nlohmann::json::object();
  std::ostringstream md, csv;
  csv << "case,region,pixels,method,mean_r,mean_g,mean_b,truth_r,truth_g,truth_b,mean_colour_error,chroma_error,"
         "relmse\n";
  md << "Fine bumpy sphere (radius 0.7, bump deviation " << scene.sigma() << ", frequencies " << a.frequency[0] << "-"
     << a.frequency[1] << " per radian: wavelengths " << fmt(2 * M_PI * 0.7 / a.frequency[1], 3) << "-"
     << fmt(2 * M_PI * 0.7 / a.frequency[0], 3) << "), colour red in the valleys and green on the crests; " << a.size
     << "x" << a.size << ", the sphere " << sphere_pixels << " pixels across (a pixel is "
     << fmt(2 * scene.radius() / sphere_pixels, 4) << " units), octree " << a.resolution << "^3, ground truth " << a.spp
     << " spp, shadows on. Regions from the mean sphere at each pixel's centre, fully covered pixels of "
     << "the ground truth: grazing view = view more than 60 degrees from the normal; grazing light = light more "
        "than 60 degrees from the normal, view within 60.\n\n"
     << "Error: the largest relative per-channel difference of the region's mean colour; hue: the largest "
        "difference of its chromaticity r/(r+g+b), g/(r+g+b), b/(r+g+b), which brightness does not change.\n\n"
     << "| light | region | pixels | ground truth mean (R G B) | prefiltered | error | hue | MIP | error | hue | "
        "relMSE prefiltered | relMSE MIP |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<render::Frame> keep;
  keep.reserve(cases.size() * 5);
  std::vector<std::vector<const render::Frame*>> rows;
  for (const auto& cs : cases) {
    render::RenderSettings s;
    s.width = s.height = a.size;
    s.camera = camera;
    s.shadows = true;
    s.lights = {render::Light{false, cs.light, glm::vec3(3.0f), 0.02f}};
    s.ambient = glm::vec3(0.03f);
    s.specular = 0;
    s.background = glm::vec3(0);
    render::Frame truth = reference_frame(setup, s, a.spp, bar, cs.name + ": reference");
    s.mode = render::Mode::Prefiltered;
    render::Frame pre = setup.gpu->render(s);
    s.mode = render::Mode::Mip;
    render::Frame mip = setup.gpu->render(s);
    // Region masks.
    std::vector<std::vector<uint8_t>> masks(regions.size(), std::vector<uint8_t>(truth.colour.size(), 0));
    for (uint32_t y = 0; y < a.size; ++y) {
      for (uint32_t x = 0; x < a.size; ++x) {
        size_t i = size_t(y) * a.size + x;
        if (truth.colour[i].a < 0.99f) continue;
        auto n = sphere_normal(camera.eye, pixel_ray(camera, a.size, a.size, x, y), scene.radius());
        if (!n) continue;
        float cv = glm::dot(*n, glm::normalize(camera.eye - *n * scene.radius()));
        float cl = glm::dot(*n, cs.light);
        for (size_t r = 0; r < regions.size(); ++r) masks[r][i] = regions[r].inside(cv, cl) ? 1 : 0;
      }
    }
    for (size_t r = 0; r < regions.size(); ++r) {
      uint64_t count = uint64_t(std::count(masks[r].begin(), masks[r].end(), uint8_t(1)));
      if (count == 0) continue;
      glm::dvec3 t = mean_over(truth, masks[r]), mp = mean_over(pre, masks[r]), mm = mean_over(mip, masks[r]);
      double ep = relative(mp, t), em = relative(mm, t);
      double hp = chroma_error(mp, t), hm = chroma_error(mm, t);
      double rp = relmse_over(pre, truth, masks[r]), rm = relmse_over(mip, truth, masks[r]);
      md << "| " << cs.name << " | " << regions[r].name << " | " << count << " | " << rgb_text(t) << " | "
         << rgb_text(mp) << " | " << fmt(100 * ep, 1) << "% | " << fmt(hp, 4) << " | " << rgb_text(mm) << " | "
         << fmt(100 * em, 1) << "% | " << fmt(hm, 4) << " | " << sci(rp) << " | " << sci(rm) << " |\n";
      for (auto [name, m, e, h, rel] : {std::tuple{"prefiltered", mp, ep, hp, rp}, std::tuple{"mip", mm, em, hm, rm}}) {
        csv << cs.name << "," << regions[r].name << "," << count << "," << name << "," << m.x << "," << m.y << ","
            << m.z << "," << t.x << "," << t.y << "," << t.z << "," << e << "," << h << "," << rel << "\n";
        jrows.push_back({{"case", cs.name},
                         {"region", regions[r].name},
                         {"pixels", count},
                         {"method", name},
                         {"mean", rgb_json(m)},
                         {"truth_mean", rgb_json(t)},
                         {"mean_colour_error", e},
                         {"chroma_error", h},
                         {"relmse", rel}});
      }
      if (regions[r].name != "all" && regions[r].name != "facing") {
        claims[cs.name + "/" + regions[r].name + ": prefiltered hue closer to the truth than MIP"] = hp < hm;
      }
    }
    keep.push_back(std::move(truth));
    keep.push_back(std::move(pre));
    keep.push_back(std::move(mip));
    const render::Frame& t = keep[keep.size() - 3];
    const double scale = 0.2;
    keep.push_back(reference::error_image(render::frame_image(keep[keep.size() - 2]), render::frame_image(t), scale));
    keep.push_back(reference::error_image(render::frame_image(keep[keep.size() - 2]), render::frame_image(t), scale));
    rows.push_back({&keep[keep.size() - 5], &keep[keep.size() - 4], &keep[keep.size() - 3], &keep[keep.size() - 2],
                    &keep[keep.size() - 1]});
  }
  bar.finish();
  render::write_colour((dir / "fig11.png").string(), bench::strip(rows, a.size <= 128 ? 2 : 1));
  md << "\nImages `fig11.png`, one row per light: ground truth, prefiltered, MIP, |prefiltered - truth| and |MIP - "
        "truth| (false colour, full scale 0.2).\n";
  files::write_file((dir / "results.csv").string(), csv.str());
  files::write_file((dir / "table.md").string(), md.str());
  write_json(dir, {{"figure", 11},
                   {"resolution", a.resolution},
                   {"size", a.size},
                   {"spp", a.spp},
                   {"sphere_pixels", sphere_pixels},
                   {"frequency", a.frequency},
                   {"device", setup.gpu->device_name()},
                   {"rows", jrows},
                   {"claims", claims}});
  std::cout << md.str();
}

// ---------------------------------------------------------------------------
// Fig. 12: a bumpy specular surface turning glossy at distance.

void run_fig12(const FigureArgs& a, float roughness, float specular) {
  fs::path dir(a.out);
  fs::create_directories(dir);
  render::check_writable_output((dir / "results.csv").string());
  ProgressBar bar("bench fig12");
  voxelizer::FineBumpySphere::Options so;
  so.min_frequency = a.frequency[0];
  so.max_frequency = a.frequency[1];
  so.abar = glm::vec3(0.05f);
  so.a_s = glm::vec3(0.0f);
  voxelizer::FineBumpySphere scene(so);
  scene.set_sigma_rho2(roughness * roughness);
  Setup setup = make_setup(scene, a, bar);
  struct Distance {
    std::string name;
    float pixels;  // the sphere's diameter on the image
  };
  const std::vector<Distance> distances = {
      {"close", 0.9f * float(a.size)}, {"mid", 0.3f * float(a.size)}, {"far", 0.1f * float(a.size)}};
  const glm::vec3 light = glm::normalize(glm::vec3(0.45f, 0.45f, 1.0f));
  std::ostringstream md, csv;
  nlohmann::json jrows = nlohmann::json::array();
  nlohmann::json claims = nlohmann::json::object();
  csv << "distance,sphere_pixels,method,relmse_covered,relmse,energy_ratio,peak_ratio,highlight_pixels,"
         "truth_highlight_pixels\n";
  md << "Fine bumpy sphere (bump deviation " << scene.sigma() << ", frequencies " << a.frequency[0] << "-"
     << a.frequency[1] << " per radian), grey diffuse 0.05, Beckmann lobe of weight " << specular
     << " with micro-roughness sigma_rho " << roughness << "; one directional light (0.45, 0.45, 1) of irradiance 1; "
     << a.size << "x" << a.size << ", octree " << a.resolution << "^3, ground truth " << a.spp
     << " spp. Energy: the image's summed luminance over the truth's; peak: its brightest pixel over the truth's; "
        "highlight: pixels brighter than half the truth's peak.\n\n"
     << "| distance | sphere pixels | method | relMSE (covered pixels) | energy | peak | highlight pixels (truth) |\n"
     << "|---|---|---|---|---|---|---|\n";
  std::vector<render::Frame> keep;
  keep.reserve(distances.size() * 3);
  std::vector<std::vector<const render::Frame*>> rows;
  for (const auto& d : distances) {
    render::RenderSettings s;
    s.width = s.height = a.size;
    s.camera = sphere_camera(scene.radius(), d.pixels, a.size, 8.0f);
    s.lights = {render::Light{false, light, glm::vec3(1.0f), 0.02f}};
    s.ambient = glm::vec3(0.0f);
    s.specular = specular;
    s.background = glm::vec3(0);
    render::Frame truth = reference_frame(setup, s, a.spp, bar, d.name + ": reference");
    std::vector<uint8_t> covered(truth.colour.size(), 0);
    float truth_peak = 0;
    double truth_energy = 0;
    for (size_t i = 0; i < truth.colour.size(); ++i) {
      covered[i] = truth.colour[i].a > 0 ? 1 : 0;
      truth_peak = std::max(truth_peak, luminance(truth.colour[i]));
      truth_energy += luminance(truth.colour[i]);
    }
    auto highlight = [&](const render::Frame& f) {
      return uint64_t(std::count_if(f.colour.begin(), f.colour.end(),
                                    [&](glm::vec4 c) { return luminance(c) > 0.5f * truth_peak; }));
    };
    const uint64_t truth_highlight = highlight(truth);
    std::vector<std::pair<std::string, render::Frame>> frames;
    for (auto [name, mode] :
         {std::pair{"prefiltered", render::Mode::Prefiltered}, std::pair{"mip", render::Mode::Mip}}) {
      s.mode = mode;
      frames.emplace_back(name, setup.gpu->render(s));
    }
    std::map<std::string, double> rel;
    for (const auto& [name, f] : frames) {
      double energy = 0;
      float peak = 0;
      for (const auto& c : f.colour) energy += luminance(c), peak = std::max(peak, luminance(c));
      const double rc = relmse_over(f, truth, covered);
      const double r_all = reference::compare_images(render::frame_image(f), render::frame_image(truth)).relmse;
      const double er = truth_energy > 0 ? energy / truth_energy : 0.0, pr = truth_peak > 0 ? peak / truth_peak : 0.0;
      const uint64_t hl = highlight(f);
      rel[name] = rc;
      md << "| " << d.name << " | " << fmt(d.pixels, 0) << " | " << name << " | " << sci(rc) << " | " << fmt(er, 3)
         << " | " << fmt(pr, 3) << " | " << hl << " (" << truth_highlight << ") |\n";
      csv << d.name << "," << d.pixels << "," << name << "," << rc << "," << r_all << "," << er << "," << pr << ","
          << hl << "," << truth_highlight << "\n";
      jrows.push_back({{"distance", d.name},
                       {"sphere_pixels", d.pixels},
                       {"method", name},
                       {"relmse_covered", rc},
                       {"relmse", r_all},
                       {"energy_ratio", er},
                       {"peak_ratio", pr},
                       {"highlight_pixels", hl},
                       {"truth_highlight_pixels", truth_highlight}});
    }
    claims[d.name + ": prefiltered relMSE below MIP's"] = rel["prefiltered"] < rel["mip"];
    keep.push_back(std::move(truth));
    for (auto& [name, f] : frames) keep.push_back(std::move(f));
    rows.push_back({&keep[keep.size() - 3], &keep[keep.size() - 2], &keep[keep.size() - 1]});
  }
  bar.finish();
  render::write_colour((dir / "fig12.png").string(), bench::strip(rows, a.size <= 128 ? 2 : 1, 2.0f));
  md << "\nImages `fig12.png`, one row per distance: ground truth, prefiltered (slope variance folded into the "
        "lobe), MIP (mean normal, micro-roughness only); exposure x2.\n";
  files::write_file((dir / "results.csv").string(), csv.str());
  files::write_file((dir / "table.md").string(), md.str());
  write_json(dir, {{"figure", 12},
                   {"resolution", a.resolution},
                   {"size", a.size},
                   {"spp", a.spp},
                   {"roughness", roughness},
                   {"specular", specular},
                   {"frequency", a.frequency},
                   {"device", setup.gpu->device_name()},
                   {"rows", jrows},
                   {"claims", claims}});
  std::cout << md.str();
}

// ---------------------------------------------------------------------------
// Fig. 4: silhouettes under depth of field, against alpha blending.

void run_fig4(const FigureArgs& a, const std::string& scene_name, std::vector<float> apertures) {
  fs::path dir(a.out);
  fs::create_directories(dir);
  render::check_writable_output((dir / "results.csv").string());
  ProgressBar bar("bench fig4");
  auto scene = voxelizer::make_scene(scene_name);
  Setup setup = make_setup(*scene, a, bar);
  // The scene's bounds span 70% of the image height from 6 units away: a
  // field of view of about 14 degrees, so that measuring the focus along each
  // ray (the tracer) or along the view axis (the reference) differs by < 1%.
  const voxelizer::Box box = scene->bounds();
  const float extent = glm::length(box.hi - box.lo) / std::sqrt(3.0f);
  const glm::vec3 centre = 0.5f * (box.lo + box.hi);
  render::Camera camera;
  camera.eye = centre + glm::vec3(0.0f, 0.0f, 6.0f);
  camera.target = centre;
  camera.fov_deg = glm::degrees(2.0f * std::atan(0.5f * extent / 0.7f / 6.0f));
  const float focus = 3.0f;  // in front of the object: its silhouette is out of focus
  std::ostringstream md, csv;
  nlohmann::json jrows = nlohmann::json::array();
  nlohmann::json claims = nlohmann::json::object();
  csv << "aperture,focus,method,relmse,coverage_error,coverage_error_silhouette,coverage_bias_silhouette,"
         "coverage_ratio,silhouette_pixels\n";
  md << "Scene " << scene_name << ", " << a.size << "x" << a.size << ", camera 6 units away (field of view "
     << fmt(camera.fov_deg, 1) << " degrees), thin lens focused " << focus
     << " units away (in front of the object), octree " << a.resolution << "^3, ground truth " << a.spp
     << " spp with the same lens. Silhouette pixels: the ground truth's partly covered pixels (compare.h); "
        "bias: mean (coverage - truth's) there; coverage ratio: summed coverage over the truth's.\n\n"
     << "| aperture | blur at the object (pixels) | method | coverage error (silhouette) | bias (silhouette) | "
        "coverage ratio | relMSE |\n|---|---|---|---|---|---|---|\n";
  std::vector<render::Frame> keep;
  keep.reserve(apertures.size() * 3);
  std::vector<std::vector<const render::Frame*>> rows;
  const float pixel = 2.0f * 6.0f * std::tan(glm::radians(camera.fov_deg) * 0.5f) / float(a.size);
  for (float aperture : apertures) {
    render::RenderSettings s;
    s.width = s.height = a.size;
    s.camera = camera;
    s.camera.aperture = aperture;
    s.camera.focus = focus;
    s.lens_parts = 1;  // the paper's one cone per pixel (svo render splits a wide lens: --lens-parts)
    s.background = glm::vec3(0);
    const std::string label = aperture > 0 ? "aperture " + fmt(aperture, 3) : std::string("pinhole");
    render::Frame truth = reference_frame(setup, s, a.spp, bar, label + ": reference");
    const render::Image truth_image = render::frame_image(truth);
    const std::vector<uint8_t> sil = reference::silhouette_mask(truth_image);
    double truth_coverage = 0;
    for (const auto& c : truth.colour) truth_coverage += c.a;
    const float blur = aperture * std::abs(6.0f - focus) / focus / pixel;  // radius, pixels
    std::map<std::string, double> err;
    std::vector<render::Frame> frames;
    for (auto [name, mode] :
         {std::pair{"prefiltered", render::Mode::Prefiltered}, std::pair{"alpha", render::Mode::Alpha}}) {
      s.mode = mode;
      render::Frame f = setup.gpu->render(s);
      reference::ImageErrors e = reference::compare_images(render::frame_image(f), truth_image, name, "reference");
      double bias = 0, coverage = 0;
      uint64_t n = 0;
      for (size_t i = 0; i < f.colour.size(); ++i) {
        coverage += f.colour[i].a;
        if (sil[i]) bias += f.colour[i].a - truth.colour[i].a, ++n;
      }
      bias = n ? bias / double(n) : 0.0;
      const double ratio = truth_coverage > 0 ? coverage / truth_coverage : 0.0;
      const double ces = e.coverage_error_silhouette.value_or(0.0);
      err[name] = ces;
      md << "| " << fmt(aperture, 3) << " | " << fmt(blur, 1) << " | " << name << " | " << fmt(ces, 3) << " | "
         << (bias >= 0 ? "+" : "") << fmt(bias, 3) << " | " << fmt(ratio, 3) << " | " << sci(e.relmse) << " |\n";
      csv << aperture << "," << focus << "," << name << "," << e.relmse << "," << e.coverage_error.value_or(0.0) << ","
          << ces << "," << bias << "," << ratio << "," << e.silhouette_pixels << "\n";
      jrows.push_back({{"aperture", aperture},
                       {"focus", focus},
                       {"blur_pixels", blur},
                       {"method", name},
                       {"relmse", e.relmse},
                       {"coverage_error", e.coverage_error.value_or(0.0)},
                       {"coverage_error_silhouette", ces},
                       {"coverage_bias_silhouette", bias},
                       {"coverage_ratio", ratio},
                       {"silhouette_pixels", e.silhouette_pixels}});
      frames.push_back(std::move(f));
    }
    claims[label + ": prefiltered silhouette coverage error below alpha's"] = err["prefiltered"] < err["alpha"];
    keep.push_back(std::move(truth));
    for (auto& f : frames) keep.push_back(std::move(f));
    rows.push_back({&keep[keep.size() - 3], &keep[keep.size() - 2], &keep[keep.size() - 1]});
  }
  bar.finish();
  render::write_colour((dir / "fig4.png").string(), bench::strip(rows, a.size <= 128 ? 2 : 1));
  md << "\nImages `fig4.png`, one row per aperture: ground truth, prefiltered, alpha.\n";
  files::write_file((dir / "results.csv").string(), csv.str());
  files::write_file((dir / "table.md").string(), md.str());
  write_json(dir, {{"figure", 4},
                   {"scene", scene_name},
                   {"resolution", a.resolution},
                   {"size", a.size},
                   {"spp", a.spp},
                   {"focus", focus},
                   {"fov_deg", camera.fov_deg},
                   {"device", setup.gpu->device_name()},
                   {"rows", jrows},
                   {"claims", claims}});
  std::cout << md.str();
}

}  // namespace

void add_bench_figure_commands(CLI::App& bench, int& exit_code) {
  {
    auto a = std::make_shared<FigureArgs>();
    auto pixels = std::make_shared<float>(48.0f);
    CLI::App* cmd = bench.add_subcommand(
        "fig11",
        "Paper Fig. 11: light- and view-dependent colour at grazing angles on a sphere with fine bumps (red "
        "valleys, green crests), front light (grazing view at the limb) and side light (grazing light along the "
        "terminator): ground truth (svo reference), prefiltered and MIP, mean colour and relMSE per region; writes "
        "table.md, results.csv, results.json and fig11.png to --out");
    add_figure_options(*cmd, *a, 256, 96, "bench-fig11", true);
    cmd->add_option("--sphere-pixels", *pixels, "The sphere's diameter on the image, pixels")
        ->default_val(48.0f)
        ->check(CLI::Range(4.0f, 4096.0f));
    cmd->callback([a, pixels, &exit_code] {
      run_fig11(*a, *pixels);
      exit_code = 0;
    });
  }
  {
    auto a = std::make_shared<FigureArgs>();
    auto roughness = std::make_shared<float>(0.1f);
    auto specular = std::make_shared<float>(0.25f);
    CLI::App* cmd = bench.add_subcommand(
        "fig12",
        "Paper Fig. 12: a bumpy specular sphere seen close (bumps a few pixels wide), mid and far (bumps below a "
        "pixel): ground truth, prefiltered (slope variance in the lobe) and MIP (mean normal only): relMSE, "
        "energy, peak and highlight size per distance; writes table.md, results.csv, results.json and fig12.png "
        "to --out");
    add_figure_options(*cmd, *a, 256, 96, "bench-fig12", true);
    cmd->add_option("--roughness", *roughness, "Micro-BRDF slope deviation sigma_rho")
        ->default_val(0.1f)
        ->check(CLI::Range(0.01f, 1.0f));
    cmd->add_option("--specular", *specular, "Weight of the Beckmann lobe")
        ->default_val(0.25f)
        ->check(CLI::Range(0.0f, 10.0f));
    cmd->callback([a, roughness, specular, &exit_code] {
      run_fig12(*a, *roughness, *specular);
      exit_code = 0;
    });
  }
  {
    auto a = std::make_shared<FigureArgs>();
    auto scene = std::make_shared<std::string>("bumpy-sphere");
    auto apertures = std::make_shared<std::vector<float>>(std::vector<float>{0.0f, 0.05f, 0.15f});
    CLI::App* cmd = bench.add_subcommand(
        "fig4",
        "Paper Fig. 4: silhouettes out of focus (thin lens focused in front of the object): ground truth with the "
        "same lens, prefiltered (A-buffer masks) and alpha (opacity blending, thickens silhouettes): coverage "
        "error and bias on silhouette pixels; writes table.md, results.csv, results.json and fig4.png to --out");
    add_figure_options(*cmd, *a, 128, 96, "bench-fig4", false);
    cmd->add_option("--scene", *scene, "Built-in scene")->default_val("bumpy-sphere");
    cmd->add_option("--apertures", *apertures, "Lens radii, scene units (0: pinhole)")
        ->delimiter(',')
        ->default_str("0,0.05,0.15")
        ->check(CLI::Range(0.0f, 1.0f));
    cmd->callback([a, scene, apertures, &exit_code] {
      run_fig4(*a, *scene, *apertures);
      exit_code = 0;
    });
  }
}

}  // namespace svo::tools
