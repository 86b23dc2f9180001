// Small helpers of the bench commands (cmd_bench.cpp, cmd_bench_zoom.cpp,
// cmd_bench_figures.cpp, cmd_bench_heightmap.cpp): number formatting, frames
// as images, strips of frames side by side, gnuplot.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "svo/octree/files.h"
#include "svo/reference/compare.h"
#include "svo/reference/material.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"

namespace svo::tools::bench {

// A text output of a bench (CSV, Markdown, gnuplot script): streamed into
// memory, then written by save() through svo::files::write_file (atomic,
// every write checked). save() may be called as results come in: each call
// replaces the file with everything streamed so far.
class TextFile : public std::ostringstream {
 public:
  explicit TextFile(std::filesystem::path path) : path_(std::move(path)) {}
  void save() const { files::write_file(path_.string(), str()); }

 private:
  std::filesystem::path path_;
};

inline std::string fmt(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// The CPU's model name and thread count, for the tables.
inline std::string machine_description() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  }
  return model + ", " + std::to_string(std::thread::hardware_concurrency()) + " threads";
}

// relMSE of a frame against the truth, as svo compare measures it.
inline double relmse(const render::Frame& image, const render::Frame& truth) {
  return reference::compare_images(render::frame_image(image), render::frame_image(truth)).relmse;
}

inline std::string sci(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// Rows of frames side by side, `gap` pixels of dark grey between them,
// colours scaled by `exposure`, each pixel repeated `zoom` x `zoom` times,
// alpha 1 (the frames' backgrounds are black). Frames of a row may differ in
// size; each cell takes the largest.
inline render::Frame strip(const std::vector<std::vector<const render::Frame*>>& rows, uint32_t zoom = 1,
                           float exposure = 1.0f, uint32_t gap = 4) {
  zoom = std::max(zoom, 1u);
  uint32_t cell_w = 0, cell_h = 0, cols = 0;
  for (const auto& r : rows) {
    cols = std::max(cols, uint32_t(r.size()));
    for (const auto* f : r) cell_w = std::max(cell_w, f->width * zoom), cell_h = std::max(cell_h, f->height * zoom);
  }
  render::Frame s;
  s.width = cols * cell_w + (cols + 1) * gap;
  s.height = uint32_t(rows.size()) * cell_h + uint32_t(rows.size() + 1) * gap;
  s.colour.assign(size_t(s.width) * s.height, glm::vec4(0.25f, 0.25f, 0.25f, 1.0f));
  for (size_t r = 0; r < rows.size(); ++r) {
    for (size_t c = 0; c < rows[r].size(); ++c) {
      const render::Frame& f = *rows[r][c];
      uint32_t x0 = gap + uint32_t(c) * (cell_w + gap), y0 = gap + uint32_t(r) * (cell_h + gap);
      for (uint32_t y = 0; y < cell_h; ++y) {
        for (uint32_t x = 0; x < cell_w; ++x) {
          glm::vec4 v(0, 0, 0, 1);
          const uint32_t fx = x / zoom, fy = y / zoom;
          if (fx < f.width && fy < f.height)
            v = glm::vec4(glm::vec3(f.colour[size_t(fy) * f.width + fx]) * exposure, 1.0f);
          s.colour[size_t(y0 + y) * s.width + x0 + x] = v;
        }
      }
    }
  }
  return s;
}

// The engine's colour in the material bench (paper Fig. 9): the mean over
// the covered pixels of one prefiltered cone per pixel, the view 4 pixels
// high, at `degrees`.
inline glm::vec3 engine_material_colour(render::Renderer& gpu, float degrees,
                                        const reference::MaterialOptions& options) {
  render::Frame f = gpu.render(reference::material_view(degrees, 4, options));
  glm::dvec3 sum(0);
  double covered = 0;
  for (const auto& c : f.colour) sum += glm::dvec3(c.r, c.g, c.b), covered += c.a;
  return covered > 0 ? glm::vec3(sum / covered) : glm::vec3(0);
}

// Largest relative per-channel difference of x from t.
inline double relative_error(glm::vec3 x, glm::vec3 t) {
  glm::vec3 e = glm::abs(x - t) / glm::max(t, glm::vec3(1e-6f));
  return std::max(e.x, std::max(e.y, e.z));
}

// One angle of the material bench: a CSV row (degrees, then R, G, B of the
// ground truth, Eq. 17, MIP and the engine) and a Markdown row with the
// relative errors.
inline void write_material_row(std::ostream& csv, std::ostream& md, const reference::MaterialPoint& p,
                               glm::vec3 engine) {
  csv << p.degrees;
  for (glm::vec3 c : {p.truth, p.eq17, p.mip, engine}) csv << "," << c.x << "," << c.y << "," << c.z;
  csv << "\n";
  auto rgb = [](glm::vec3 c) { return fmt(c.x, 4) + " " + fmt(c.y, 4) + " " + fmt(c.z, 4); };
  md << "| " << fmt(p.degrees, 0) << " | " << rgb(p.truth) << " | " << rgb(p.eq17) << " | "
     << fmt(100 * relative_error(p.eq17, p.truth), 2) << "% | " << rgb(p.mip) << " | "
     << fmt(100 * relative_error(p.mip, p.truth), 2) << "% | " << rgb(engine) << " | "
     << fmt(100 * relative_error(engine, p.truth), 2) << "% |\n";
}

// Writes DIR/material.gp, the Fig. 9 plot of DIR/material.csv (degrees, then
// R, G, B of ground truth, Eq. 17, MIP and the engine) into DIR/material.png,
// with `title` (may be empty).
inline void write_material_plot(const std::filesystem::path& dir, const std::string& title) {
  TextFile gp(dir / "material.gp");
  gp << "set terminal pngcairo size 900,500 font 'sans,10'\nset output '" << (dir / "material.png").string()
     << "'\nset datafile separator ','\nset key top left\nset grid\nset xlabel 'view angle (degrees)'\n"
     << "set ylabel 'colour'\n";
  if (!title.empty()) gp << "set title '" << title << "'\n";
  gp << "f='" << (dir / "material.csv").string() << "'\nplot ";
  const char* names[] = {"R", "G", "B"};
  const char* colours[] = {"red", "dark-green", "blue"};
  for (int c = 0; c < 3; ++c) {
    gp << (c ? ", " : "") << "f every ::1 using 1:" << 2 + c << " with lines lw 2 lc '" << colours[c]
       << "' title 'ground truth " << names[c] << "', f every ::1 using 1:" << 5 + c << " with points pt 7 lc '"
       << colours[c] << "' title 'Eq. 17', f every ::1 using 1:" << 8 + c << " with lines dt 2 lc '" << colours[c]
       << "' title 'MIP', f every ::1 using 1:" << 11 + c << " with points pt 2 lc '" << colours[c]
       << "' title 'engine (one cone)'";
  }
  gp << "\n";
  gp.save();
}

// Runs gnuplot on `script`; says why on stderr when there is no plot.
inline void run_gnuplot(const std::filesystem::path& script) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    std::cerr << "svo bench: gnuplot is not installed; no plot (apt-get install gnuplot-nox)\n";
  } else if (std::system(("gnuplot '" + script.string() + "'").c_str()) != 0) {
    std::cerr << "svo bench: gnuplot failed on " << script.string() << "\n";
  }
}

}  // namespace svo::tools::bench
