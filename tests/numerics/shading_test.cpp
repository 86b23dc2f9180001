// Lighting and materials of the shading passes (DESIGN 10.2): the
// environment map's distribution (pdf integrates to 1, equals what the
// sampler reports, > 0 wherever radiance is, never NaN), the loaders' one-line
// errors, and each analytic BRDF's reciprocity and energy.
#include "svo/render/shading.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "numerics/chi_square.h"
#include "render/test_lighting.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"

namespace svo::math {
struct ShadingKernel : render::NativeShadingReader {
#include "common/environment.glsl"
#include "common/material.glsl"
};
}  // namespace svo::math

namespace svo::render {
namespace {

namespace fs = std::filesystem;
using svo::math::ShadingKernel;
using test::sky;

struct Lit {
  ShadingTables t;
  ShadingKernel k;
  explicit Lit(const Environment& env, float rotate = 0) {
    ShadingOptions o;
    o.environment = std::make_shared<const Environment>(env);
    o.env_rotate_deg = rotate;
    t = build_shading_tables(o, builtin_material(0.04f, 0.01f), false);
    k = ShadingKernel{{t.params, t.floats.data()}};
  }
};

glm::vec3 sphere_direction(double u, double v) {
  const double z = 1 - 2 * v, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * M_PI * u;
  return glm::vec3(float(r * std::cos(phi)), float(z), float(r * std::sin(phi)));
}

TEST(Environment, PdfIntegratesToOneAndMatchesTheSampler) {
  for (float rotate : {0.0f, 77.0f}) {
    Lit lit(sky(), rotate);
    // Integral over the sphere, uniform in z and phi (area 4 pi).
    const int n = 2400;  // fine enough to resolve the bright patch's edges
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) sum += lit.k.svo_env_pdf(lit.k.shade, sphere_direction((i + 0.5) / n, (j + 0.5) / n));
    }
    EXPECT_NEAR(sum * 4 * M_PI / (double(n) * n), 1.0, 0.01) << "rotation " << rotate;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u01(0, 1);
    for (int i = 0; i < 20000; ++i) {
      const glm::vec4 s = lit.k.svo_env_sample(lit.k.shade, glm::vec2(u01(rng), u01(rng)));
      ASSERT_TRUE(std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.z) && std::isfinite(s.w));
      ASSERT_GT(s.w, 0.0f);
      const glm::vec3 d(s);
      EXPECT_NEAR(glm::length(d), 1.0f, 1e-4f);
      // Only where there is light.
      ASSERT_GT(lit.k.svo_env_radiance(lit.k.shade, d).g, 0.0f) << "sampled a black texel";
      const float pdf = lit.k.svo_env_pdf(lit.k.shade, d);
      EXPECT_NEAR(pdf / s.w, 1.0f, 2e-3f) << "direction " << d.x << "," << d.y << "," << d.z;
    }
  }
}

TEST(Environment, EveryLitDirectionHasAPositivePdfAndTheCornersOfTheSquareAreNotNaN) {
  Lit lit(sky());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u01(0, 1);
  for (int i = 0; i < 100000; ++i) {
    const glm::vec3 d = sphere_direction(u01(rng), u01(rng));
    const glm::vec3 r = lit.k.svo_env_radiance(lit.k.shade, d);
    const float pdf = lit.k.svo_env_pdf(lit.k.shade, d);
    ASSERT_TRUE(std::isfinite(pdf));
    if (r.x + r.y + r.z > 0) {
      ASSERT_GT(pdf, 0.0f);
    }
  }
  for (glm::vec2 u : {glm::vec2(0, 0), glm::vec2(0.99999994f), glm::vec2(0, 0.99999994f), glm::vec2(1, 1)}) {
    const glm::vec4 s = lit.k.svo_env_sample(lit.k.shade, u);
    EXPECT_TRUE(std::isfinite(s.x) && std::isfinite(s.w));
  }
  // At the poles themselves.
  for (float y : {1.0f, -1.0f}) EXPECT_TRUE(std::isfinite(lit.k.svo_env_pdf(lit.k.shade, glm::vec3(0, y, 0))));
}

