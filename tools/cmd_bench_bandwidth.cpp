// svo bench bandwidth: Bagher et al. 2013's figures (issue 17) measured on
// the engine (DESIGN 10.3), each in one run on one machine:
//   1. the headline (Figs. 11, 14): frame time of adaptive shading against
//      forward shading at equal relMSE against ground truth, per scene x
//      material x environment: forward at a sweep of samples per pixel,
//      adaptive at a sweep of tau (Eq. 9's bound and our measured variance),
//      the forward time at the adaptive frame's error interpolated log-log;
//      with the bandwidth buffer's share of the adaptive frame;
//   2. validation (Fig. 12): the predicted variance against the variance of
//      the forward estimator measured by brute force, and the predicted
//      image bandwidth against a windowed FFT (32x32) of the reference;
//   3. n_b = 16, 64, 256, 1024 (Fig. 13): PSNR and time;
//   4. what the voxels' slope band-limit saves on the far view (ours);
//   5. adaptive sampling for pre-convolved shading (section 2.5, Eq. 10,
//      Fig. 16): adaptive frames against the map pre-convolved at the
//      BRDF's sharpest lobe against adaptive frames of the map as it is
//      (multiple importance sampling, and the paper's BRDF sampling alone),
//      at equal relMSE;
//   6. adaptive multisample anti-aliasing (section 4.3, Fig. 10 right,
//      Fig. 19): frame time against samples per pixel;
//   7. area lights (section 4.3, Fig. 17): a white and a checkered square
//      light, adaptive against forward at equal relMSE.
// Ground truth is `svo reference` (the source geometry, many samples), or
// with --truth forward a converged forward frame of the same G-buffer
// (shading error alone, without the octree's).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <thread>

#include "bench_fft_agreement.h"
#include "bench_tie.h"
#include "bench_util.h"
#include "commands.h"
#include "progress.h"
#include "source_options.h"
#include "svo/octree/files.h"
#include "svo/reference/compare.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/bandwidth.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/mesh.h"
#include "view_options.h"

