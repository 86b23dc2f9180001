// svo bench luminaire: Lu et al. 2015's figures (issue 18) measured on the
// engine, each against a ground truth of the same G-buffer (DESIGN 10.4):
//   1. restricted, uniform and global sampling at equal samples per pixel:
//      mean CIE Lab error and relMSE against dense quadrature (Fig. 12 left,
//      Fig. 11), and the samples uniform and global sampling need to reach
//      the restricted sampler's error (Fig. 12 right, Fig. 11);
//   2. K_max = 7 against no cap (Fig. 9);
//   3. the Halton sequence against independent random numbers at 16 to 1024
//      samples (Fig. 8);
//   4. the modified secant search against binary search at equal depth (Fig. 5);
//   5. visibility by one cone per basis cell against one per sample (Fig. 7),
//      against per-sample visibility at many samples;
//   6. frame times at 200 samples per pixel on every host asked for, split
//      into the passes and the luminaire pass's parts (Fig. 10).
// Parts 1-4 shade without visibility, so that the quadrature (no shadows)
// is their ground truth; the errors are those of the estimators alone.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "bench_util.h"
#include "commands.h"
#include "progress.h"
#include "source_options.h"
#include "svo/octree/files.h"
#include "svo/reference/compare.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/luminaire.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "view_options.h"

namespace svo::tools {

namespace {

namespace fs = std::filesystem;
using bench::machine_description;
using bench::relmse;
using bench::sci;

struct LuminaireBenchArgs {
  std::string scene = "material-spheres";
  // Procedural emitters by name (led, headlight) or .lfl files; part 1 runs
  // for each, the other parts for the first.
  std::vector<std::string> luminaires{"led", "headlight"};
  uint32_t resolution = 128;
  uint32_t size = 192;
  uint32_t spp = 256;
  uint32_t max_uniform_spp = 8192;
  uint32_t max_global_spp = 16384;
  uint32_t quadrature = 1;
  uint32_t visibility_reference_spp = 2048;
  std::vector<uint32_t> timing_size{512, 512};
  std::vector<std::string> timing_devices{"native", "llvmpipe"};
  uint32_t repeats = 3;
  bool glossy = false;
  std::vector<uint32_t> parts{1, 2, 3, 4, 5, 6};
  std::string out = "bench-luminaire";
};

// CIE L*a*b* (D65) of a linear sRGB colour.
glm::dvec3 lab(glm::dvec3 c) {
  const double x = (0.4124 * c.r + 0.3576 * c.g + 0.1805 * c.b) / 0.95047;
  const double y = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
  const double z = (0.0193 * c.r + 0.1192 * c.g + 0.9505 * c.b) / 1.08883;
  auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
  return {116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))};
}

// The paper's error: both images tone-mapped by the global exponential
// operator 1 - exp(-L / L_avg) with the reference's mean luminance L_avg,
// then the mean CIE76 distance in L*a*b* over the pixels.
double mean_lab_error(const render::Frame& image, const render::Frame& reference) {
  double avg = 0;
  for (const auto& c : reference.colour) avg += 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
  avg = std::max(avg / double(reference.colour.size()), 1e-12);
  auto tone = [&](const glm::vec4& c) {
    return glm::dvec3(1.0 - std::exp(-c.r / avg), 1.0 - std::exp(-c.g / avg), 1.0 - std::exp(-c.b / avg));
  };
  double sum = 0;
  for (size_t i = 0; i < image.colour.size(); ++i)
    sum += glm::length(lab(tone(image.colour[i])) - lab(tone(reference.colour[i])));
  return sum / double(image.colour.size());
}

double pass_ms(const render::Frame& f, const std::string& name) {
  for (const auto& p : f.passes)
    if (p.name == name) return p.ms;
  return -1;
}

// The samples at which `error(spp)` falls to `target`, from a sweep doubling
// spp from `from` to `to`: log-log interpolation between the two sweeps
// around it; 0 when the sweep does not reach it.
struct EqualError {
  std::vector<std::pair<uint32_t, double>> sweep;  // (spp, error)
  double spp = 0;
};