TEST(Environment, TheRotationTurnsTheMapAboutY) {
  Lit a(sky()), b(sky(), 90.0f);
  const glm::vec3 d = glm::normalize(glm::vec3(0.3f, 0.2f, -0.9f));
  const float t = glm::radians(90.0f);
  // Rotated by 90 degrees, the map shows in d what it showed in d turned back.
  const glm::vec3 back(d.x * std::cos(t) + d.z * std::sin(t), d.y, -d.x * std::sin(t) + d.z * std::cos(t));
  EXPECT_EQ(b.k.svo_env_radiance(b.k.shade, back), a.k.svo_env_radiance(a.k.shade, d));
}

TEST(Environment, BadMapsAreOneLineErrors) {
  auto message = [](const Environment& env) {
    try {
      validate_environment(env);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  Environment nan = sky(8, 4);
  nan.rgb[7] = std::nanf("");
  EXPECT_NE(message(nan).find("NaN at texel (2, 0)"), std::string::npos) << message(nan);
  Environment inf = sky(8, 4);
  inf.rgb[30] = INFINITY;
  EXPECT_NE(message(inf).find("Inf"), std::string::npos);
  Environment black = sky(8, 4);
  std::fill(black.rgb.begin(), black.rgb.end(), 0.0f);
  EXPECT_NE(message(black).find("black everywhere"), std::string::npos);
  Environment huge;
  huge.source = "huge";
  huge.width = 100000;
  huge.height = 2;
  EXPECT_NE(message(huge).find("100000x2 texels"), std::string::npos);
  for (const auto& env : {nan, inf, black, huge}) EXPECT_EQ(message(env).find('\n'), std::string::npos);
}

std::string load_error(const fs::path& path, std::string* warning = nullptr) {
  try {
    load_environment(path, warning);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

void write_map(const fs::path& path, float value_at_1, uint32_t w = 8, uint32_t h = 4) {
  Frame f;
  f.width = w;
  f.height = h;
  f.colour.assign(size_t(w) * h, glm::vec4(0.5f, 0.5f, 0.5f, 1));
  f.colour[1] = glm::vec4(value_at_1, 0.5f, 0.5f, 1);
  write_colour(path.string(), f);
}

TEST(Environment, FilesAreCheckedBeforeTheyAreRead) {
  const fs::path dir = fs::temp_directory_path() / ("svo-env-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  EXPECT_NE(load_error(dir / "none.exr").find("no such file"), std::string::npos);
  EXPECT_NE(load_error(dir).find("not a regular file"), std::string::npos);
  ASSERT_EQ(::mkfifo((dir / "fifo.exr").c_str(), 0600), 0);
  EXPECT_NE(load_error(dir / "fifo.exr").find("not a regular file"), std::string::npos);
  // A small negative texel is clamped with a warning; a large one is an error.
  write_map(dir / "small.exr", -1e-5f);
  std::string warning;
  EXPECT_EQ(load_error(dir / "small.exr", &warning), "");
  EXPECT_NE(warning.find("1 small negative texel values"), std::string::npos) << warning;
  EXPECT_EQ(load_environment(dir / "small.exr").rgb[3], 0.0f);
  write_map(dir / "negative.exr", -0.5f);
  EXPECT_NE(load_error(dir / "negative.exr").find("negative radiance"), std::string::npos);
  write_map(dir / "nan.exr", std::nanf(""));
  EXPECT_NE(load_error(dir / "nan.exr").find("NaN at texel (1, 0)"), std::string::npos) << load_error(dir / "nan.exr");
  std::ofstream(dir / "junk.exr") << "not an image";
  EXPECT_NE(load_error(dir / "junk.exr").find("environment: "), std::string::npos);
  fs::remove_all(dir);
}

TEST(Environment, TheBlenderMapsLoad) {
  const fs::path dir = "/usr/share/blender/datafiles/studiolights/world";
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " missing (Debian blender-data; scripts/setup.sh installs it)";
  int maps = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".exr") continue;
    const Environment env = load_environment(entry.path());
    EXPECT_GE(env.width, 2u);
    Lit lit(env);
    const glm::vec4 s = lit.k.svo_env_sample(lit.k.shade, glm::vec2(0.3f, 0.6f));
    EXPECT_GT(s.w, 0.0f) << entry.path();
    ++maps;
  }
  EXPECT_EQ(maps, 8);
}

std::string material_error(const std::string& json) {
  try {
    parse_material(json, ".", "m.json");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(MaterialJson, ValidMaterialsParseAndBadKeysAreNamed) {
  const Material g = parse_material(R"({"name": "gold", "brdf": "ggx", "roughness": 0.3, "f0": [1, 0.8, 0.3],
                                        "diffuse": [0.1, 0.1, 0.1]})",
                                    ".");
  EXPECT_EQ(g.kind, BrdfKind::Ggx);
  EXPECT_FLOAT_EQ(g.f0.g, 0.8f);
  const Material d = parse_material(R"({"brdf": "beckmann", "ior": 1.5})", ".");
  EXPECT_NEAR(d.f0.r, 0.04f, 1e-6f);
  EXPECT_EQ(parse_material(R"({"brdf": "lambert", "colour": [0.2, 0.3, 0.4]})", ".").diffuse.b, 0.4f);
  EXPECT_EQ(parse_material(R"({"brdf": "phong", "exponent": 400})", ".").exponent, 400.0f);
  // The JSON written back parses to the same material.
  const Material again = parse_material(material_json(g), ".");
  EXPECT_EQ(again.kind, g.kind);
  EXPECT_EQ(again.f0, g.f0);
  EXPECT_EQ(again.roughness, g.roughness);
  const std::pair<std::string, std::string> bad[] = {
      {R"({"brdf": "ggx", "roughnes": 0.3})", "key 'roughnes': unknown"},
      {R"({"roughness": 0.3})", "key 'brdf': missing"},
      {R"({"brdf": "glass"})", "key 'brdf': 'glass' is none of"},
      {R"({"brdf": "ggx", "roughness": -1})", "key 'roughness': -1"},
      {R"({"brdf": "ggx", "roughness": "rough"})", "key 'roughness': not a number"},
      {R"({"brdf": "ggx", "f0": [1, 2]})", "key 'f0': not [r, g, b]"},
      {R"({"brdf": "ggx", "f0": [1, 0, 2]})", "key 'f0': component 2"},
      {R"({"brdf": "ggx", "f0": 0.04, "ior": 1.5})", "key 'ior': given with 'f0'"},
      {R"({"brdf": "ggx", "ior": 0.5})", "key 'ior'"},
      {R"({"brdf": "ggx", "file": "x.binary"})", "key 'file': only brdf 'merl'"},
      {R"({"brdf": "merl"})", "key 'file': missing"},
      {R"({"brdf": "merl", "file": "/nonexistent.binary"})", "merl: "},
      {R"([1, 2])", "not a JSON object"},
      {R"({"brdf": )", "not JSON"},
      // Strings from the file stay on one line (a fuzz finding: a newline in the value).
      {R"({"brdf": "mer\nl"})", "key 'brdf': 'mer\\nl' is none of"},
      {R"({"brdf": "merl", "file": "x\ny.binary"})", "key 'file': 'x\\ny.binary' holds control characters"},
      {R"({"brdf": "ggx", "a\nb": 1})", "key 'a\\nb': unknown"},
      // A key cut inside a UTF-8 sequence in the message (a fuzz finding: it threw).
      {"{\"" + std::string(39, 'x') + "\xc3\xa9\": 1, \"brdf\": \"ggx\"}", "unknown"},
  };
  for (const auto& [json, expected] : bad) {
    const std::string e = material_error(json);
    EXPECT_NE(e.find(expected), std::string::npos) << json << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

// The analytic materials: reciprocity, and an albedo at most 1 (estimated
// with the material's own sampler, which this also checks against the
// pdf: f cos / pdf has the right mean only if the pdf is the sampler's).
std::vector<Material> analytic_materials() {
  std::vector<Material> out;
  for (BrdfKind k : {BrdfKind::Lambert, BrdfKind::Beckmann, BrdfKind::Ggx, BrdfKind::Phong}) {
    for (float r : {0.05f, 0.3f, 0.8f}) {
      Material m;
      m.kind = k;
      m.roughness = r;
      m.exponent = 2.0f / (r * r) - 2.0f;  // the Phong exponent of Beckmann roughness r
      m.diffuse = glm::vec3(k == BrdfKind::Lambert ? 1.0f : 0.0f);
      m.f0 = glm::vec3(1.0f);
      out.push_back(m);
    }
  }
  return out;
}

svo::math::SvoMaterial to_shader(const Material& m, glm::vec2 anisotropy = glm::vec2(1)) {
  svo::math::SvoShadeParams p{};
  p.material.x = uint32_t(m.kind);
  p.diffuse = glm::vec4(m.diffuse, m.roughness);
  p.specular = glm::vec4(m.f0, m.exponent);
  svo::math::SvoMaterial s = svo::math::svo_material_of(p);
  s.alpha2 *= anisotropy;
  return s;
}

glm::vec3 hemisphere(double u, double v) {
  const double z = u, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * M_PI * v;
  return glm::vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
}

TEST(AnalyticBrdfs, AreReciprocal) {
  ShadingKernel k{};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u01(0, 1);
  for (const Material& m : analytic_materials()) {
    for (glm::vec2 aniso : {glm::vec2(1), glm::vec2(0.3f, 2.0f)}) {
      const auto s = to_shader(m, aniso);
      for (int i = 0; i < 100; ++i) {
        const glm::vec3 v = hemisphere(u01(rng), u01(rng)), l = hemisphere(u01(rng), u01(rng));
        const glm::vec3 a = k.svo_material_brdf(s, glm::vec3(0.7f), v, l),
                        b = k.svo_material_brdf(s, glm::vec3(0.7f), l, v);
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(a[c], b[c], 1e-4f * std::max(1.0f, std::abs(a[c]))) << brdf_name(m.kind);
      }
    }
  }
}

TEST(AnalyticBrdfs, ReflectAtMostWhatArrives) {
  ShadingKernel k{};
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u01(0, 1);
  for (const Material& m : analytic_materials()) {
    const auto s = to_shader(m);
    for (float cos_v : {1.0f, 0.7f, 0.3f, 0.1f}) {
      const glm::vec3 v(std::sqrt(1 - cos_v * cos_v), 0, cos_v);
      const int n = 200000;
      double sum = 0;
      for (int i = 0; i < n; ++i) {
        const glm::vec4 d = k.svo_sample_material(s, glm::vec3(1), v, glm::vec3(u01(rng), u01(rng), u01(rng)));
        if (!(d.w > 0)) continue;
        const glm::vec3 f = k.svo_material_brdf(s, glm::vec3(1), v, glm::vec3(d));
        ASSERT_TRUE(std::isfinite(f.g) && std::isfinite(d.w));
        sum += double(f.g) * d.z / d.w;
      }
      const double albedo = sum / n;
      EXPECT_LE(albedo, 1.01) << brdf_name(m.kind) << " roughness " << m.roughness << " cos " << cos_v;
      if (m.kind == BrdfKind::Lambert) {
        EXPECT_NEAR(albedo, 1.0, 0.01);
      }
    }
  }
}

// Each sampler against its pdf (chi-square), and the pdf's integral: the
// microfacet and Phong lobes alone and mixed with the diffuse lobe, at
// several view elevations, isotropic and anisotropic.
TEST(AnalyticBrdfs, SamplersFollowTheirPdfs) {
  ShadingKernel k{};
  struct Case {
    BrdfKind kind;
    float roughness;
    glm::vec2 anisotropy;
    float diffuse;
  };
  const std::vector<Case> cases = {
      {BrdfKind::Beckmann, 0.3f, {1, 1}, 0}, {BrdfKind::Beckmann, 0.6f, {0.25f, 2.0f}, 0},
      {BrdfKind::Ggx, 0.2f, {1, 1}, 0},      {BrdfKind::Ggx, 0.5f, {3.0f, 0.5f}, 0},
      {BrdfKind::Phong, 0.3f, {1, 1}, 0},    {BrdfKind::Ggx, 0.3f, {1, 1}, 0.5f},
      {BrdfKind::Lambert, 1.0f, {1, 1}, 1},
  };
  const float views[] = {10, 50, 80};
  const double alpha = svo::test::sidak_significance(0.01, int(cases.size() * std::size(views)));
  for (const Case& c : cases) {
    Material m;
    m.kind = c.kind;
    m.roughness = c.roughness;
    m.exponent = 2.0f / (c.roughness * c.roughness) - 2.0f;
    m.diffuse = glm::vec3(c.diffuse);
    m.f0 = glm::vec3(0.5f);
    const auto s = to_shader(m, c.anisotropy);
    for (float deg : views) {
      const float t = glm::radians(deg);
      const glm::vec3 v(std::sin(t) * 0.6f, std::sin(t) * 0.8f, std::cos(t));
      std::mt19937 lobe_rng(17);
      std::uniform_real_distribution<float> u01(0, 1);
      svo::test::ChiSquareOptions options;
      options.samples = 400000;
      const auto r = svo::test::chi_square_test(
          [&](glm::dvec2 u) -> std::optional<glm::dvec3> {
            const glm::vec4 d = k.svo_sample_material(s, glm::vec3(1), v, glm::vec3(u.x, u.y, u01(lobe_rng)));
            if (!(d.w > 0)) return std::nullopt;
            return glm::dvec3(glm::vec3(d));
          },
          [&](glm::dvec3 d) { return double(k.svo_material_pdf(s, glm::vec3(1), v, glm::vec3(d))); }, options);
      const std::string what = std::string(brdf_name(c.kind)) + " roughness " + std::to_string(c.roughness) + " view " +
                               std::to_string(deg) + ": " + r.summary();
      EXPECT_TRUE(r.passed(alpha)) << what;
      // Directions reflected below the plane are no sample: the pdf's
      // integral is the share of samples returned.
      EXPECT_NEAR(r.pdf_integral, 1.0 - double(r.no_sample) / double(options.samples), 0.01) << what;
    }
  }
}

TEST(Environment, TheSamplerFollowsItsPdf) {
  std::vector<Environment> maps = {sky()};
  const fs::path forest = "/usr/share/blender/datafiles/studiolights/world/forest.exr";
  if (fs::exists(forest)) maps.push_back(load_environment(forest));
  for (const Environment& env : maps) {
    Lit lit(env, 40.0f);
    svo::test::ChiSquareOptions options;
    options.samples = 1000000;
    options.integration_points = 64;  // a piecewise-constant pdf, texels 13x smaller than a bin
    const auto r = svo::test::chi_square_test(
        [&](glm::dvec2 u) -> std::optional<glm::dvec3> {
          const glm::vec4 d = lit.k.svo_env_sample(lit.k.shade, glm::vec2(u));
          if (!(d.w > 0)) return std::nullopt;
          return glm::dvec3(glm::vec3(d));
        },
        [&](glm::dvec3 d) { return double(lit.k.svo_env_pdf(lit.k.shade, glm::vec3(d))); }, options);
    EXPECT_TRUE(r.passed(0.005)) << env.source << ": " << r.summary();
    EXPECT_NEAR(r.pdf_integral, 1.0, 0.01) << env.source;
    EXPECT_EQ(r.no_sample, 0u) << env.source;
  }
}

}  // namespace
}  // namespace svo::render