namespace svo::tools {

namespace {

namespace fs = std::filesystem;
using bench::machine_description;
using bench::relmse;
using bench::sci;

struct BandwidthBenchArgs {
  // Built-in scenes by name, or mesh files.
  std::vector<std::string> scenes{"bumpy-sphere"};
  // Material JSON files, or the built-in names diffuse, glossy, mirror.
  std::vector<std::string> materials{"diffuse", "glossy", "mirror"};
  std::vector<std::string> envs{"/usr/share/blender/datafiles/studiolights/world/courtyard.exr"};
  std::string view = "mid";
  uint32_t resolution = 256;
  uint32_t size = 512;
  std::vector<uint32_t> spp{8, 16, 32, 64, 128};
  std::vector<float> taus{};  // empty: per variance mode, a default sweep
  std::string truth = "reference";
  uint32_t truth_spp = 128;
  uint32_t variance_frames = 32;
  uint32_t repeats = 2;
  uint32_t directions = render::AdaptiveOptions{}.directions;  // n_b of parts 1, 2 and 4
  std::vector<uint32_t> parts{1, 2, 3, 4};                     // parts 5 to 7 on request
  uint32_t msaa_spp = 16;                                      // part 6: the forward frames' samples per pixel
  float msaa_tau = 0.01f;                                      // and the adaptive frames' tau (measured variance)
  std::string out = "bench-bandwidth";
};

std::shared_ptr<const render::Material> bench_material(const std::string& name) {
  auto m = std::make_shared<render::Material>();
  m->name = name;
  if (name == "diffuse") {
    m->kind = render::BrdfKind::Lambert;
    m->diffuse = glm::vec3(0.8f);
  } else if (name == "glossy") {
    m->kind = render::BrdfKind::Ggx;
    m->roughness = 0.25f;
    m->diffuse = glm::vec3(0.5f);
    m->f0 = glm::vec3(0.04f);
  } else if (name == "mirror") {
    m->kind = render::BrdfKind::Ggx;
    m->roughness = 0.03f;
    m->diffuse = glm::vec3(0.05f);
    m->f0 = glm::vec3(0.9f, 0.8f, 0.6f);
  } else {
    render::Material loaded = render::load_material(name);
    if (loaded.name.empty() || loaded.name == "default") loaded.name = fs::path(name).stem().string();
    return std::make_shared<const render::Material>(std::move(loaded));
  }
  return m;
}

bool is_builtin_scene(const std::string& s) { return s.find('.') == std::string::npos; }

struct Scene {
  std::string name;
  octree::Octree tree;
  std::unique_ptr<voxelizer::AnalyticScene> analytic;  // kept alive for the reference geometry
  std::unique_ptr<reference::Geometry> geometry;
};

Scene load_scene(const std::string& what, uint32_t resolution, ProgressBar& bar) {
  Scene s;
  s.name = is_builtin_scene(what) ? what : fs::path(what).stem().string();
  voxelizer::VoxelizeOptions vo;
  vo.resolution = resolution;
  vo.progress = [&](const std::string& stage, double f) { bar.update("voxelize " + s.name + " " + stage, f); };
  SourceOptions source;
  if (is_builtin_scene(what)) {
    source.scene = what;
    s.tree = voxelizer::voxelize(*make_scene_source(source, false), vo);
    s.analytic = make_scene_source(source);
    s.analytic->set_sigma_rho2(s.tree.sigma_rho2);
    s.geometry = reference::scene_geometry(*s.analytic);
  } else {
    source.input = what;
    voxelizer::TriangleMesh mesh = read_source_mesh(source);
    s.tree = voxelizer::voxelize(*voxelizer::mesh_source(mesh), vo);
    mesh.sigma_rho2 = s.tree.sigma_rho2;
    s.geometry = reference::mesh_geometry(std::move(mesh));
  }
  return s;
}

// PSNR and relMSE of a frame against the truth, from one comparison.
reference::ImageErrors errors(const render::Frame& image, const render::Frame& truth) {
  return reference::compare_images(render::frame_image(image), render::frame_image(truth));
}

struct Point {
  std::string method;  // "forward", "bound", "measured"
  double knob = 0;     // spp or tau
  double ms = 0, relmse = 0, bandwidth_ms = 0;
  uint64_t shaded = 0, samples = 0, covered = 0;
};

// The median frame time of `repeats` frames (after one to warm the tables).
template <class F>
render::Frame timed(F render_frame, uint32_t repeats, double& ms) {
  render::Frame f = render_frame();
  std::vector<double> t;
  for (uint32_t r = 0; r < std::max(repeats, 1u); ++r) {
    f = render_frame();
    t.push_back(render::frame_ms(f));
  }
  std::sort(t.begin(), t.end());
  ms = t[t.size() / 2];
  return f;
}

// A scalar image in false colour (svo compare --diff's colour map, black
// to pale yellow) between lo and hi, on a log scale when `log`.
render::Frame false_colour(const std::vector<float>& v, uint32_t w, uint32_t h, double lo, double hi, bool log) {
  render::Frame f;
  f.width = w;
  f.height = h;
  f.colour.resize(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    double t = log ? (std::log(std::max(double(v[i]), lo)) - std::log(lo)) / (std::log(hi) - std::log(lo))
                   : (double(v[i]) - lo) / (hi - lo);
    if (!(v[i] >= 0)) t = 0;  // no surface
    f.colour[i] = glm::vec4(reference::false_colour(t), 1.0f);
  }
  return f;
}

void save_png(const fs::path& path, const render::Frame& f) { render::write_colour(path.string(), f); }

// A frame of `ms` against a baseline curve at equal error, as two table
// cells (the baseline's time at that error; the speed-up) and the speed-up
// it claims (0: none). Errors within the noise of a baseline frame's
// (bench_tie.h) tie and claim nothing; below the curve's smallest error
// beyond the noise, the curve's slowest time over ours is a lower bound
// (">=").
struct ClaimCells {
  std::string at, speedup;
  double factor = 0;
};

ClaimCells claim_cells(double ms, double error, const std::vector<bench::CostErrorPoint>& curve) {
  const bench::EqualErrorClaim claim = bench::claim_at_equal_error(ms, error, curve);
  using Kind = bench::EqualErrorClaim::Kind;
  ClaimCells c;
  switch (claim.kind) {
    case Kind::Speedup:
      c = {bench::fmt(claim.factor * ms, 0), bench::fmt(claim.factor, 2) + "x", claim.factor};
      break;
    case Kind::AtLeast:
      c = {"below the sweep's best", ">= " + bench::fmt(claim.factor, 2) + "x", claim.factor};
      break;
    case Kind::Tie:
      c = {"ties " + claim.against + " (" + sci(claim.against_error) + ")",
           "tie (" + bench::fmt(claim.factor * ms, 0) + " ms there)", 0};
      break;
    case Kind::Worse:
      c = {"outside the sweep", "-", 0};
      break;
  }
  return c;
}

void run_bandwidth_bench(const BandwidthBenchArgs& a) {
  fs::path dir(a.out);
  fs::create_directories(dir);
  render::check_writable_output((dir / "results.csv").string());
  ProgressBar bar("bench bandwidth");
  auto wants = [&](uint32_t n) { return std::find(a.parts.begin(), a.parts.end(), n) != a.parts.end(); };
  bench::TextFile md(dir / "table.md"), csv(dir / "results.csv");
  nlohmann::json json;
  json["machine"] = machine_description();
  json["size"] = a.size;
  json["resolution"] = a.resolution;
  json["truth"] = a.truth;
  json["truth_spp"] = a.truth_spp;
  md << "# svo bench bandwidth (Bagher et al. 2013)\n\nMachine: " << machine_description() << ". Frames " << a.size
     << "x" << a.size << ", octrees " << a.resolution << "^3, view " << a.view << ", native host; ground truth: "
     << (a.truth == "reference" ? "svo reference (" + std::to_string(a.truth_spp) + " spp)"
                                : "forward shading at " + std::to_string(a.truth_spp) + " spp")
     << ". Times are medians of " << a.repeats << " frames after a warm-up frame. n_b = " << a.directions << ".\n\n";
  csv << "part,scene,material,env,method,knob,ms,relmse,bandwidth_ms,shaded,samples,covered\n";

  for (size_t si = 0; si < a.scenes.size(); ++si) {
    Scene scene = load_scene(a.scenes[si], a.resolution, bar);
    auto forward = render::make_renderer(scene.tree, {"native"});
    forward->add_pass(render::make_pass("forward"));
    auto adaptive_renderer = render::make_renderer(scene.tree, {"native"});
    auto pass = std::make_unique<render::AdaptivePass>();
    render::AdaptivePass* adaptive = pass.get();
    adaptive_renderer->add_pass(std::move(pass));
    // One timed adaptive frame and its point against the truth.
    auto adaptive_point = [&](const std::string& method, double knob, const render::RenderSettings& t,
                              const render::Frame& truth, render::Frame& f) {
      Point p{method, knob};
      f = timed([&] { return adaptive_renderer->render(t); }, a.repeats, p.ms);
      p.relmse = relmse(f, truth);
      const auto& st = adaptive->stats();
      p.bandwidth_ms = st.bandwidth_ms;
      p.shaded = st.shaded;
      p.samples = st.samples;
      p.covered = st.covered;
      return p;
    };
    render::RenderSettings base;
    base.width = base.height = a.size;
    base.camera = render::view_preset(scene.tree, a.view);
    base.lights.clear();
    base.ambient = glm::vec3(0);
    const bool map_parts = wants(1) || wants(2) || wants(3) || wants(4) || wants(5) || wants(6);
    for (const std::string& env_path : a.envs) {
      if (!map_parts) break;  // part 7 alone: no map
      auto env = std::make_shared<const render::Environment>(render::load_environment(env_path));
      const std::string env_name = fs::path(env_path).stem().string();
      // Part 5's map, pre-convolved once per map (its time stated).
      std::shared_ptr<const render::PreconvolvedEnvironment> preconvolved;
      double preconvolve_ms = 0;
      if (wants(5)) {
        bar.update(env_name + ": pre-convolving the map", 0);
        const auto t0 = std::chrono::steady_clock::now();
        preconvolved = std::make_shared<const render::PreconvolvedEnvironment>(render::preconvolve_environment(*env));
        preconvolve_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      }
      for (const std::string& material_name : a.materials) {
        const auto material = bench_material(material_name);
        const std::string label = scene.name + " / " + material->name + " / " + env_name;
        render::RenderSettings s = base;
        s.shading.environment = env;
        s.shading.material = material;
        s.adaptive.directions = a.directions;
        // Ground truth.
        bar.update(label + ": ground truth", 0);
        render::Frame truth;
        if (a.truth == "reference") {
          reference::ReferenceSettings rs;
          rs.render = s;
          rs.spp = a.truth_spp;
          rs.progress = [&, rows = uint64_t(rs.render.height)](double f) {
            bar.update(label + ": svo reference", uint64_t(f * double(rows) + 0.5), rows, "rows");
          };
          truth = reference::render_reference(*scene.geometry, rs);
        } else {
          render::RenderSettings t = s;
          t.shading.spp = a.truth_spp;
          t.shading.seed = 99;
          truth = forward->render(t);
        }
        save_png(dir / (scene.name + "-" + material->name + "-" + env_name + "-truth.png"), truth);
        const bool first = &env_path == &a.envs.front() && &material_name == &a.materials.front();

        // Part 1: the headline.
        std::vector<Point> fwd, ad;
        if (wants(1)) {
          for (size_t k = 0; k < a.spp.size(); ++k) {
            bar.update(label + ": forward " + std::to_string(a.spp[k]) + " spp", double(k) / a.spp.size());
            render::RenderSettings t = s;
            t.shading.spp = a.spp[k];
            Point p{"forward", double(a.spp[k])};
            const render::Frame f = timed([&] { return forward->render(t); }, a.repeats, p.ms);
            p.relmse = relmse(f, truth);
            fwd.push_back(p);
          }
          for (const bool measured : {false, true}) {
            std::vector<float> taus = a.taus;
            if (taus.empty()) {
              taus = measured ? std::vector<float>{0.003f, 0.01f, 0.03f} : std::vector<float>{10.0f, 30.0f, 100.0f};
            }
            for (size_t k = 0; k < taus.size(); ++k) {
              bar.update(label + ": adaptive tau " + sci(taus[k]), double(k) / taus.size());
              render::RenderSettings t = s;
              t.adaptive.tau = taus[k];
              t.adaptive.measured_variance = measured;
              render::Frame f;
              ad.push_back(adaptive_point(measured ? "measured" : "bound", taus[k], t, truth, f));
              if (first && measured && k == 1) {
                save_png(dir / (scene.name + "-adaptive.png"), f);
              }
            }
          }
          for (const Point& p : fwd)
            csv << "1," << scene.name << "," << material->name << "," << env_name << "," << p.method << "," << p.knob
                << "," << p.ms << "," << p.relmse << ",,,,\n";
          for (const Point& p : ad)
            csv << "1," << scene.name << "," << material->name << "," << env_name << "," << p.method << "," << p.knob
                << "," << p.ms << "," << p.relmse << "," << p.bandwidth_ms << "," << p.shaded << "," << p.samples << ","
                << p.covered << "\n";
          // The best speed-up at equal error per variance mode.
          nlohmann::json row{{"scene", scene.name}, {"material", material->name}, {"env", env_name}};
          md << "### " << label << "\n\n| method | spp or tau | ms | relMSE | forward ms at that relMSE | speed-up | "
             << "bandwidth share | shaded texels / covered pixels | samples / covered pixel "
                "|\n|---|---|---|---|---|---|"
                "---|---|---|\n";
          for (const Point& p : fwd)
            md << "| forward | " << p.knob << " | " << bench::fmt(p.ms, 0) << " | " << sci(p.relmse) << " | | | | 1 | "
               << p.knob << " |\n";
          double best_bound = 0, best_measured = 0;
          std::vector<bench::CostErrorPoint> curve;
          for (const Point& p : fwd) curve.push_back({"forward " + bench::fmt(p.knob, 0) + " spp", p.ms, p.relmse});
          for (const Point& p : ad) {
            const ClaimCells claim = claim_cells(p.ms, p.relmse, curve);
            double& best = p.method == "bound" ? best_bound : best_measured;
            best = std::max(best, claim.factor);
            md << "| adaptive (" << p.method << ") | " << sci(p.knob) << " | " << bench::fmt(p.ms, 0) << " | "
               << sci(p.relmse) << " | " << claim.at << " | " << claim.speedup << " | "
               << bench::fmt(100 * p.bandwidth_ms / p.ms, 1) << "% | "
               << bench::fmt(double(p.shaded) / double(std::max<uint64_t>(p.covered, 1)), 3) << " | "
               << bench::fmt(double(p.samples) / double(std::max<uint64_t>(p.covered, 1)), 1) << " |\n";
          }
          md << "\nBest speed-up at equal relMSE: " << bench::fmt(best_bound, 2) << "x (Eq. 9's bound), "
             << bench::fmt(best_measured, 2) << "x (measured variance); a frame below the forward sweep's smallest "
             << "error counts as the slowest forward frame's time over its own (a lower bound); a relMSE within "
             << bench::fmt(100 * bench::kErrorTieTolerance, 0) << "% of a forward frame's is a tie and claims no "
             << "speed-up; 0: no frame beyond the noise within the sweep.\n\n";
          row["best_speedup_bound"] = best_bound;
          row["best_speedup_measured"] = best_measured;
          row["forward"] = nlohmann::json::array();
          for (const Point& p : fwd) row["forward"].push_back({{"spp", p.knob}, {"ms", p.ms}, {"relmse", p.relmse}});
          row["adaptive"] = nlohmann::json::array();
          for (const Point& p : ad)
            row["adaptive"].push_back({{"variance", p.method},
                                       {"tau", p.knob},
                                       {"ms", p.ms},
                                       {"relmse", p.relmse},
                                       {"bandwidth_ms", p.bandwidth_ms},
                                       {"shaded", p.shaded},
                                       {"samples", p.samples},
                                       {"covered", p.covered}});
          json["headline"].push_back(row);
          md.save();
          csv.save();
        }
        // Part 5: adaptive sampling for pre-convolved shading (section 2.5,
        // Eq. 10, Fig. 16): adaptive frames against the pre-convolved map
        // (a measured BRDF sampled from itself, each sample reading the map
        // at its sharpest lobe; analytic lobes looked up once) against
        // adaptive frames of the map as it is, sampled with multiple
        // importance sampling (ours) and from the BRDF alone (the paper's
        // baseline), all with the measured variance, at equal relMSE.
        if (wants(5)) {
          const bool measured_brdf = material->kind == render::BrdfKind::Merl;
          const std::vector<float> taus = a.taus.empty() ? std::vector<float>{0.03f, 0.01f, 0.003f} : a.taus;
          const std::vector<std::string> methods{"mis", "brdf", "pre-convolved"};
          std::vector<std::vector<Point>> points(methods.size());
          for (size_t m = 0; m < methods.size(); ++m) {
            const bool pre = methods[m] == "pre-convolved";
            // Analytic lobes against the pre-convolved map take one lookup
            // whatever tau is: one frame.
            const size_t count = pre && !measured_brdf ? 1 : taus.size();
            for (size_t k = 0; k < count; ++k) {
              bar.update(label + ": " + methods[m] + " tau " + sci(taus[k]), double(k) / double(count));
              render::RenderSettings t = s;
              t.adaptive.tau = taus[k];
              t.adaptive.measured_variance = true;
              t.shading.brdf_sampling = methods[m] == "brdf";
              if (pre) t.shading.preconvolved = preconvolved;
              render::Frame f;
              points[m].push_back(adaptive_point(methods[m], taus[k], t, truth, f));
              if (k == count / 2)
                save_png(dir / (scene.name + "-" + material->name + "-" + env_name + "-fig16-" + methods[m] + ".png"),
                         f);
            }
          }
          std::vector<std::vector<bench::CostErrorPoint>> curves(2);
          for (size_t m = 0; m < 2; ++m)
            for (const Point& p : points[m]) curves[m].push_back({methods[m] + " tau " + sci(p.knob), p.ms, p.relmse});
          md << "### Pre-convolved shading (Eq. 10, Fig. 16): " << label << "\n\nThe map pre-convolved once in "
             << bench::fmt(preconvolve_ms, 0) << " ms (not in the frame times). "
             << (measured_brdf ? "The measured BRDF is sampled from itself against the map pre-convolved at its "
                                 "sharpest lobe."
                               : "Analytic lobes: one lookup per lobe, no samples, one frame.")
             << "\n\n| method | tau | ms | relMSE | samples / covered px | mis ms at that relMSE | vs mis | "
                "brdf ms at that relMSE | vs brdf |\n|---|---|---|---|---|---|---|---|---|\n";
          double best[2] = {0, 0};
          nlohmann::json row{{"scene", scene.name},
                             {"material", material->name},
                             {"env", env_name},
                             {"preconvolve_ms", preconvolve_ms},
                             {"measured_brdf", measured_brdf}};
          for (size_t m = 0; m < methods.size(); ++m) {
            for (const Point& p : points[m]) {
              md << "| " << p.method << " | " << sci(p.knob) << " | " << bench::fmt(p.ms, 0) << " | " << sci(p.relmse)
                 << " | " << bench::fmt(double(p.samples) / double(std::max<uint64_t>(p.covered, 1)), 1);
              nlohmann::json point{{"method", p.method}, {"tau", p.knob},        {"ms", p.ms},
                                   {"relmse", p.relmse}, {"samples", p.samples}, {"covered", p.covered}};
              for (size_t b = 0; b < 2; ++b) {
                if (m < 2) {
                  md << " | | ";
                  continue;
                }
                const ClaimCells claim = claim_cells(p.ms, p.relmse, curves[b]);
                best[b] = std::max(best[b], claim.factor);
                md << " | " << claim.at << " | " << claim.speedup;
                point[std::string("speedup_vs_") + methods[b]] = claim.factor;
              }
              md << " |\n";
              row["points"].push_back(point);
              csv << "5," << scene.name << "," << material->name << "," << env_name << "," << p.method << "," << p.knob
                  << "," << p.ms << "," << p.relmse << "," << p.bandwidth_ms << "," << p.shaded << "," << p.samples
                  << "," << p.covered << "\n";
            }
          }
          md << "\nBest speed-up of the pre-convolved frames at equal relMSE: " << bench::fmt(best[0], 2)
             << "x against mis, " << bench::fmt(best[1], 2) << "x against brdf (0: none beyond the noise within the "
             << "sweep).\n\n";
          row["best_speedup_vs_mis"] = best[0];
          row["best_speedup_vs_brdf"] = best[1];
          json["preconvolved"].push_back(row);
          md.save();
          csv.save();
        }

        // Parts 2-4 and 6: the first material and map of the first scene.
        if (!first || si != 0) continue;

        // Part 6: adaptive multisample anti-aliasing (section 4.3, Fig. 10
        // right, Fig. 19): frame time against samples per pixel (1, 4, 16),
        // forward shading of every sample against adaptive shading, and the
        // exponent e of each (time ~ samples^e, least squares in log-log).
        if (wants(6)) {
          md << "## Adaptive multisample anti-aliasing (Fig. 10 right, Fig. 19): " << label << "\n\nForward at "
             << a.msaa_spp << " spp per sample against adaptive (measured variance, tau " << sci(a.msaa_tau)
             << "); shading ms is the frame's less the trace pass.\n\n| samples per pixel | "
             << "forward ms | forward shading ms | forward relMSE | adaptive ms | adaptive shading ms | adaptive "
                "relMSE | shaded texels / samples |\n|---|---|---|---|---|---|---|---|\n";
          std::vector<double> lx, lf, lfs, la, las;
          auto shading_ms = [](const render::Frame& f) {
            double ms = 0;
            for (const render::PassTime& p : f.passes) ms += p.name == "trace" ? 0.0 : p.ms;
            return ms;
          };
          for (uint32_t m : {1u, 2u, 4u}) {
            bar.update(label + ": msaa " + std::to_string(m), 0);
            render::RenderSettings t = s;
            t.msaa = m;
            t.shading.spp = a.msaa_spp;
            t.adaptive.tau = a.msaa_tau;
            t.adaptive.measured_variance = true;
            double fms = 0, ams = 0;
            const render::Frame ff = timed([&] { return forward->render(t); }, a.repeats, fms);
            const render::Frame af = timed([&] { return adaptive_renderer->render(t); }, a.repeats, ams);
            const auto& st = adaptive->stats();
            const double samples = double(m) * m * a.size * a.size;
            lx.push_back(std::log(double(m) * m));
            lf.push_back(std::log(fms));
            lfs.push_back(std::log(shading_ms(ff)));
            la.push_back(std::log(ams));
            las.push_back(std::log(shading_ms(af)));
            const double fe = relmse(ff, truth), ae = relmse(af, truth);
            md << "| " << m * m << " | " << bench::fmt(fms, 0) << " | " << bench::fmt(shading_ms(ff), 0) << " | "
               << sci(fe) << " | " << bench::fmt(ams, 0) << " | " << bench::fmt(shading_ms(af), 0) << " | " << sci(ae)
               << " | " << bench::fmt(double(st.shaded) / samples, 3) << " |\n";
            json["msaa"].push_back({{"samples_per_pixel", m * m},
                                    {"forward_ms", fms},
                                    {"forward_shading_ms", shading_ms(ff)},
                                    {"forward_relmse", fe},
                                    {"adaptive_ms", ams},
                                    {"adaptive_shading_ms", shading_ms(af)},
                                    {"adaptive_relmse", ae},
                                    {"shaded", st.shaded},
                                    {"samples", st.samples}});
            if (m == 4) {
              // Fig. 19: where the samples were shaded (pale: at the finest
              // level; black: upsampled or no surface).
              render::FrameImages& images = adaptive_renderer->images();
              const auto mask = images.texels<glm::vec4>(images.read(render::AdaptivePass::mask_image()));
              const size_t n = size_t(a.size) * m * a.size * m;
              std::vector<float> shaded(n);
              for (size_t i = 0; i < n; ++i) shaded[i] = mask[i].x < 0 ? -1 : 1.0f - mask[i].x / 7.0f;
              save_png(dir / "fig19-shaded-samples.png", false_colour(shaded, a.size * m, a.size * m, 0, 1, false));
              save_png(dir / "fig19-adaptive-msaa.png", af);
            }
          }
          // The least-squares slope of y against x.
          auto slope = [](const std::vector<double>& x, const std::vector<double>& y) {
            const double mx = std::accumulate(x.begin(), x.end(), 0.0) / double(x.size());
            const double my = std::accumulate(y.begin(), y.end(), 0.0) / double(y.size());
            double sxy = 0, sxx = 0;
            for (size_t i = 0; i < x.size(); ++i) {
              sxy += (x[i] - mx) * (y[i] - my);
              sxx += (x[i] - mx) * (x[i] - mx);
            }
            return sxx > 0 ? sxy / sxx : 0.0;
          };
          md << "\nExponent of time against samples per pixel (paper: 0.7 for adaptive): forward "
             << bench::fmt(slope(lx, lf), 2) << " (shading " << bench::fmt(slope(lx, lfs), 2) << "), adaptive "
             << bench::fmt(slope(lx, la), 2) << " (shading " << bench::fmt(slope(lx, las), 2)
             << "). Images: fig19-shaded-samples.png (16 samples per pixel: pale where shaded at the finest "
             << "level), fig19-adaptive-msaa.png.\n\n";
          json["msaa_exponent"] = {{"forward", slope(lx, lf)},
                                   {"forward_shading", slope(lx, lfs)},
                                   {"adaptive", slope(lx, la)},
                                   {"adaptive_shading", slope(lx, las)}};
          md.save();
        }

        // Part 2: validation (Fig. 12) and the images of Fig. 1b-d.
        if (wants(2)) {
          bar.update(label + ": validation", 0);
          render::RenderSettings t = s;
          t.adaptive.tau = 30.0f;
          const render::Frame result = adaptive_renderer->render(t);
          render::FrameImages& images = adaptive_renderer->images();
          const auto bw = images.texels<glm::vec4>(images.read(render::AdaptivePass::bandwidth_image()));
          const auto mask = images.texels<glm::vec4>(images.read(render::AdaptivePass::mask_image()));
          const auto g = images.texels<glm::vec4>(images.read(render::gbuffer_image()));
          const size_t n = size_t(a.size) * a.size;
          std::vector<float> level(n), spp(n), shaded(n), predicted(n), bp(n);
          std::vector<float> coverage(n);
          for (size_t i = 0; i < n; ++i) {
            coverage[i] = g[render::kGBufferVec4s * i + 1].w;
            const bool covered = coverage[i] > 0;
            level[i] = covered ? bw[i].x : -1;
            spp[i] = covered ? bw[i].y : -1;
            shaded[i] = mask[i].x;
            bp[i] = covered ? float(0.5 * std::exp2(-double(bw[i].x))) : -1;
          }
          save_png(dir / "fig1b-level.png", false_colour(level, a.size, a.size, 0, 7, false));
          save_png(dir / "fig1c-samples.png", false_colour(spp, a.size, a.size, 1, 256, true));
          {
            std::vector<float> m(n);
            for (size_t i = 0; i < n; ++i) m[i] = shaded[i] < 0 ? -1 : 1.0f - shaded[i] / 7.0f;
            save_png(dir / "fig1d-shaded.png", false_colour(m, a.size, a.size, 0, 1, false));
          }
          // The forward estimator's variance per pixel at 1 spp, by brute
          // force over independent frames, against Eq. 9's prediction for one
          // sample (bandwidth z times (L + 0.01)^2; a forward sample draws two
          // directions, the bound's uniform sampling one: both per sample).
          std::vector<double> sum(n, 0), sum2(n, 0);
          render::RenderSettings one = s;
          one.shading.spp = 1;
          for (uint32_t k = 0; k < a.variance_frames; ++k) {
            bar.update(label + ": brute-force variance", double(k) / a.variance_frames);
            one.shading.seed = 1000 + k;
            const render::Frame f = forward->render(one);
            for (size_t i = 0; i < n; ++i) {
              const double y = 0.2126 * f.colour[i].r + 0.7152 * f.colour[i].g + 0.0722 * f.colour[i].b;
              sum[i] += y;
              sum2[i] += y * y;
            }
          }
          std::vector<float> measured(n, -1), pred(n, -1);
          std::vector<double> ratio;
          uint32_t conservative = 0, counted = 0;
          for (size_t i = 0; i < n; ++i) {
            if (!(coverage[i] >= 0.999f)) continue;
            const double mean = sum[i] / a.variance_frames;
            const double var = std::max(sum2[i] / a.variance_frames - mean * mean, 0.0) * a.variance_frames /
                               std::max(a.variance_frames - 1.0, 1.0);
            const double p = double(bw[i].z) * (mean + 0.01) * (mean + 0.01);
            measured[i] = float(var);
            pred[i] = float(p);
            ++counted;
            conservative += p >= var ? 1 : 0;
            if (var > 0) ratio.push_back(p / var);
          }
          std::sort(ratio.begin(), ratio.end());
          const double median_over = ratio.empty() ? 0 : ratio[ratio.size() / 2];
          // Each on its own log scale (the bound is hundreds of times the
          // truth): four decades below its largest value.
          double vmax = 1e-12, pmax = 1e-12;
          for (float v : measured) vmax = std::max(vmax, double(v));
          for (float v : pred) pmax = std::max(pmax, double(v));
          save_png(dir / "fig12a-predicted-variance.png", false_colour(pred, a.size, a.size, pmax * 1e-4, pmax, true));
          save_png(dir / "fig12b-measured-variance.png",
                   false_colour(measured, a.size, a.size, vmax * 1e-4, vmax, true));
          // Bandwidth: the prediction against a windowed FFT of an image's
          // luminance (bench_fft_agreement.h); the prediction per pixel and
          // averaged over the FFT's window (it comes from n_b random
          // directions, so it is grainy pixel to pixel).
          const std::vector<double> bp_window = bench::window_mean(bp, coverage, a.size, 32);
          auto fft_agreement = [&](const render::Frame& image) {
            return bench::fft_agreement(image, bp, bp_window, coverage, a.size);
          };
          const bench::FftAgreement of_truth = fft_agreement(truth);
          const double rho = of_truth.rho, rho_interior = of_truth.rho_interior;
          const std::vector<float>& fft_shown = of_truth.shown;
          // The same against a noise-free image: the forward pass with the
          // map pre-convolved (one lookup per lobe, no samples), so that no
          // Monte Carlo noise sits in the FFT's bins above epsilon. Noise-free
          // for analytic materials only: a measured BRDF is still sampled.
          if (!preconvolved)
            preconvolved =
                std::make_shared<const render::PreconvolvedEnvironment>(render::preconvolve_environment(*env));
          render::RenderSettings smooth_settings = s;
          smooth_settings.shading.preconvolved = preconvolved;
          const render::Frame smooth = forward->render(smooth_settings);
          const bench::FftAgreement of_smooth = fft_agreement(smooth);
          save_png(dir / "fig12g-preconvolved.png", smooth);
          save_png(dir / "fig12h-fft-bandwidth-preconvolved.png",
                   false_colour(of_smooth.shown, a.size, a.size, 1e-3, 0.5, true));
          save_png(dir / "fig12c-predicted-bandwidth.png", false_colour(bp, a.size, a.size, 1e-3, 0.5, true));
          save_png(dir / "fig12d-fft-bandwidth.png", false_colour(fft_shown, a.size, a.size, 1e-3, 0.5, true));
          save_png(dir / "fig12e-result.png", result);
          std::vector<float> err(n, -1);
          for (size_t i = 0; i < n; ++i) {
            const glm::vec3 d = glm::vec3(result.colour[i]) - glm::vec3(truth.colour[i]);
            const double r = glm::dot(d, d) / 3.0;
            const double b = (0.2126 * truth.colour[i].r + 0.7152 * truth.colour[i].g + 0.0722 * truth.colour[i].b);
            err[i] = float(r / ((b + 0.01) * (b + 0.01)));
          }
          save_png(dir / "fig12f-relative-error.png", false_colour(err, a.size, a.size, 1e-5, 1, true));
          md << "## Validation (Fig. 12): " << label << "\n\nEq. 9's predicted variance of one sample against the "
             << "forward estimator's at 1 spp measured over " << a.variance_frames << " frames, on " << counted
             << " fully covered pixels: conservative on " << bench::fmt(100.0 * conservative / counted, 1)
             << "%, median over-estimate " << sci(median_over) << "x. Predicted image bandwidth b_p against a "
             << "windowed FFT (32x32, Hann) of the ground truth: Spearman rank correlation " << bench::fmt(rho, 3)
             << " (" << bench::fmt(rho_interior, 3) << " over the " << of_truth.interior
             << " pixels whose 32x32 window is all surface); against the same FFT of the noise-free pre-convolved "
             << "forward frame (fig12g): " << bench::fmt(of_smooth.rho, 3) << " ("
             << bench::fmt(of_smooth.rho_interior, 3)
             << "). With the prediction averaged over the FFT's 32x32 window: " << bench::fmt(of_truth.rho_window, 3)
             << " against the truth, " << bench::fmt(of_smooth.rho_window, 3)
             << " against the pre-convolved frame. Images: fig12a-h, fig1b-d.\n\n";
          json["validation"] = {{"label", label},
                                {"conservative_share", double(conservative) / counted},
                                {"median_overestimate", median_over},
                                {"rank_correlation", rho},
                                {"rank_correlation_interior", rho_interior},
                                {"rank_correlation_preconvolved", of_smooth.rho},
                                {"rank_correlation_preconvolved_interior", of_smooth.rho_interior},
                                {"rank_correlation_window", of_truth.rho_window},
                                {"rank_correlation_preconvolved_window", of_smooth.rho_window},
                                {"pixels", counted}};
          md.save();
        }

        // Part 3: n_b (Fig. 13).
        if (wants(3)) {
          md << "## n_b (Fig. 13): " << label << ", tau 30 (bound)\n\n| n_b | ms | bandwidth ms | PSNR | relMSE |\n"
             << "|---|---|---|---|---|\n";
          for (uint32_t nb : {16u, 64u, 256u, 1024u}) {
            bar.update(label + ": n_b " + std::to_string(nb), 0);
            render::RenderSettings t = s;
            t.adaptive.tau = 30.0f;
            t.adaptive.directions = nb;
            double ms = 0;
            const render::Frame f = timed([&] { return adaptive_renderer->render(t); }, a.repeats, ms);
            const double bms = adaptive->stats().bandwidth_ms;
            const reference::ImageErrors e = errors(f, truth);
            md << "| " << nb << " | " << bench::fmt(ms, 0) << " | " << bench::fmt(bms, 0) << " | "
               << bench::fmt(e.psnr, 2) << " | " << sci(e.relmse) << " |\n";
            json["n_b"].push_back({{"n_b", nb}, {"ms", ms}, {"bandwidth_ms", bms}, {"psnr", e.psnr}});
          }
          md << "\n";
          md.save();
        }

        // Part 4: the slope band-limit on the far view.
        if (wants(4)) {
          md << "## The voxels' slope band-limit (ours): " << scene.name << " / " << material->name << " / " << env_name
             << ", view far, tau 30 (bound)\n\n| slope limit | ms | shaded texels | samples | relMSE |\n"
             << "|---|---|---|---|---|\n";
          render::RenderSettings t = s;
          t.camera = render::view_preset(scene.tree, "far");
          t.adaptive.tau = 30.0f;
          reference::ReferenceSettings rs;
          rs.render = t;
          rs.spp = a.truth_spp;
          render::Frame far_truth;
          if (a.truth == "reference") {
            rs.progress = [&, rows = uint64_t(rs.render.height)](double f) {
              bar.update(label + ": far view reference", uint64_t(f * double(rows) + 0.5), rows, "rows");
            };
            far_truth = reference::render_reference(*scene.geometry, rs);
          } else {
            render::RenderSettings u = t;
            u.shading.spp = a.truth_spp;
            far_truth = forward->render(u);
          }
          for (bool limit : {false, true}) {
            t.adaptive.slope_limit = limit;
            double ms = 0;
            const render::Frame f = timed([&] { return adaptive_renderer->render(t); }, a.repeats, ms);
            const auto& st = adaptive->stats();
            const double err = relmse(f, far_truth);
            md << "| " << (limit ? "on" : "off") << " | " << bench::fmt(ms, 0) << " | " << st.shaded << " | "
               << st.samples << " | " << sci(err) << " |\n";
            json["slope_limit"].push_back(
                {{"on", limit}, {"ms", ms}, {"shaded", st.shaded}, {"samples", st.samples}, {"relmse", err}});
          }
          md << "\n";
          md.save();
        }
      }
    }

    // Part 7: area lights (section 4.3, Fig. 17): the first scene under
    // a white square light and a checkered one above it (no map), shadows
    // on, the first material: adaptive (measured variance) against forward
    // shading at equal relMSE against ground truth.
    if (wants(7) && si == 0) {
      const auto material = bench_material(a.materials.front());
      const glm::vec3 centre = scene.tree.origin + glm::vec3(0.5f * scene.tree.size);
      const uint32_t n = 8;
      std::vector<float> checker(size_t(n) * n * 3);
      for (uint32_t i = 0; i < n * n; ++i)
        for (uint32_t c = 0; c < 3; ++c) checker[3 * i + c] = (i % n + i / n) % 2 == 0 ? 20.0f : 0.0f;
      const std::vector<std::pair<std::string, std::vector<float>>> lights{{"white", {10.0f, 10.0f, 10.0f}},
                                                                           {"checker", checker}};
      for (const auto& [light_name, rgb] : lights) {
        const uint32_t w = light_name == "white" ? 1 : n;
        const std::string label = scene.name + " / " + material->name + " / " + light_name + " area light";
        render::RenderSettings s = base;
        s.shading.material = material;
        s.shading.area_light = std::make_shared<const render::AreaLight>(
            render::AreaLight::placed(centre + glm::vec3(0.0f, 1.2f * scene.tree.size, 0.0f), centre,
                                      0.5f * scene.tree.size, w, w, rgb, light_name));
        s.shadows = true;
        s.adaptive.directions = a.directions;
        s.adaptive.measured_variance = true;
        bar.update(label + ": ground truth", 0);
        reference::ReferenceSettings rs;
        rs.render = s;
        rs.spp = a.truth_spp;
        rs.progress = [&, rows = uint64_t(rs.render.height)](double f) {
          bar.update(label + ": svo reference", uint64_t(f * double(rows) + 0.5), rows, "rows");
        };
        const render::Frame truth = reference::render_reference(*scene.geometry, rs);
        const std::string stem = scene.name + "-fig17-" + light_name;
        save_png(dir / (stem + "-truth.png"), truth);
        std::vector<bench::CostErrorPoint> curve;
        md << "## Area light (Fig. 17): " << label
           << "\n\nThe light: half a domain size across, 1.2 above the domain's centre, facing down, radiance 10 "
              "(white) or 8x8 checkers of 20 and 0 (mean 10); shadows on; no map.\n\n| method | "
           << "spp or tau | ms | relMSE | forward ms at that relMSE | speed-up | shaded texels / covered pixels | "
              "samples / covered pixel |\n|---|---|---|---|---|---|---|---|\n";
        nlohmann::json row{{"scene", scene.name}, {"material", material->name}, {"light", light_name}};
        for (uint32_t spp : a.spp) {
          bar.update(label + ": forward " + std::to_string(spp) + " spp", 0);
          render::RenderSettings t = s;
          t.shading.spp = spp;
          Point p{"forward", double(spp)};
          const render::Frame f = timed([&] { return forward->render(t); }, a.repeats, p.ms);
          p.relmse = relmse(f, truth);
          curve.push_back({"forward " + std::to_string(spp) + " spp", p.ms, p.relmse});
          md << "| forward | " << spp << " | " << bench::fmt(p.ms, 0) << " | " << sci(p.relmse) << " | | | 1 | " << spp
             << " |\n";
          csv << "7," << scene.name << "," << material->name << "," << light_name << ",forward," << spp << "," << p.ms
              << "," << p.relmse << ",,,,\n";
          row["forward"].push_back({{"spp", spp}, {"ms", p.ms}, {"relmse", p.relmse}});
        }
        double best = 0;
        const std::vector<float> taus = a.taus.empty() ? std::vector<float>{0.003f, 0.01f, 0.03f} : a.taus;
        for (size_t k = 0; k < taus.size(); ++k) {
          bar.update(label + ": adaptive tau " + sci(taus[k]), 0);
          render::RenderSettings t = s;
          t.adaptive.tau = taus[k];
          render::Frame f;
          const Point p = adaptive_point("adaptive", taus[k], t, truth, f);
          const ClaimCells claim = claim_cells(p.ms, p.relmse, curve);
          best = std::max(best, claim.factor);
          md << "| adaptive | " << sci(p.knob) << " | " << bench::fmt(p.ms, 0) << " | " << sci(p.relmse) << " | "
             << claim.at << " | " << claim.speedup << " | "
             << bench::fmt(double(p.shaded) / double(std::max<uint64_t>(p.covered, 1)), 3) << " | "
             << bench::fmt(double(p.samples) / double(std::max<uint64_t>(p.covered, 1)), 1) << " |\n";
          csv << "7," << scene.name << "," << material->name << "," << light_name << ",adaptive," << p.knob << ","
              << p.ms << "," << p.relmse << "," << p.bandwidth_ms << "," << p.shaded << "," << p.samples << ","
              << p.covered << "\n";
          row["adaptive"].push_back({{"tau", p.knob},
                                     {"ms", p.ms},
                                     {"relmse", p.relmse},
                                     {"shaded", p.shaded},
                                     {"samples", p.samples},
                                     {"covered", p.covered}});
          if (k == taus.size() / 2) save_png(dir / (stem + "-adaptive.png"), f);
        }
        md << "\nBest speed-up at equal relMSE: " << bench::fmt(best, 2) << "x. Images: " << stem << "-truth.png, "
           << stem << "-adaptive.png.\n\n";
        row["best_speedup"] = best;
        json["area_light"].push_back(row);
        md.save();
        csv.save();
      }
    }
  }
  md.save();
  csv.save();
  files::write_file((dir / "results.json").string(), json.dump(1) + "\n");
  bar.finish();
  std::cout << "bench bandwidth: " << (dir / "table.md").string() << ", results.csv, results.json, images\n";
}

}  // namespace

void add_bench_bandwidth_command(CLI::App& bench, int& exit_code) {
  auto a = std::make_shared<BandwidthBenchArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "bandwidth",
      "Bagher et al. 2013's figures on the engine: adaptive against forward shading at equal relMSE against ground "
      "truth (Figs. 11, 14) with the bandwidth buffer's share, validation of the predicted variance and bandwidth "
      "(Fig. 12, images of Fig. 1b-d), n_b (Fig. 13), the voxels' slope band-limit and pre-convolved shading "
      "(Eq. 10, Fig. 16), multisample anti-aliasing (Fig. 10 right, Fig. 19) and area lights (Fig. 17); writes "
      "table.md, "
      "results.csv, results.json and images to --out");
  cmd->add_option("--scenes", a->scenes, "Built-in scenes or mesh files (OFF, OBJ, PLY, ...)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--materials", a->materials, "diffuse, glossy (GGX 0.25), mirror (GGX 0.03), or material JSON files")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--envs", a->envs, "Environment maps (EXR or HDR)")->delimiter(',')->capture_default_str();
  cmd->add_option("--view", a->view, "far, mid, close")->capture_default_str();
  cmd->add_option("--resolution", a->resolution, "Finest lattice cells per axis of the octrees")
      ->capture_default_str()
      ->check(CLI::Range(16u, 2048u));
  cmd->add_option("--size", a->size, "Image width and height, pixels")
      ->capture_default_str()
      ->check(CLI::Range(16u, 4096u));
  cmd->add_option("--spp", a->spp, "Part 1: the forward sweep, samples per pixel")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(1u, 65536u));
  cmd->add_option("--taus", a->taus,
                  "Parts 1 and 5: the adaptive sweep's tau (default: 10, 30, 100 with Eq. 9's bound; 0.003, 0.01, "
                  "0.03 with the measured variance, part 5's)")
      ->delimiter(',')
      ->check(CLI::Range(1e-9f, 1e9f));
  cmd->add_option("--truth", a->truth,
                  "reference (svo reference on the source) or forward (converged forward shading: the shading's "
                  "error alone)")
      ->capture_default_str()
      ->check(CLI::IsMember({"reference", "forward"}));
  cmd->add_option("--truth-spp", a->truth_spp, "Samples per pixel of the ground truth")
      ->capture_default_str()
      ->check(CLI::Range(1u, 65536u));
  cmd->add_option("--variance-frames", a->variance_frames, "Part 2: frames of the brute-force variance")
      ->capture_default_str()
      ->check(CLI::Range(2u, 4096u));
  cmd->add_option("--repeats", a->repeats, "Frames per timing after a warm-up; the median is reported")
      ->capture_default_str()
      ->check(CLI::Range(1u, 100u));
  cmd->add_option("--directions", a->directions, "n_b, the directions per pixel of the adaptive frames (not part 3's)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 4096u));
  cmd->add_option(
         "--parts", a->parts,
         "1 (headline, Figs. 11, 14), 2 (validation, Fig. 12), 3 (n_b, Fig. 13), 4 (slope band-limit), 5 "
         "(pre-convolved shading, Eq. 10, Fig. 16: give MERL materials), 6 (multisample anti-aliasing, Fig. "
         "10 right, Fig. 19), 7 (area lights, Fig. 17: the first scene and material, no map); parts 2-4 and 6 run "
         "on the first scene's first material and map")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(1u, 7u));
  cmd->add_option("--msaa-spp", a->msaa_spp, "Part 6: samples per pixel of the forward frames")
      ->capture_default_str()
      ->check(CLI::Range(1u, 4096u));
  cmd->add_option("--msaa-tau", a->msaa_tau, "Part 6: tau of the adaptive frames (measured variance)")
      ->capture_default_str()
      ->check(CLI::Range(1e-9f, 1e9f));
  cmd->add_option("-o,--out", a->out, "Output directory (created)")->capture_default_str();
  cmd->callback([a, &exit_code] {
    run_bandwidth_bench(*a);
    exit_code = 0;
  });
}

}  // namespace svo::tools