EqualError equal_error(const std::function<double(uint32_t)>& error, double target, uint32_t from, uint32_t to) {
  EqualError e;
  for (uint32_t k = from; k <= to; k *= 2) {
    e.sweep.emplace_back(k, error(k));
    if (e.sweep.back().second <= target) break;
  }
  const auto& s = e.sweep;
  if (s.back().second > target) return e;
  if (s.size() == 1) {
    e.spp = s[0].first;
    return e;
  }
  const auto& [k0, e0] = s[s.size() - 2];
  const auto& [k1, e1] = s.back();
  const double t = (std::log(target) - std::log(e0)) / (std::log(e1) - std::log(e0));
  e.spp = std::exp(std::log(double(k0)) + t * (std::log(double(k1)) - std::log(double(k0))));
  return e;
}

void run_luminaire_bench(const LuminaireBenchArgs& a) {
  fs::path dir(a.out);
  fs::create_directories(dir);
  render::check_writable_output((dir / "results.csv").string());
  ProgressBar bar("bench luminaire");
  auto wants = [&](uint32_t n) { return std::find(a.parts.begin(), a.parts.end(), n) != a.parts.end(); };

  SourceOptions source;
  source.scene = a.scene;
  voxelizer::VoxelizeOptions vo;
  vo.resolution = a.resolution;
  vo.progress = [&](const std::string& stage, double f) { bar.update("voxelize " + a.scene + " " + stage, f); };
  const octree::Octree tree = voxelizer::voxelize(*make_scene_source(source), vo);

  // The luminaire: a file, or the headlight, above and in front of the
  // scene, aimed a little below its centre; a deterministic material
  // (the quadrature's lobes must not be sampled).
  auto emitter = [](const std::string& name) {
    if (name == "led") return render::make_led_luminaire(128, 5, 300.0f);
    if (name == "headlight") return render::make_headlight_luminaire(128, 5, 100.0f, 0.05f, 0.12f);
    return render::load_light_field(name);
  };
  std::vector<std::shared_ptr<const render::LightField>> fields;
  for (const auto& name : a.luminaires) fields.push_back(std::make_shared<const render::LightField>(emitter(name)));
  auto field = fields.front();
  const glm::vec3 centre = tree.origin + glm::vec3(0.5f * tree.size);
  render::RenderSettings base;
  base.width = base.height = a.size;
  base.camera = render::view_preset(tree, "mid");
  base.lights.clear();
  base.ambient = glm::vec3(0.0f);
  base.background = glm::vec3(0.0f);
  auto material = std::make_shared<render::Material>();
  material->name = a.glossy ? "bench-ggx" : "bench-lambert";
  material->kind = a.glossy ? render::BrdfKind::Ggx : render::BrdfKind::Lambert;
  material->roughness = 0.3f;
  material->f0 = glm::vec3(0.04f);
  material->diffuse = glm::vec3(0.8f);
  base.shading.material = material;
  // In the near field of the scene, as a headlight lights the road: its
  // beam converges to a hot spot on the floor in front of the spheres.
  base.luminaire.luminaires.push_back({field,
                                       {centre + tree.size * glm::vec3(0.0f, 0.1f, 0.35f),
                                        centre + tree.size * glm::vec3(0.0f, -0.25f, -0.08f), 0.31f * tree.size}});
  base.luminaire.visibility = render::LuminaireVisibility::None;
  base.luminaire.spp = a.spp;

  auto renderer = render::make_renderer(tree, {"native"});
  renderer->add_pass(std::make_unique<render::LuminairePass>());
  auto render_with = [&](const std::function<void(render::RenderSettings&)>& change) {
    render::RenderSettings s = base;
    change(s);
    return renderer->render(s);
  };
  auto quadrature = [&](const std::shared_ptr<const render::LightField>& f) {
    bar.update("quadrature (ground truth) of " + f->source, 0.0);
    return render_with([&](render::RenderSettings& s) {
      s.luminaire.luminaires[0].field = f;
      s.luminaire.quadrature = a.quadrature;
    });
  };
  const render::Frame truth = quadrature(field);
  render::write_colour((dir / "truth.exr").string(), truth);
  render::write_colour((dir / "truth.png").string(), truth);

  nlohmann::json results;
  results["machine"] = machine_description();
  results["scene"] = a.scene;
  results["resolution"] = a.resolution;
  results["size"] = a.size;
  results["luminaire"] = field->source;  // parts 2-6
  results["material"] = material->name;
  bench::TextFile csv(dir / "results.csv");
  csv << "part,case,spp,lab,relmse,ms\n";
  std::ostringstream md;
  md << "# svo bench luminaire\n\nScene " << a.scene << " at " << a.resolution << "^3, " << a.size << "x" << a.size
     << ", luminaire: " << field->source << " (" << field->image_count() << " images of " << field->width << "x"
     << field->height << "), material " << material->name << ". Ground truth: quadrature of the same G-buffer, "
     << a.quadrature << "^2 points per texel, "
     << "no visibility. Machine: " << results["machine"].get<std::string>() << ".\n\n";
  auto record = [&](const std::string& part, const std::string& name, uint32_t spp, const render::Frame& f,
                    const render::Frame& ref) {
    const double e = mean_lab_error(f, ref), r = relmse(f, ref), ms = pass_ms(f, "luminaire");
    csv << part << "," << name << "," << spp << "," << e << "," << r << "," << ms << "\n";
    results[part].push_back({{"case", name}, {"spp", spp}, {"lab", e}, {"relmse", r}, {"ms", ms}});
    csv.save();
    return e;
  };
  auto flush = [&] {
    files::write_file((dir / "table.md").string(), md.str());
    files::write_file((dir / "results.json").string(), results.dump(2) + "\n");
  };

  if (wants(1)) {
    for (size_t e_i = 0; e_i < fields.size(); ++e_i) {
      const auto& f1 = fields[e_i];
      const std::string tag = a.luminaires[e_i];
      const render::Frame truth1 = e_i == 0 ? truth : quadrature(f1);
      auto sample = [&](render::LuminaireSampler sampler, uint32_t spp) {
        return render_with([&](render::RenderSettings& s) {
          s.luminaire.luminaires[0].field = f1;
          s.luminaire.sampler = sampler;
          s.luminaire.spp = spp;
        });
      };
      const std::string part = "equal_spp_" + tag;
      bar.update("part 1: samplers at equal samples, " + tag, 0.0);
      md << "## 1. Restricted, uniform and global sampling (Figs. 11, 12): " << f1->source
         << "\n\n| sampler | spp | "
            "mean Lab error | relMSE | luminaire pass ms |\n|---|---|---|---|---|\n";
      std::vector<render::Frame> frames;
      std::vector<double> errors;
      for (auto sampler : {render::LuminaireSampler::Restricted, render::LuminaireSampler::Uniform,
                           render::LuminaireSampler::Global, render::LuminaireSampler::Box}) {
        frames.push_back(sample(sampler, a.spp));
        errors.push_back(record(part, render::luminaire_sampler_name(sampler), a.spp, frames.back(), truth1));
        md << "| " << render::luminaire_sampler_name(sampler) << " | " << a.spp << " | " << bench::fmt(errors.back(), 3)
           << " | " << sci(relmse(frames.back(), truth1)) << " | " << bench::fmt(pass_ms(frames.back(), "luminaire"), 0)
           << " |\n";
      }
      const double restricted_error = errors[0];
      md << "\nLab error ratio at " << a.spp << " spp: uniform / restricted " << bench::fmt(errors[1] / errors[0], 2)
         << " (paper: 2.4), global / restricted " << bench::fmt(errors[2] / errors[0], 2) << "; uniform / box "
         << bench::fmt(errors[1] / errors[3], 2) << ".\n\n";
      flush();
      for (auto [sampler, cap] : {std::pair{render::LuminaireSampler::Uniform, a.max_uniform_spp},
                                  std::pair{render::LuminaireSampler::Global, a.max_global_spp}}) {
        const std::string name = render::luminaire_sampler_name(sampler);
        bar.update("part 1: " + name + " at equal error, " + tag, 0.0);
        EqualError eq = equal_error(
            [&, sampler = sampler](uint32_t k) {  // a structured binding: captured by name (Clang 14)
              const render::Frame f = sample(sampler, k);
              return record("equal_error_" + tag, name, k, f, truth1);
            },
            restricted_error, a.spp, cap);
        md << "- " << name << " reaches the restricted sampler's error (" << bench::fmt(restricted_error, 3) << " at "
           << a.spp << " spp) at ";
        if (eq.spp > 0) {
          md << bench::fmt(eq.spp, 0) << " spp: " << bench::fmt(eq.spp / a.spp, 1) << "x the samples";
        } else {
          md << "more than " << cap << " spp (error " << bench::fmt(eq.sweep.back().second, 3) << " there): more than "
             << bench::fmt(double(cap) / a.spp, 0) << "x the samples";
        }
        md << " (sweep:";
        for (const auto& [k, e] : eq.sweep) md << " " << k << " spp " << bench::fmt(e, 3) << ";";
        md << ")\n";
        results["equal_error_spp_" + tag][name] = eq.spp;
        flush();
      }
      render::Frame s = bench::strip({{&truth1, &frames[0], &frames[3], &frames[1], &frames[2]}});
      render::write_colour((dir / ("samplers-" + tag + ".png")).string(), s);
      md << "\nImages: samplers-" << tag << ".png (quadrature, restricted, box, uniform, global at " << a.spp
         << " spp).\n\n";
      flush();
    }
  }

  if (wants(2)) {
    bar.update("part 2: K_max", 0.0);
    md << "## 2. K_max = 7 against no cap (Fig. 9), 200 spp\n\n| K_max | mean Lab error vs truth | relMSE | ms |\n"
          "|---|---|---|---|\n";
    render::Frame uncapped, capped;
    for (uint32_t kmax : {0u, 7u}) {
      render::Frame f = render_with([&](render::RenderSettings& s) {
        s.luminaire.spp = 200;
        s.luminaire.kmax = kmax;
      });
      const double e = record("kmax", kmax ? "7" : "none", 200, f, truth);
      md << "| " << (kmax ? "7" : "none") << " | " << bench::fmt(e, 3) << " | " << sci(relmse(f, truth)) << " | "
         << bench::fmt(pass_ms(f, "luminaire"), 0) << " |\n";
      (kmax ? capped : uncapped) = std::move(f);
    }
    md << "\nMean Lab error between the two: " << bench::fmt(mean_lab_error(capped, uncapped), 3)
       << " (paper: 0.63).\n\n";
    flush();
  }

  if (wants(3)) {
    bar.update("part 3: Halton against random", 0.0);
    md << "## 3. Halton against independent random numbers (Fig. 8)\n\n| spp | Halton Lab | random Lab "
          "|\n|---|---|---|\n";
    for (uint32_t spp : {16u, 64u, 256u, 1024u}) {
      double e[2];
      for (auto seq : {render::LuminaireSequence::Halton, render::LuminaireSequence::Random}) {
        render::Frame f = render_with([&](render::RenderSettings& s) {
          s.luminaire.spp = spp;
          s.luminaire.sequence = seq;
        });
        e[size_t(seq)] = record("sequence", render::luminaire_sequence_name(seq), spp, f, truth);
      }
      md << "| " << spp << " | " << bench::fmt(e[0], 3) << " | " << bench::fmt(e[1], 3) << " |\n";
      flush();
    }
    md << "\n";
  }

  if (wants(4)) {
    bar.update("part 4: secant, binary, Illinois and classical binary search", 0.0);
    constexpr std::array<render::LuminaireSearch, 4> searches{
        render::LuminaireSearch::Secant, render::LuminaireSearch::Binary, render::LuminaireSearch::Illinois,
        render::LuminaireSearch::Classic};
    md << "## 4. Modified secant against binary search at equal depth (Fig. 5), 200 spp\n\n"
          "binary: halving, then the chord's root in the interval left; classic: halving, then the interval's "
          "midpoint (the paper's classical binary search, which does not use the CDF's linearity).\n\n| depth |";
    for (auto search : searches) md << " " << render::luminaire_search_name(search) << " Lab |";
    for (auto search : searches) md << " " << render::luminaire_search_name(search) << " ms |";
    md << "\n|---|---|---|---|---|---|---|---|---|\n";
    for (uint32_t depth : {1u, 2u, 3u, 4u, 6u, 0u}) {
      std::array<double, searches.size()> e{}, ms{};
      for (size_t i = 0; i < searches.size(); ++i) {
        render::Frame f = render_with([&](render::RenderSettings& s) {
          s.luminaire.spp = 200;
          s.luminaire.search = searches[i];
          s.luminaire.search_depth = depth;
        });
        e[i] =
            record("search_depth_" + std::to_string(depth), render::luminaire_search_name(searches[i]), 200, f, truth);
        ms[i] = pass_ms(f, "luminaire");
      }
      md << "| " << (depth ? std::to_string(depth) : "exact") << " |";
      for (double v : e) md << " " << bench::fmt(v, 3) << " |";
      for (double v : ms) md << " " << bench::fmt(v, 0) << " |";
      md << "\n";
      flush();
    }
    md << "\n";
  }

  if (wants(5)) {
    bar.update("part 5: visibility", 0.0);
    auto shadowed = [&](render::LuminaireVisibility v, uint32_t spp, uint32_t seed) {
      return render_with([&](render::RenderSettings& s) {
        s.luminaire.visibility = v;
        s.luminaire.spp = spp;
        s.luminaire.seed = seed;
      });
    };
    const render::Frame reference = shadowed(render::LuminaireVisibility::Samples, a.visibility_reference_spp, 99);
    render::write_colour((dir / "visibility-reference.png").string(), reference);
    md << "## 5. Visibility: one cone per basis cell against one per sample (Fig. 7), 200 spp\n\nReference: a cone per "
          "sample at "
       << a.visibility_reference_spp << " spp.\n\n| visibility | mean Lab error | relMSE | ms |\n|---|---|---|---|\n";
    std::vector<render::Frame> frames;
    for (auto v : {render::LuminaireVisibility::Cells, render::LuminaireVisibility::Samples,
                   render::LuminaireVisibility::None, render::LuminaireVisibility::CellsOnU}) {
      frames.push_back(shadowed(v, 200, 1));
      const double e = record("visibility", render::luminaire_visibility_name(v), 200, frames.back(), reference);
      md << "| " << render::luminaire_visibility_name(v) << " | " << bench::fmt(e, 3) << " | "
         << sci(relmse(frames.back(), reference)) << " | " << bench::fmt(pass_ms(frames.back(), "luminaire"), 0)
         << " |\n";
    }
    render::write_colour((dir / "visibility.png").string(),
                         bench::strip({{&reference, &frames[0], &frames[1], &frames[2], &frames[3]}}));
    md << "\nImages: visibility.png (reference, cells, samples, none, cells-on-u). Paper (shadow maps against ray "
          "tracing): mean "
          "Lab error 1.2.\n\n";
    flush();
  }

  if (wants(6)) {
    md << "## 6. Frame time at 200 spp (Fig. 10), " << a.timing_size[0] << "x" << a.timing_size[1] << ", median of "
       << a.repeats
       << "\n\n| host | trace ms | luminaire pass ms (cells) | of which A_m and "
          "set-up (1 spp, no visibility) | sampling and shading (200 spp, no visibility) | visibility cones |\n"
          "|---|---|---|---|---|---|\n";
    for (const std::string& device : a.timing_devices) {
      bar.update("part 6: timing on " + device, 0.0);
      auto timed = render::make_renderer(tree, {device});
      timed->add_pass(std::make_unique<render::LuminairePass>());
      auto median = [&](uint32_t spp, render::LuminaireVisibility v, double* trace) {
        std::vector<double> lum, tr;
        for (uint32_t r = 0; r < a.repeats + 1; ++r) {
          render::RenderSettings s = base;
          s.width = a.timing_size[0];
          s.height = a.timing_size[1];
          s.camera = render::view_preset(tree, "mid", float(s.width) / float(s.height));
          s.luminaire.spp = spp;
          s.luminaire.visibility = v;
          render::Frame f = timed->render(s);
          if (r == 0) continue;  // the first frame allocates
          lum.push_back(pass_ms(f, "luminaire"));
          tr.push_back(pass_ms(f, "trace"));
        }
        std::sort(lum.begin(), lum.end());
        std::sort(tr.begin(), tr.end());
        if (trace) *trace = tr[tr.size() / 2];
        return lum[lum.size() / 2];
      };
      double trace = 0;
      const double full = median(200, render::LuminaireVisibility::Cells, &trace);
      const double setup = median(1, render::LuminaireVisibility::None, nullptr);
      const double unshadowed = median(200, render::LuminaireVisibility::None, nullptr);
      md << "| " << timed->device_name() << " | " << bench::fmt(trace, 0) << " | " << bench::fmt(full, 0) << " | "
         << bench::fmt(setup, 0) << " | " << bench::fmt(unshadowed - setup, 0) << " | "
         << bench::fmt(full - unshadowed, 0) << " |\n";
      results["timing"].push_back({{"device", timed->device_name()},
                                   {"trace_ms", trace},
                                   {"luminaire_ms", full},
                                   {"setup_ms", setup},
                                   {"unshadowed_ms", unshadowed}});
      flush();
    }
    md << "\n";
  }
  flush();
  bar.finish();
  std::cout << md.str();
}

}  // namespace

