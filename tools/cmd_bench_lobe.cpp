// svo bench lobe-filter: Tokuyoshi 2015's figures (issue 19) measured on
// the engine, each against a converged reference of the same forward pass
// (DESIGN 10.5):
//   1. MSE over sigma_n^2 (the normal-aware weight, Eq. 4) and over beta
//      (the lobe-aware weight, Eq. 12) for single-material images (Phong
//      exponents 10, 100, 1000) and for one image holding all of them with
//      a glossiness map (paper Figs. 10 and 13);
//   2. anisotropic lobes (Fig. 9): Eq. 13 (ASG) against Eq. 12 and Eq. 4 on
//      grooves whose voxels' slopes spread along one axis;
//   3. upsampling from 1/4 of the size (Figs. 14-16) with one fixed
//      parameter each (chosen on the rough image, and the paper's), with
//      and without adaptive recomputation, of four inputs: the sampled
//      pass, the pre-convolved lookup, the cone-traced specular (Fig. 14)
//      and the cone-traced bumpy sphere (Fig. 15);
//   4. the filter's time per frame of each weight at radius 8 and 16 at
//      1920x1080 on every host asked for (Table 1);
//   5. the voxels' own slope covariance as the lobe, on a far view of the
//      bumpy sphere, against the material's lobe alone.
// The materials have no diffuse part, so that every error is the specular
// image's, as the paper measures it.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bench_util.h"
#include "commands.h"
#include "progress.h"
#include "source_options.h"
#include "svo/octree/files.h"
#include "svo/reference/compare.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "view_options.h"

namespace svo::tools {

namespace {

namespace fs = std::filesystem;
using bench::sci;

struct LobeArgs {
  std::string env = "/usr/share/blender/datafiles/studiolights/world/forest.exr";
  uint32_t resolution = 128;
  uint32_t size = 256;
  uint32_t spp = 4;
  uint32_t reference_spp = 1024;
  uint32_t upsample_spp = 64;
  uint32_t radius = 8;
  std::vector<uint32_t> timing_size{1920, 1080};
  std::vector<std::string> timing_devices{"native", "llvmpipe"};
  uint32_t repeats = 3;
  std::vector<uint32_t> parts{1, 2, 3, 4, 5};
  std::string device;
  std::string camera;  // part 1's images from this camera instead of the mid preset (svo render --camera's text)
  std::string out = "bench-lobe-filter";
};

const std::vector<float> kSigmas{1e-5f, 3e-5f, 1e-4f, 3e-4f, 1e-3f, 3e-3f, 1e-2f, 3e-2f, 0.1f, 0.3f, 1.0f};
const std::vector<float> kBetas{0.1f, 0.2f, 0.5f, 1.0f, 2.0f, 5.0f, 10.0f, 20.0f, 50.0f, 100.0f, 200.0f};

std::shared_ptr<const render::Material> specular_material(const std::string& name, render::BrdfKind kind,
                                                          float exponent, float roughness) {
  auto m = std::make_shared<render::Material>();
  m->name = name;
  m->kind = kind;
  m->exponent = exponent;
  m->roughness = roughness;
  m->diffuse = glm::vec3(0.0f);
  m->f0 = glm::vec3(0.9f);
  return m;
}

octree::Octree build(const std::string& scene, uint32_t resolution, ProgressBar& bar) {
  SourceOptions source;
  source.scene = scene;
  voxelizer::VoxelizeOptions vo;
  vo.resolution = resolution;
  vo.progress = [&](const std::string& stage, double f) { bar.update("voxelize " + scene + " " + stage, f); };
  return voxelizer::voxelize(*make_scene_source(source), vo);
}

// Mean over the pixels and R, G, B of the squared difference.
double mse(const render::Frame& a, const render::Frame& b) {
  double sum = 0;
  for (size_t i = 0; i < a.colour.size(); ++i) {
    const glm::vec3 d = glm::vec3(a.colour[i]) - glm::vec3(b.colour[i]);
    sum += double(glm::dot(d, d));
  }
  return sum / (3.0 * double(a.colour.size()));
}

// One test image: an octree, a view, materials.
struct Scene {
  std::string name;
  const octree::Octree* tree;
  render::RenderSettings settings;  // spp, materials and camera set; filter left to the runs
};

// The frames of one image: the reference and renderers for the filtered runs.
class Runs {
 public:
  Runs(const Scene& scene, const std::string& device, uint32_t reference_spp, uint32_t upsample)
      : scene_(scene), filtered_(render::make_renderer(*scene.tree, {device})) {
    auto plain = render::make_renderer(*scene.tree, {device});
    plain->add_pass(render::make_pass("forward"));
    render::RenderSettings s = scene.settings;
    s.shading.spp = reference_spp;
    s.shading.seed = 7;  // other samples than the filtered runs'
    reference = plain->render(s);
    noisy = plain->render(scene.settings);
    filtered_->add_pass(std::make_unique<render::ForwardPass>(render::ForwardOutput{true, upsample}));
    filtered_->add_pass(std::make_unique<render::LobeFilterPass>(upsample));
  }
  render::Frame run(const render::FilterOptions& filter) {
    render::RenderSettings s = scene_.settings;
    s.filter = filter;
    return filtered_->render(s);
  }
  // The share of covered pixels the last upsampled frame shaded again
  // (the filter's weight image, z).
  double shaded_again() {
    render::FrameImages& images = filtered_->images();
    auto w = images.texels<const glm::vec4>(images.read(render::LobeFilterPass::weight_image()));
    auto c = images.texels<const glm::vec4>(images.read(render::colour_image()));
    double again = 0, covered = 0;
    for (size_t i = 0; i < size_t(images.width()) * images.height(); ++i) {
      if (!(c[i].a > 0)) continue;
      covered += 1;
      again += w[i].z > 0.5f ? 1 : 0;
    }
    return covered > 0 ? again / covered : 0;
  }
  // The lobe-filter pass's time in the last frame, ms.
  static double filter_ms(const render::Frame& f) {
    for (const auto& p : f.passes)
      if (p.name == "lobe-filter" || p.name == "lobe-upsample") return p.ms;
    return -1;
  }
  render::Frame reference, noisy;

 private:
  const Scene& scene_;
  std::unique_ptr<render::Renderer> filtered_;
};

struct Sweep {
  std::vector<double> mse;  // per parameter value
  size_t best = 0;
  render::Frame best_frame;
};

Sweep sweep(Runs& runs, render::FilterOptions base, bool over_beta, const std::vector<float>& values,
            const std::function<void(double)>& progress) {
  Sweep s;
  for (size_t i = 0; i < values.size(); ++i) {
    render::FilterOptions f = base;
    (over_beta ? f.beta : f.sigma_n2) = values[i];
    render::Frame frame = runs.run(f);
    s.mse.push_back(mse(frame, runs.reference));
    if (s.mse.back() <= s.mse[s.best] || i == 0) {
      s.best = i;
      s.best_frame = std::move(frame);
    }
    progress(double(i + 1) / double(values.size()));
  }
  return s;
}

// The paper's Fig. 10: MSE against sigma_n^2 (normal-aware) and against
// beta (lobe-aware), one line per image, from results.csv's fig10 rows.
void write_fig10_plot(const fs::path& dir, const std::vector<std::string>& images) {
  bench::TextFile gp(dir / "fig10.gp");
  gp << "set terminal pngcairo size 960,420 font 'sans,10'\nset output '" << (dir / "fig10.png").string()
     << "'\nset datafile separator ','\nset logscale xy\nset grid\nset key top left\nset ylabel 'MSE'\n"
     << "set multiplot layout 1,2 title 'Fig. 10: the error of each weight over its parameter'\n";
  const char* colours[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2"};
  for (const char* weight : {"normal", "lobe"}) {
    const bool lobe = std::string(weight) == "lobe";
    gp << "set title '" << (lobe ? "lobe-aware (Eq. 12)" : "normal-aware (Eq. 4)") << "'\nset xlabel '"
       << (lobe ? "beta" : "sigma_n^2") << "'\nset format x '" << (lobe ? "%g" : "10^{%L}") << "'\nplot ";
    for (size_t i = 0; i < images.size(); ++i) {
      gp << (i ? ", " : "") << "'" << (dir / "results.csv").string()
         << "' every ::1 using (stringcolumn(1) eq 'fig10' && stringcolumn(2) eq '" << images[i]
         << "' && stringcolumn(3) eq '" << weight << "' ? $5 : 1/0):6 with linespoints pt 7 lc '" << colours[i % 6]
         << "' title '" << images[i] << "'";
    }
    gp << "\n";
  }
  gp << "unset multiplot\n";
  gp.save();
  bench::run_gnuplot(dir / "fig10.gp");
}

void write_png(const fs::path& path, const render::Frame& frame) { render::write_colour(path.string(), frame); }

// The per-pixel error of `frame` against the reference, as a heat map.
render::Frame error_map(const render::Frame& frame, const render::Frame& reference, double scale) {
  return reference::error_image(render::frame_image(frame), render::frame_image(reference), scale);
}

void run_lobe_bench(const LobeArgs& a) {
  fs::path dir(a.out);
  fs::create_directories(dir);
  render::check_writable_output((dir / "results.csv").string());
  if (!fs::is_regular_file(a.env)) {
    throw std::runtime_error("--env " + a.env +
                             ": not a file (an environment map lights every image; Debian's blender-data has "
                             "/usr/share/blender/datafiles/studiolights/world/forest.exr)");
  }
  LightingOptions lighting;
  lighting.env = a.env;
  ProgressBar bar("bench lobe-filter");
  auto wants = [&](uint32_t n) { return std::find(a.parts.begin(), a.parts.end(), n) != a.parts.end(); };
  const octree::Octree spheres = build("material-spheres", a.resolution, bar);
  const octree::Octree grooves = wants(2) ? build("grooved-cylinder", a.resolution, bar) : octree::Octree{};
  const octree::Octree bumpy = wants(3) || wants(5) ? build("bumpy-sphere", a.resolution, bar) : octree::Octree{};

  render::RenderSettings lit;  // the environment, read once
  apply_lighting(lighting, lit);
  auto settings_of = [&](const octree::Octree& tree, const std::string& view, uint32_t w, uint32_t h) {
    render::RenderSettings s = lit;
    s.width = w;
    s.height = h;
    s.camera = render::view_preset(tree, view, float(w) / float(h));
    s.lights.clear();
    s.shading.spp = a.spp;
    s.shading.seed = 1;
    s.filter.radius = a.radius;
    return s;
  };
  using render::BrdfKind;
  auto phong = [&](float e) { return specular_material("phong-" + std::to_string(int(e)), BrdfKind::Phong, e, 0.2f); };
  std::vector<Scene> singles;
  for (float e : {10.0f, 100.0f, 1000.0f}) {
    Scene s{"phong-" + std::to_string(int(e)), &spheres, settings_of(spheres, "mid", a.size, a.size)};
    s.settings.shading.material = phong(e);
    singles.push_back(s);
  }
  // All three with a glossiness map: the floor's tiles 1000 and 10, the
  // spheres 10, 100, 1000 (material-spheres' slots: floor-glossy,
  // floor-rough, the left, middle and right spheres).
  Scene mixed{"mixed", &spheres, settings_of(spheres, "mid", a.size, a.size)};
  mixed.settings.shading.scene_materials = {phong(1000), phong(10), phong(10), phong(100), phong(1000)};

  const auto& part = wants;
  nlohmann::json results = nlohmann::json::object();
  bench::TextFile csv(dir / "results.csv");
  csv << "experiment,image,weight,parameter,value,mse\n";
  std::ostringstream md;
  // What is measured so far, written after every part (a later part's
  // failure keeps the earlier ones).
  auto save = [&]() {
    files::write_file((dir / "results.json").string(), results.dump(2) + "\n");
    files::write_file((dir / "table.md").string(), md.str());
    csv.save();
  };
  md << "# Lobe-aware filtering (Tokuyoshi 2015) on the engine\n\n"
     << "Environment " << a.env << "; octrees at " << a.resolution << "^3; " << a.size << "x" << a.size
     << " frames; forward pass at " << a.spp << " spp filtered, against the same pass at " << a.reference_spp
     << " spp; radius " << a.radius << "; materials without diffuse part (errors are the specular image's).\n\n";

  // --- 1. Figs. 10 and 13.
  if (part(1)) {
    md << "## 1. MSE over sigma_n^2 (normal-aware, Eq. 4) and beta (lobe-aware, Eq. 12)\n\n"
       << "| image | unfiltered | normal: best sigma_n^2 | its MSE | lobe: best beta | its MSE | lobe / normal |\n"
       << "|---|---|---|---|---|---|---|\n";
    std::vector<Scene> images = singles;
    images.push_back(mixed);
    if (!a.camera.empty()) {
      const render::Camera c = render::parse_camera(a.camera);
      for (Scene& scene : images) scene.settings.camera = c;
    } else {
      // The mixed image again from the mid view as framed before
      // 2026-12-02's presets (3x closer than the whole domain's far view;
      // the spheres and tiles larger in the frame): how much the ratio owes
      // to the view.
      Scene closer = mixed;
      closer.name = "mixed-domain-mid";
      render::PresetOptions domain;
      domain.whole_domain = true;
      closer.settings.camera = render::view_preset(spheres, "mid", 1.0f, domain);
      images.push_back(closer);
    }
    std::vector<float> best_sigma, best_beta;
    nlohmann::json fig10 = nlohmann::json::array();
    for (size_t k = 0; k < images.size(); ++k) {
      const Scene& scene = images[k];
      auto stage = [&](const std::string& what) {
        return [&, what](double f) { bar.update(scene.name + " " + what, (double(k) + f) / double(images.size())); };
      };
      stage("reference")(0);
      Runs runs(scene, a.device, a.reference_spp, 1);
      render::FilterOptions normal;
      normal.weight = render::FilterWeight::Normal;
      normal.radius = a.radius;
      render::FilterOptions lobe = normal;
      lobe.weight = render::FilterWeight::Lobe;
      const Sweep n = sweep(runs, normal, false, kSigmas, stage("normal"));
      const Sweep l = sweep(runs, lobe, true, kBetas, stage("lobe"));
      const double raw = mse(runs.noisy, runs.reference);
      md << "| " << scene.name << " | " << sci(raw) << " | " << kSigmas[n.best] << " | " << sci(n.mse[n.best]) << " | "
         << kBetas[l.best] << " | " << sci(l.mse[l.best]) << " | " << bench::fmt(l.mse[l.best] / n.mse[n.best], 2)
         << " |\n";
      for (size_t i = 0; i < kSigmas.size(); ++i)
        csv << "fig10," << scene.name << ",normal,sigma_n2," << kSigmas[i] << "," << n.mse[i] << "\n";
      for (size_t i = 0; i < kBetas.size(); ++i)
        csv << "fig10," << scene.name << ",lobe,beta," << kBetas[i] << "," << l.mse[i] << "\n";
      csv << "fig10," << scene.name << ",none,,," << raw << "\n";
      fig10.push_back({{"image", scene.name},
                       {"unfiltered", raw},
                       {"normal", {{"sigma_n2", kSigmas}, {"mse", n.mse}, {"best", kSigmas[n.best]}}},
                       {"lobe", {{"beta", kBetas}, {"mse", l.mse}, {"best", kBetas[l.best]}}}});
      if (k < singles.size()) {
        best_sigma.push_back(kSigmas[n.best]);
        best_beta.push_back(kBetas[l.best]);
      } else {
        results[scene.name == "mixed" ? "mixed_lobe_over_normal" : "mixed_domain_mid_lobe_over_normal"] =
            l.mse[l.best] / n.mse[n.best];
      }
      write_png(dir / (scene.name + "-strip.png"),
                bench::strip({{&runs.noisy, &n.best_frame, &l.best_frame, &runs.reference}}));
      const double scale = std::sqrt(std::max(n.mse[n.best], l.mse[l.best])) * 4.0;
      const render::Frame en = error_map(n.best_frame, runs.reference, scale);
      const render::Frame el = error_map(l.best_frame, runs.reference, scale);
      write_png(dir / (scene.name + "-error.png"), bench::strip({{&en, &el}}));
    }
    auto spread = [](const std::vector<float>& v) {
      return double(*std::max_element(v.begin(), v.end())) / double(*std::min_element(v.begin(), v.end()));
    };
    results["fig10"] = fig10;
    results["best_sigma_n2_spread"] = spread(best_sigma);
    results["best_beta_spread"] = spread(best_beta);
    md << "\nBest parameters of the single-material images: sigma_n^2 over a factor "
       << bench::fmt(spread(best_sigma), 1) << ", beta over a factor " << bench::fmt(spread(best_beta), 1)
       << ". Mixed image: lobe-aware MSE at its best beta / normal-aware MSE at its best sigma_n^2 = "
       << bench::fmt(results["mixed_lobe_over_normal"].get<double>(), 3) << " (target <= 0.8)";
    if (results.contains("mixed_domain_mid_lobe_over_normal"))
      md << "; from the mid view with whole-domain framing (mixed-domain-mid) "
         << bench::fmt(results["mixed_domain_mid_lobe_over_normal"].get<double>(), 3);
    md << ".\n"
       << "Strips (`IMAGE-strip.png`): 4 spp, normal-aware at its best, lobe-aware at its best, reference. "
       << "Error maps (`IMAGE-error.png`): normal-aware, lobe-aware. MSE over sigma_n^2 and beta: `fig10.png` "
          "(gnuplot, `fig10.gp`).\n\n";
    save();
    std::vector<std::string> names;
    for (const Scene& scene : images) names.push_back(scene.name);
    write_fig10_plot(dir, names);
  }

  save();
  // --- 2. Fig. 9: anisotropic lobes on grooves.
  if (part(2)) {
    bar.update("grooves", 0);
    // Three times farther than the far preset: the grooves are under a
    // pixel, and the voxels' slopes spread across them (an anisotropic lobe
    // outside, an isotropic one on the smooth inside).
    Scene g{"grooves", &grooves, settings_of(grooves, "far", a.size, a.size)};
    render::Camera& c = g.settings.camera;
    c.eye = c.target + 3.0f * (c.eye - c.target);
    g.settings.shading.material = specular_material("beckmann-0.05", BrdfKind::Beckmann, 100, 0.05f);
    Runs runs(g, a.device, a.reference_spp, 1);
    auto progress = [&](double f) { bar.update("grooves", f); };
    render::FilterOptions normal;
    normal.weight = render::FilterWeight::Normal;
    normal.radius = a.radius;
    render::FilterOptions lobe = normal, asg = normal;
    lobe.weight = render::FilterWeight::Lobe;
    asg.weight = render::FilterWeight::Asg;
    const Sweep n = sweep(runs, normal, false, kSigmas, progress);
    const Sweep l = sweep(runs, lobe, true, kBetas, progress);
    const Sweep s = sweep(runs, asg, true, kBetas, progress);
    md << "## 2. Anisotropic lobes (Fig. 9): grooved cylinder, 3x the far view's distance, Beckmann alpha "
          "0.05\n\n"
       << "| weight | best parameter | MSE |\n|---|---|---|\n"
       << "| unfiltered | | " << sci(mse(runs.noisy, runs.reference)) << " |\n"
       << "| normal (Eq. 4) | sigma_n^2 " << kSigmas[n.best] << " | " << sci(n.mse[n.best]) << " |\n"
       << "| lobe (Eq. 12) | beta " << kBetas[l.best] << " | " << sci(l.mse[l.best]) << " |\n"
       << "| asg (Eq. 13) | beta " << kBetas[s.best] << " | " << sci(s.mse[s.best]) << " |\n\n"
       << "Strip (`grooves-strip.png`): 4 spp, normal, lobe, asg, reference.\n\n";
    for (size_t i = 0; i < kBetas.size(); ++i) csv << "fig9,grooves,asg,beta," << kBetas[i] << "," << s.mse[i] << "\n";
    for (size_t i = 0; i < kBetas.size(); ++i) csv << "fig9,grooves,lobe,beta," << kBetas[i] << "," << l.mse[i] << "\n";
    for (size_t i = 0; i < kSigmas.size(); ++i)
      csv << "fig9,grooves,normal,sigma_n2," << kSigmas[i] << "," << n.mse[i] << "\n";
    results["fig9"] = {{"normal", n.mse[n.best]}, {"lobe", l.mse[l.best]}, {"asg", s.mse[s.best]}};
    write_png(dir / "grooves-strip.png",
              bench::strip({{&runs.noisy, &n.best_frame, &l.best_frame, &s.best_frame, &runs.reference}}));
  }

  save();
  // --- 3. Figs. 14-16: upsampling from 1/4. As in Fig. 14, each weight's
  // parameter is chosen once, on the rough image, and kept for the sharp and
  // the mixed one.
  // The table of one kind of input (the sampled pass, or the pre-convolved
  // lookup); `key` names its CSV rows, JSON entries and strip.
  auto upsampling = [&](std::vector<Scene> ups, const std::string& key, const std::string& title) {
    std::vector<std::unique_ptr<Runs>> runs;
    for (const Scene& scene : ups) runs.push_back(std::make_unique<Runs>(scene, a.device, a.reference_spp, 4));
    md << title << "| weight | parameter | " << ups[0].name << " | " << ups[1].name << " | " << ups[2].name << " | "
       << ups[2].name << ", recomputed under 0.25 | pixels shaded again |\n|---|---|---|---|---|---|---|\n";
    nlohmann::json up = nlohmann::json::array();
    std::vector<render::Frame> frames;
    // One row: the three images with `f`, then the third recomputed under
    // 0.25; returns the share of its pixels shaded again.
    auto row = [&](render::FilterOptions f, const std::string& label, std::vector<render::Frame>& out) {
      const bool lobe = f.weight == render::FilterWeight::Lobe;
      const float value = lobe ? f.beta : f.sigma_n2;
      md << "| " << label << " | " << (lobe ? "beta " : "sigma_n^2 ") << value;
      nlohmann::json r{{"weight", render::filter_weight_name(f.weight)}, {"label", label}, {"parameter", value}};
      std::string tag = label;  // the CSV's column: no comma
      std::replace(tag.begin(), tag.end(), ',', ';');
      for (size_t k = 0; k < ups.size(); ++k) {
        out.push_back(runs[k]->run(f));
        const double e = mse(out.back(), runs[k]->reference);
        md << " | " << sci(e);
        r[ups[k].name] = e;
        csv << key << "," << ups[k].name << "," << tag << ",recompute,0," << e << "\n";
      }
      f.recompute = 0.25f;
      out.push_back(runs[2]->run(f));
      const double e = mse(out.back(), runs[2]->reference);
      const double shaded = runs[2]->shaded_again();
      md << " | " << sci(e) << " | " << bench::fmt(100.0 * shaded, 1) << "% |\n";
      r["mixed_recomputed"] = e;
      r["shaded_again"] = shaded;
      csv << key << "," << ups[2].name << "," << tag << ",recompute,0.25," << e << "\n";
      up.push_back(r);
      return shaded;
    };
    double lobe_share = 0;
    render::FilterOptions tuned_normal;
    for (auto weight : {render::FilterWeight::Normal, render::FilterWeight::Lobe}) {
      const bool lobe = weight == render::FilterWeight::Lobe;
      render::FilterOptions f;
      f.weight = weight;
      f.recompute = 0.0f;
      const Sweep tuned = sweep(*runs[0], f, lobe, lobe ? kBetas : kSigmas, [&](double x) {
        bar.update("upsampling " + std::string(render::filter_weight_name(weight)), 0.5 * (x + (lobe ? 1 : 0)));
      });
      (lobe ? f.beta : f.sigma_n2) = (lobe ? kBetas : kSigmas)[tuned.best];
      const double shaded = row(f, render::filter_weight_name(weight), frames);
      if (lobe) lobe_share = shaded;
      if (!lobe) tuned_normal = f;
    }
    // The paper's own parameters of Fig. 14 (sigma_n^2 0.01, beta 20,
    // chosen there by hand), the same for every image.
    std::vector<render::Frame> paper;
    for (auto weight : {render::FilterWeight::Normal, render::FilterWeight::Lobe}) {
      render::FilterOptions f;
      f.weight = weight;
      f.recompute = 0.0f;
      f.sigma_n2 = 0.01f;
      f.beta = 20.0f;
      row(f, std::string(render::filter_weight_name(weight)) + ", Fig. 14's parameter", paper);
    }
    // At equal cost: the normal-aware weight with the threshold that shades
    // about as many pixels again as the lobe-aware one does under 0.25.
    {
      double best_gap = 2, matched_mse = 0, matched_share = 0;
      float matched = 0;
      for (float t = 0.05f; t < 0.999f; t += 0.05f) {
        render::FilterOptions f = tuned_normal;
        f.recompute = t;
        const render::Frame frame = runs[2]->run(f);
        const double share = runs[2]->shaded_again();
        if (std::abs(share - lobe_share) < best_gap) {
          best_gap = std::abs(share - lobe_share);
          matched = t;
          matched_mse = mse(frame, runs[2]->reference);
          matched_share = share;
        }
      }
      md << "| normal, threshold matched to the lobe's share | sigma_n^2 " << tuned_normal.sigma_n2 << " | | | | "
         << sci(matched_mse) << " (under " << bench::fmt(matched, 2) << ") | " << bench::fmt(100.0 * matched_share, 1)
         << "% |\n";
      results[key + "_normal_matched"] = {
          {"threshold", matched}, {"mse", matched_mse}, {"shaded_again", matched_share}};
    }
    // frames: normal rough, sharp, mixed, mixed recomputed; then the same for lobe.
    const std::string strip = key == "fig14" ? "upsample-strip.png" : "upsample-" + key + "-strip.png";
    write_png(dir / strip, bench::strip({{&frames[1], &frames[5], &runs[1]->reference},
                                         {&frames[2], &frames[6], &runs[2]->reference},
                                         {&frames[3], &frames[7], &runs[2]->reference}}));
    write_png(dir / ("upsample-" + key + "-paper-strip.png"),
              bench::strip({{&paper[1], &paper[5], &runs[1]->reference},
                            {&paper[2], &paper[6], &runs[2]->reference},
                            {&paper[3], &paper[7], &runs[2]->reference}}));
    results[key] = up;
    md << "\nStrip (`" << strip << "`), rows " << ups[1].name << ", " << ups[2].name << ", " << ups[2].name
       << " recomputed under 0.25; columns normal-aware, lobe-aware, reference; the same with Fig. 14's "
          "parameters in `upsample-"
       << key << "-paper-strip.png`.\n\n";
  };
  if (part(3)) {
    bar.update("upsampling", 0);
    std::vector<Scene> ups{singles.front(), singles.back(), mixed};
    for (Scene& scene : ups) scene.settings.shading.spp = a.upsample_spp;
    upsampling(ups, "fig14",
               "## 3. Upsampling from 1/4 (Figs. 14-16): " + std::to_string(a.upsample_spp) +
                   " spp at 1/4 of the size, kappa 100; each weight's parameter chosen on " + ups[0].name +
                   " (the rough image) and kept\n\n");
    // The paper upsamples voxel-cone-traced specular, smooth already: the
    // pre-convolved lookup (--env-preconvolved, one cone along the lobe
    // when --env-shadows), against itself at the full size.
    bar.update("upsampling pre-convolved", 0);
    const auto pre = std::make_shared<const render::PreconvolvedEnvironment>(
        render::preconvolve_environment(*lit.shading.environment));
    for (Scene& scene : ups) scene.settings.shading.preconvolved = pre;
    upsampling(ups, "fig14_preconvolved",
               "\n### 3b. Upsampling the pre-convolved specular from 1/4: one lookup per pixel at 1/4 of the size, "
               "against the same lookup at the full size; parameters chosen on " +
                   ups[0].name + " and kept\n\n");
    // Fig. 14's input: the specular cone-traced through the octree (one
    // cone along each lobe, --env-shadows), so that the spheres' shadows
    // and reflections of one another are in the image.
    bar.update("upsampling cone-traced", 0);
    for (Scene& scene : ups) scene.settings.shading.env_shadows = true;
    upsampling(ups, "fig14_cones",
               "\n### 3c. Upsampling the cone-traced specular from 1/4 (Fig. 14's input): the pre-convolved lookup "
               "with one cone along each lobe through the octree; parameters chosen on " +
                   ups[0].name + " and kept\n\n");
    // Fig. 15: normals and lobe widths that change from pixel to pixel
    // (the paper's normal maps with filtered mipmaps; here the bumpy
    // sphere's bumps, a few pixels across, and the voxels' slopes).
    bar.update("upsampling bumps", 0);
    std::vector<Scene> bumps;
    for (float e : {10.0f, 1000.0f, 100.0f}) {
      Scene s{"bumpy-phong-" + std::to_string(int(e)), &bumpy, settings_of(bumpy, "mid", a.size, a.size)};
      s.settings.shading.material = phong(e);
      s.settings.shading.preconvolved = pre;
      s.settings.shading.env_shadows = true;
      bumps.push_back(s);
    }
    upsampling(bumps, "fig15",
               "\n### 3d. Fig. 15: the bumpy sphere's mid view, cone-traced specular, upsampled from 1/4; the "
               "third image (phong-100) is the one recomputed; parameters chosen on " +
                   bumps[0].name + " and kept\n\n");
  }
  save();
  // --- 5. The voxels' slopes as the lobe: the bumpy sphere seen from afar,
  // a sharp material, lobes with and without the voxels' slope covariance.
  if (part(5)) {
    bar.update("voxel slopes", 0);
    // Three times farther than the far preset: the bumps are under a pixel,
    // so that the voxels' slopes carry them. Twice: from the far preset
    // (framed on the sphere) and from the whole domain's far view, the
    // preset of 2026-12-02, about 1.5x farther from the sphere: there the
    // bumps are about a pixel, and only there do the voxels' slopes help
    // (docs/RESULTS.md, "The voxels' slopes as the lobe").
    md << "## 5. The voxels' slope covariance as the lobe: bumpy sphere, 3x the far view's distance, Beckmann "
          "alpha 0.05\n\n"
       << "| view | unfiltered | normal-aware (Eq. 4): best sigma_n^2 | its MSE | material and voxel slopes (Eq. 12): "
          "best beta | its MSE | material alone (Eq. 12): best beta | its MSE | with / without |\n"
       << "|---|---|---|---|---|---|---|---|---|\n";
    render::PresetOptions domain;
    domain.whole_domain = true;
    const std::pair<std::string, render::Camera> views[] = {
        {"bumpy-far", render::view_preset(bumpy, "far", 1.0f)},
        {"bumpy-far-domain", render::view_preset(bumpy, "far", 1.0f, domain)}};
    for (size_t v = 0; v < std::size(views); ++v) {
      Scene b{views[v].first, &bumpy, settings_of(bumpy, "far", a.size, a.size)};
      render::Camera& c = b.settings.camera;
      c = views[v].second;
      c.eye = c.target + 3.0f * (c.eye - c.target);
      b.settings.shading.material = specular_material("beckmann-0.05", BrdfKind::Beckmann, 100, 0.05f);
      Runs runs(b, a.device, a.reference_spp, 1);
      auto progress = [&](double f) { bar.update("voxel slopes", (double(v) + f) / double(std::size(views))); };
      render::FilterOptions normal;
      normal.weight = render::FilterWeight::Normal;
      normal.radius = a.radius;
      render::FilterOptions with = normal, without = normal;
      with.weight = without.weight = render::FilterWeight::Lobe;
      without.voxel_slopes = false;
      const Sweep n = sweep(runs, normal, false, kSigmas, progress);
      const Sweep w = sweep(runs, with, true, kBetas, progress);
      const Sweep o = sweep(runs, without, true, kBetas, progress);
      md << "| " << b.name << " | " << sci(mse(runs.noisy, runs.reference)) << " | " << kSigmas[n.best] << " | "
         << sci(n.mse[n.best]) << " | " << kBetas[w.best] << " | " << sci(w.mse[w.best]) << " | " << kBetas[o.best]
         << " | " << sci(o.mse[o.best]) << " | " << bench::fmt(w.mse[w.best] / o.mse[o.best], 2) << " |\n";
      for (size_t i = 0; i < kBetas.size(); ++i) {
        csv << "slopes," << b.name << ",lobe+voxels,beta," << kBetas[i] << "," << w.mse[i] << "\n";
        csv << "slopes," << b.name << ",lobe,beta," << kBetas[i] << "," << o.mse[i] << "\n";
      }
      results[v == 0 ? "voxel_slopes" : "voxel_slopes_domain"] = {
          {"normal", n.mse[n.best]}, {"with", w.mse[w.best]}, {"without", o.mse[o.best]}};
      write_png(dir / (b.name + "-strip.png"),
                bench::strip({{&runs.noisy, &n.best_frame, &w.best_frame, &o.best_frame, &runs.reference}}));
    }
    md << "\nStrips (`bumpy-far-strip.png`, `bumpy-far-domain-strip.png`): 4 spp, normal, lobes with voxel slopes, "
          "without, reference. From the whole domain's far view the sphere is about 1.5x smaller (about 40 against "
          "58 pixels across at 256x256), its bumps about a pixel.\n\n";
  }

  save();
  // --- 4. Table 1: the filter's time per weight, radius and host.
  if (part(4)) {
    const uint32_t tw = a.timing_size.at(0), th = a.timing_size.at(1);
    md << "## 4. The filter's time per frame at " << tw << "x" << th << " (Table 1), median of " << a.repeats
       << "\n\n| host | radius | normal (Eq. 4) | lobe (Eq. 12) | mixture (Eq. 11) | asg (Eq. 13) | Eq. 12 / Eq. 4 |\n"
       << "|---|---|---|---|---|---|---|\n";
    nlohmann::json timing = nlohmann::json::array();
    const auto weights = {render::FilterWeight::Normal, render::FilterWeight::Lobe, render::FilterWeight::Mixture,
                          render::FilterWeight::Asg};
    size_t done = 0;
    const size_t total = a.timing_devices.size() * 2 * weights.size();
    for (const std::string& device : a.timing_devices) {
      std::unique_ptr<render::Renderer> r = render::make_renderer(spheres, {device});
      r->add_pass(std::make_unique<render::ForwardPass>(render::ForwardOutput{true, 1}));
      r->add_pass(std::make_unique<render::LobeFilterPass>(1));
      render::RenderSettings s = settings_of(spheres, "mid", tw, th);
      s.shading.spp = 1;
      s.shading.scene_materials = mixed.settings.shading.scene_materials;
      // A device whose storage buffers cannot hold the frame's G-buffer
      // (lavapipe: 128 MiB, 96 bytes a pixel) times the largest 16:9 frame
      // that fits, and says so.
      try {
        r->render(s);
      } catch (const std::exception& e) {
        std::cerr << "svo: " << r->device_name() << ": " << e.what() << "; timing at 1280x720 there\n";
        s = settings_of(spheres, "mid", 1280, 720);
        s.shading.spp = 1;
        s.shading.scene_materials = mixed.settings.shading.scene_materials;
      }
      for (uint32_t radius : {8u, 16u}) {
        md << "| " << r->device_name() << " (" << s.width << "x" << s.height << ") | " << radius;
        std::vector<double> ms;
        for (auto weight : weights) {
          bar.update("timing " + device, double(done++) / double(total));
          s.filter.weight = weight;
          s.filter.radius = radius;
          std::vector<double> t;
          for (uint32_t k = 0; k < a.repeats; ++k) t.push_back(Runs::filter_ms(r->render(s)));
          std::sort(t.begin(), t.end());
          ms.push_back(t[t.size() / 2]);
          md << " | " << bench::fmt(ms.back(), 1);
          timing.push_back({{"device", r->device_name()},
                            {"radius", radius},
                            {"weight", render::filter_weight_name(weight)},
                            {"ms", ms.back()}});
          csv << "table1," << device << "," << render::filter_weight_name(weight) << ",radius," << radius << ","
              << ms.back() << "\n";
        }
        md << " | " << bench::fmt(ms[1] / ms[0], 2) << " |\n";
      }
    }
    results["table1"] = timing;
    md << "\nTimes are the lobe-filter pass's (per-pixel lobes, rows and columns), device timestamps on Vulkan, "
          "wall clock natively.\n";
  }
  save();
  bar.finish();
  std::cout << md.str();
}

}  // namespace

void add_bench_lobe_command(CLI::App& bench, int& exit_code) {
  auto a = std::make_shared<LobeArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "lobe-filter",
      "Tokuyoshi 2015's figures on the engine, against a converged reference: MSE over sigma_n^2 and beta for "
      "single-material and mixed images (Figs. 10, 13), anisotropic lobes (Fig. 9), upsampling from 1/4 with "
      "recomputation (Figs. 14-16), the filter's time per weight at radius 8 and 16 (Table 1) and the voxels' "
      "slopes as the lobe; writes table.md, results.csv, results.json, image strips, error maps and fig10.png (MSE "
      "over sigma_n^2 and beta; gnuplot) to --out");
  cmd->add_option("--env", a->env, "Environment map lighting every image")->capture_default_str();
  cmd->add_option("--resolution", a->resolution, "Finest lattice cells per axis of the octrees")
      ->capture_default_str()
      ->check(CLI::Range(16u, 1024u));
  cmd->add_option("--size", a->size, "Image width and height, pixels")
      ->capture_default_str()
      ->check(CLI::Range(16u, 2048u));
  cmd->add_option("--spp", a->spp, "Samples per pixel of the filtered input")
      ->capture_default_str()
      ->check(CLI::Range(1u, 4096u));
  cmd->add_option("--reference-spp", a->reference_spp, "Samples per pixel of the reference")
      ->capture_default_str()
      ->check(CLI::Range(1u, 65536u));
  cmd->add_option("--upsample-spp", a->upsample_spp, "Samples per pixel of the 1/4-size input of the upsampling")
      ->capture_default_str()
      ->check(CLI::Range(1u, 65536u));
  cmd->add_option("--radius", a->radius, "The filter's radius for the MSE figures")
      ->capture_default_str()
      ->check(CLI::Range(1u, 64u));
  cmd->add_option("--timing-size", a->timing_size, "Width and height of the timing frames")
      ->expected(2)
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--timing-devices", a->timing_devices, "Hosts of the timing table (native, a Vulkan device)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--repeats", a->repeats, "Frames per timing; the median is reported")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100u));
  cmd->add_option(
         "--parts", a->parts,
         "The experiments to run: 1 (Figs. 10, 13), 2 (Fig. 9), 3 (Figs. 14-16), 4 (Table 1), 5 (voxel slopes)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(1u, 5u));
  cmd->add_option("--camera", a->camera,
                  "Part 1: every image from this camera, ex,ey,ez,tx,ty,tz,ux,uy,uz,fov as svo render --camera "
                  "(default: the mid preset, and the mixed image also with whole-domain framing)");
  cmd->add_option("--device", a->device, kDeviceHelp);
  cmd->add_option("-o,--out", a->out, "Output directory (created)")->capture_default_str();
  cmd->callback([a, &exit_code] {
    run_lobe_bench(*a);
    exit_code = 0;
  });
}

}  // namespace svo::tools