void add_bench_luminaire_command(CLI::App& bench, int& exit_code) {
  auto a = std::make_shared<LuminaireBenchArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "luminaire",
      "Lu et al. 2015's figures on the engine against quadrature of the same G-buffer: restricted, uniform and "
      "global sampling at equal samples and at equal error (Figs. 11, 12), K_max (Fig. 9), Halton against random "
      "(Fig. 8), secant against binary, classical binary search and the Illinois secant (Fig. 5), cell against "
      "per-sample visibility (Fig. 7) and frame times (Fig. 10); writes table.md, results.csv, results.json and "
      "images to --out");
  cmd->add_option("--scene", a->scene, "Built-in scene")->capture_default_str();
  cmd->add_option("--luminaires", a->luminaires,
                  "Emitters: led (an LED headlight, 3x3 dies), headlight (a smooth converging beam), or .lfl files; "
                  "part 1 runs for each, the others for the first")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--resolution", a->resolution, "Finest lattice cells per axis of the octree")
      ->capture_default_str()
      ->check(CLI::Range(16u, 1024u));
  cmd->add_option("--size", a->size, "Image width and height, pixels")
      ->capture_default_str()
      ->check(CLI::Range(16u, 2048u));
  cmd->add_option("--spp", a->spp, "Samples per pixel of the restricted sampler in part 1")
      ->capture_default_str()
      ->check(CLI::Range(1u, 65536u));
  cmd->add_option("--max-uniform-spp", a->max_uniform_spp, "Part 1: the largest uniform sweep")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1u << 20));
  cmd->add_option("--max-global-spp", a->max_global_spp, "Part 1: the largest global sweep")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1u << 20));
  cmd->add_flag("--glossy", a->glossy,
                "Shade with GGX (roughness 0.3, f0 0.04, diffuse 0.8) instead of Lambert (0.8): the BRDF, which no "
                "sampler here follows, then adds its own variance");
  cmd->add_option("--quadrature", a->quadrature, "Ground truth: quadrature points per texel per axis")
      ->capture_default_str()
      ->check(CLI::Range(1u, 16u));
  cmd->add_option("--visibility-reference-spp", a->visibility_reference_spp,
                  "Part 5: samples per pixel of the per-sample visibility reference")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1u << 20));
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
  cmd->add_option("--parts", a->parts,
                  "The experiments: 1 (samplers, Figs. 11-12), 2 (K_max, Fig. 9), 3 (sequences, Fig. 8), 4 (searches, "
                  "Fig. 5), 5 (visibility, Fig. 7), 6 (frame times, Fig. 10)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(1u, 6u));
  cmd->add_option("-o,--out", a->out, "Output directory (created)")->capture_default_str();
  cmd->callback([a, &exit_code] {
    if (a->timing_size.size() != 2 || a->timing_size[0] < 16 || a->timing_size[1] < 16) {
      throw std::invalid_argument("--timing-size W,H: two sizes of at least 16");
    }
    run_luminaire_bench(*a);
    exit_code = 0;
  });
}

}  // namespace svo::tools
