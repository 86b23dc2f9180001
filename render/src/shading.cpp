#include "svo/render/shading.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "svo/render/image_io.h"
#include "svo/render/merl.h"

namespace svo::math {

struct MaterialKernel : render::NativeShadingReader {
#include "common/material.glsl"
#include "common/sequence.glsl"
};

}  // namespace svo::math

namespace svo::render {

namespace fs = std::filesystem;

namespace {

constexpr uint32_t kMaxEnvWidth = 16384, kMaxEnvHeight = 8192;

std::runtime_error env_error(const std::string& source, const std::string& why) {
  return std::runtime_error("environment: " + source + ": " + why);
}

float luminance(const float* c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

// A texel's weight in a sampling distribution: its luminance; colours whose
// luminance rounds to 0 keep a pdf > 0.
float sampling_weight(const float* c) {
  const float lum = luminance(c);
  return lum > 0 ? lum : std::max({c[0], c[1], c[2]}) * 1e-3f;
}

}  // namespace

void validate_environment(const Environment& env) {
  if (env.width < 2 || env.height < 1 || env.width > kMaxEnvWidth || env.height > kMaxEnvHeight) {
    throw env_error(env.source, std::to_string(env.width) + "x" + std::to_string(env.height) +
                                    " texels, outside 2x1 to " + std::to_string(kMaxEnvWidth) + "x" +
                                    std::to_string(kMaxEnvHeight));
  }
  if (env.rgb.size() != size_t(env.width) * env.height * 3) throw env_error(env.source, "texel count mismatch");
  bool lit = false;
  for (size_t i = 0; i < env.rgb.size(); ++i) {
    const float v = env.rgb[i];
    if (!std::isfinite(v)) {
      const size_t t = i / 3;
      throw env_error(env.source, std::string(std::isnan(v) ? "NaN" : "Inf") + " at texel (" +
                                      std::to_string(t % env.width) + ", " + std::to_string(t / env.width) + ")");
    }
    if (v < 0) throw env_error(env.source, "negative radiance " + std::to_string(v));
    lit = lit || v > 0;
  }
  if (!lit) throw env_error(env.source, "the map is black everywhere (nothing to light or sample)");
}

Environment load_environment(const fs::path& path, std::string* warning) {
  const std::string name = path.string();
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw env_error(name, "no such file");
  if (!fs::is_regular_file(st)) throw env_error(name, "not a regular file");
  Image image;
  try {
    image = read_image(name);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("environment: ") + e.what());
  }
  const size_t nc = image.channels.size();
  if (nc < 3) throw env_error(name, std::to_string(nc) + " channels, RGB needed");
  Environment env;
  env.source = name;
  env.width = uint32_t(image.width);
  env.height = uint32_t(image.height);
  if (env.width < 2 || env.width > kMaxEnvWidth || env.height > kMaxEnvHeight) validate_environment(env);
  env.rgb.resize(size_t(env.width) * env.height * 3);
  float peak = 0;
  for (size_t t = 0; t < size_t(env.width) * env.height; ++t) {
    for (size_t c = 0; c < 3; ++c) {
      const float v = image.pixels[t * nc + c];
      env.rgb[t * 3 + c] = v;
      if (std::isfinite(v)) peak = std::max(peak, v);
    }
  }
  // DWAB-compressed maps hold small negative values; larger ones are an error.
  size_t clamped = 0;
  float lowest = 0;
  for (float& v : env.rgb) {
    if (v < 0 && v >= -1e-3f * std::max(peak, 1.0f)) {
      lowest = std::min(lowest, v);
      v = 0, ++clamped;
    }
  }
  validate_environment(env);
  if (clamped > 0 && warning) {
    std::ostringstream s;
    s << "environment: " << name << ": " << clamped << " small negative texel values (down to " << lowest
      << ") clamped to 0";
    *warning = s.str();
  }
  return env;
}

Environment constant_environment(glm::vec3 radiance, uint32_t width, uint32_t height) {
  Environment env;
  env.width = width;
  env.height = height;
  env.source = "constant";
  env.rgb.resize(size_t(width) * height * 3);
  for (size_t t = 0; t < size_t(width) * height; ++t) {
    for (int c = 0; c < 3; ++c) env.rgb[t * 3 + c] = radiance[c];
  }
  validate_environment(env);
  return env;
}

uint32_t append_distribution(const std::vector<float>& f, uint32_t nu, uint32_t nv, std::vector<float>& tables) {
  const uint32_t offset = uint32_t(tables.size());
  tables.insert(tables.end(), f.begin(), f.end());
  std::vector<double> row_sum(nv, 0.0);
  for (uint32_t v = 0; v < nv; ++v) {
    double sum = 0;
    std::vector<double> cdf(nu + 1, 0.0);
    for (uint32_t u = 0; u < nu; ++u) cdf[u + 1] = sum += double(f[size_t(v) * nu + u]);
    row_sum[v] = sum;
    for (uint32_t u = 0; u <= nu; ++u) {
      // An empty row: uniform, never NaN (and never drawn: no marginal mass).
      tables.push_back(sum > 0 ? float(cdf[u] / sum) : float(u) / float(nu));
    }
    tables.back() = 1.0f;
  }
  double total = 0;
  std::vector<double> marginal(nv + 1, 0.0);
  for (uint32_t v = 0; v < nv; ++v) marginal[v + 1] = total += row_sum[v];
  for (uint32_t v = 0; v <= nv; ++v) tables.push_back(total > 0 ? float(marginal[v] / total) : float(v) / float(nv));
  tables.back() = 1.0f;
  tables.push_back(float(total / (double(nu) * nv)));  // the mean of f
  tables.push_back(0.0f);                              // padding (svo_dist2d_floats)
  return offset;
}

// The pre-convolved maps (environment.glsl, svo_env_preconvolved): the
// level count, the first level's sharpness, then width, height and offset
// (uint bits) of each level and of the irradiance, then their texels.
uint32_t append_preconvolved(const PreconvolvedEnvironment& pre, std::vector<float>& tables) {
  const auto offset = uint32_t(tables.size());
  const size_t n = pre.levels.size();
  tables.push_back(float(n));
  tables.push_back(pre.levels.front().sharpness);
  const size_t directory = tables.size();
  tables.resize(directory + 3 * (n + 1));
  for (size_t k = 0; k <= n; ++k) {
    const PreconvolvedEnvironment::Level& level = k < n ? pre.levels[k] : pre.irradiance;
    tables[directory + 3 * k] = float(level.width);
    tables[directory + 3 * k + 1] = float(level.height);
    tables[directory + 3 * k + 2] = std::bit_cast<float>(uint32_t(tables.size()));
    tables.insert(tables.end(), level.rgb.begin(), level.rgb.end());
  }
  return offset;
}

uint32_t shade_flags(const ShadingOptions& o, bool light_shadows) {
  return (o.env_shadows ? svo::math::SVO_SHADE_ENV_SHADOWS : 0u) |
         (light_shadows ? svo::math::SVO_SHADE_LIGHT_SHADOWS : 0u) |
         (o.preconvolved && o.environment ? svo::math::SVO_SHADE_PRECONVOLVED : 0u) |
         (o.brdf_sampling ? svo::math::SVO_SHADE_BRDF_SAMPLING : 0u);
}

uint32_t append_environment_distribution(const Environment& env, std::vector<float>& tables) {
  std::vector<float> f(size_t(env.width) * env.height);
  for (uint32_t y = 0; y < env.height; ++y) {
    const float s = float(std::sin(M_PI * (y + 0.5) / env.height));
    for (uint32_t x = 0; x < env.width; ++x) {
      const size_t t = size_t(y) * env.width + x;
      f[t] = sampling_weight(&env.rgb[t * 3]) * s;
    }
  }
  return append_distribution(f, env.width, env.height, tables);
}

AreaLight AreaLight::placed(glm::vec3 at, glm::vec3 aim, float size, uint32_t width, uint32_t height,
                            std::vector<float> rgb, std::string source) {
  AreaLight a;
  a.width = width;
  a.height = height;
  a.rgb = std::move(rgb);
  a.source = std::move(source);
  a.centre = at;
  const glm::vec3 d = aim - at;
  const float dl = glm::length(d);
  if (!(dl > 0) || !std::isfinite(dl) || !(size > 0) || !std::isfinite(size))
    throw std::invalid_argument("area light: " + a.source + ": its position, aim and size must be finite, the aim " +
                                "apart from the position and the size above 0");
  const glm::vec3 n = d / dl;
  // edge_v towards +Y where the light does not face along Y, else -Z; then
  // edge_u x edge_v = n (front towards the aim).
  const glm::vec3 helper = std::abs(n.y) < 0.999f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, -1);
  const glm::vec3 v = glm::normalize(helper - glm::dot(helper, n) * n);
  const glm::vec3 u = glm::cross(v, n);
  const float aspect = float(width) / float(std::max(height, 1u));
  const float su = aspect >= 1 ? size : size * aspect, sv = aspect >= 1 ? size / aspect : size;
  a.edge_u = su * u;
  a.edge_v = sv * v;
  return a;
}

void validate_area_light(const AreaLight& a) {
  auto fail = [&](const std::string& why) { throw std::invalid_argument("area light: " + a.source + ": " + why); };
  auto finite = [](glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(a.centre) || !finite(a.edge_u) || !finite(a.edge_v)) fail("a NaN or Inf in its position or edges");
  const glm::vec3 c = glm::cross(a.edge_u, a.edge_v);
  if (!(glm::length(c) > 0) || !std::isfinite(glm::length(c))) fail("its edges span no area");
  if (a.width == 0 || a.height == 0 || a.width > 1024 || a.height > 1024)
    fail("its texture must be 1 to 1024 texels a side, not " + std::to_string(a.width) + "x" +
         std::to_string(a.height));
  if (a.rgb.size() != size_t(a.width) * a.height * 3) fail("its texels do not match its size");
  double total = 0;
  for (float v : a.rgb) {
    if (!std::isfinite(v) || v < 0) fail("a texel negative, NaN or Inf");
    total += v;
  }
  if (!(total > 0)) fail("black everywhere: it would light nothing");
}

const char* brdf_name(BrdfKind kind) {
  switch (kind) {
    case BrdfKind::Lambert:
      return "lambert";
    case BrdfKind::Beckmann:
      return "beckmann";
    case BrdfKind::Ggx:
      return "ggx";
    case BrdfKind::Phong:
      return "phong";
    case BrdfKind::Merl:
      return "merl";
  }
  return "?";
}

namespace {

using nlohmann::json;

// A string from the file as messages show it: in single quotes, control
// characters escaped as JSON escapes them (so that a message stays one
// line), at most 40 characters.
std::string shown(const std::string& s) {
  // Invalid UTF-8 (cut at 40 bytes, or in the file) shows as U+FFFD, never throws.
  const std::string q =
      json(s.size() > 40 ? s.substr(0, 40) + "..." : s).dump(-1, ' ', false, json::error_handler_t::replace);
  return "'" + q.substr(1, q.size() - 2) + "'";
}

struct KeyError {
  std::string where;
  std::runtime_error operator()(const std::string& key, const std::string& why) const {
    return std::runtime_error("material: " + where + ": key " + shown(key) + ": " + why);
  }
};

float number(const json& j, const std::string& key, float lo, float hi, const KeyError& err) {
  const json& v = j.at(key);
  if (!v.is_number()) throw err(key, "not a number");
  const double d = v.get<double>();
  if (!std::isfinite(d) || d < lo || d > hi) {
    throw err(key, std::to_string(d) + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return float(d);
}

glm::vec3 colour(const json& j, const std::string& key, float hi, const KeyError& err) {
  const json& v = j.at(key);
  if (v.is_number()) {
    const float c = number(j, key, 0.0f, hi, err);
    return glm::vec3(c);
  }
  if (!v.is_array() || v.size() != 3) throw err(key, "not [r, g, b]");
  glm::vec3 c;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number()) throw err(key, "not [r, g, b] of numbers");
    const double d = v[i].get<double>();
    if (!std::isfinite(d) || d < 0 || d > hi)
      throw err(key, "component " + std::to_string(d) + " outside [0, " + std::to_string(hi) + "]");
    c[i] = float(d);
  }
  return c;
}

}  // namespace

Material parse_material(const std::string& text, const fs::path& base, const std::string& where) {
  const KeyError err{where};
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    throw std::runtime_error("material: " + where + ": not JSON: " + what);
  }
  if (!j.is_object()) throw std::runtime_error("material: " + where + ": not a JSON object");
  static const std::vector<std::string> keys = {"name",      "brdf", "colour", "color",    "diffuse",
                                                "roughness", "f0",   "ior",    "exponent", "file"};
  for (const auto& [key, value] : j.items()) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      throw err(key, "unknown (keys: name, brdf, colour, diffuse, roughness, f0, ior, exponent, file)");
    }
  }
  Material m;
  if (!j.contains("brdf")) throw err("brdf", "missing (lambert, beckmann, ggx, phong or merl)");
  if (!j["brdf"].is_string()) throw err("brdf", "not a string");
  const std::string brdf = j["brdf"].get<std::string>();
  bool known = false;
  for (BrdfKind k : {BrdfKind::Lambert, BrdfKind::Beckmann, BrdfKind::Ggx, BrdfKind::Phong, BrdfKind::Merl}) {
    if (brdf == brdf_name(k)) m.kind = k, known = true;
  }
  if (!known) throw err("brdf", shown(brdf) + " is none of lambert, beckmann, ggx, phong, merl");
  if (j.contains("name")) {
    if (!j["name"].is_string()) throw err("name", "not a string");
    m.name = j["name"].get<std::string>();
  }
  if (j.contains("color") && j.contains("colour")) throw err("color", "given with 'colour'");
  const std::string colour_key = j.contains("color") ? "color" : "colour";
  if (j.contains(colour_key) && j.contains("diffuse")) throw err(colour_key, "given with 'diffuse' (the same thing)");
  m.diffuse = m.kind == BrdfKind::Lambert ? glm::vec3(1.0f) : glm::vec3(m.kind == BrdfKind::Merl ? 0.0f : 1.0f);
  if (j.contains(colour_key)) m.diffuse = colour(j, colour_key, 1.0f, err);
  if (j.contains("diffuse")) m.diffuse = colour(j, "diffuse", 1.0f, err);
  if (j.contains("roughness")) m.roughness = number(j, "roughness", 1e-3f, 4.0f, err);
  if (j.contains("f0") && j.contains("ior")) throw err("ior", "given with 'f0'");
  if (j.contains("f0")) m.f0 = colour(j, "f0", 1.0f, err);
  if (j.contains("ior")) {
    const float n = number(j, "ior", 1.0f, 10.0f, err);
    m.f0 = glm::vec3((n - 1) * (n - 1) / ((n + 1) * (n + 1)));
  }
  if (j.contains("exponent")) m.exponent = number(j, "exponent", 0.0f, 1e6f, err);
  if (j.contains("file")) {
    if (!j["file"].is_string()) throw err("file", "not a string");
    const std::string file = j["file"].get<std::string>();
    if (std::any_of(file.begin(), file.end(), [](char c) { return (unsigned char)(c) < 0x20; })) {
      throw err("file", shown(file) + " holds control characters");
    }
    m.file = file;
    if (m.file.is_relative()) m.file = base / m.file;
  }
  if (m.kind == BrdfKind::Merl) {
    if (m.file.empty()) throw err("file", "missing (brdf 'merl' reads a MERL binary)");
    m.merl = std::make_shared<const MerlBrdf>(load_merl(m.file));
  } else if (!m.file.empty()) {
    throw err("file", "only brdf 'merl' reads a file");
  }
  return m;
}

Material load_material(const fs::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw std::runtime_error("material: " + name + ": no such file");
  if (!fs::is_regular_file(st)) throw std::runtime_error("material: " + name + ": not a regular file");
  if (fs::file_size(path, ec) > (1u << 20)) throw std::runtime_error("material: " + name + ": larger than 1 MiB");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw std::runtime_error("material: " + name + ": cannot read");
  return parse_material(text.str(), path.parent_path(), name);
}

std::string material_json(const Material& m) {
  // Floats as the shortest decimals that read back as the same floats.
  auto f = [](float v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::stod(std::string(buf, r.ptr));
  };
  auto rgb = [&](glm::vec3 c) { return json::array({f(c.r), f(c.g), f(c.b)}); };
  json j;
  j["name"] = m.name;
  j["brdf"] = brdf_name(m.kind);
  j["diffuse"] = rgb(m.diffuse);
  if (m.kind == BrdfKind::Beckmann || m.kind == BrdfKind::Ggx) j["roughness"] = f(m.roughness);
  if (m.kind != BrdfKind::Lambert && m.kind != BrdfKind::Merl) j["f0"] = rgb(m.f0);
  if (m.kind == BrdfKind::Phong) j["exponent"] = f(m.exponent);
  if (m.kind == BrdfKind::Merl) j["file"] = m.file.string();
  return j.dump();
}

Material builtin_material(float specular, float sigma_rho2) {
  Material m;
  m.name = "built-in";
  m.kind = BrdfKind::Beckmann;
  m.diffuse = glm::vec3(1.0f);
  m.f0 = glm::vec3(specular);
  m.roughness = std::sqrt(std::max(2.0f * sigma_rho2, 1e-6f));
  return m;
}

struct MaterialEvaluator::Impl {
  ShadingTables tables;
  svo::math::MaterialKernel kernel;
  svo::math::SvoMaterial material;
};

MaterialEvaluator::MaterialEvaluator(const Material& m) : impl_(std::make_unique<Impl>()) {
  impl_->tables = build_shading_tables(ShadingOptions{}, m, false);
  impl_->kernel = svo::math::MaterialKernel{{impl_->tables.params, impl_->tables.floats.data()}};
  impl_->material = svo::math::svo_material_of(impl_->tables.params);
}

MaterialEvaluator::~MaterialEvaluator() = default;

glm::vec3 MaterialEvaluator::brdf(glm::vec3 tint, glm::vec3 wi, glm::vec3 wo) const {
  return impl_->kernel.svo_material_brdf(impl_->material, tint, wo, wi);
}

glm::vec3 MaterialEvaluator::albedo(glm::vec3 tint, glm::vec3 wo, uint32_t samples) const {
  glm::dvec3 sum(0);
  auto& k = impl_->kernel;
  for (uint32_t i = 0; i < samples; ++i) {
    const glm::vec3 u(k.svo_sample_1d(0, 1, i, 0), k.svo_sample_1d(0, 1, i, 1), k.svo_sample_1d(0, 1, i, 2));
    const glm::vec4 d = k.svo_sample_material(impl_->material, tint, wo, u);
    if (!(d.w > 0)) continue;
    sum += glm::dvec3(k.svo_material_brdf(impl_->material, tint, wo, glm::vec3(d))) * double(d.z / d.w);
  }
  return glm::vec3(sum / double(std::max(samples, 1u)));
}

std::vector<std::shared_ptr<const Material>> parse_scene_materials(const std::vector<std::string>& texts,
                                                                   const std::string& source) {
  std::vector<std::shared_ptr<const Material>> out;
  for (size_t i = 0; i < texts.size(); ++i) {
    out.push_back(std::make_shared<const Material>(
        parse_material(texts[i], std::filesystem::current_path(), "material " + std::to_string(i) + " of " + source)));
  }
  return out;
}

ShadingTables build_shading_tables(const ShadingOptions& o, const Material& default_material, bool light_shadows) {
  ShadingTables t;
  auto& p = t.params;
  if (o.environment) {
    const Environment& env = *o.environment;
    p.env = glm::uvec4(env.width, env.height, uint32_t(t.floats.size()), 0);
    t.floats.insert(t.floats.end(), env.rgb.begin(), env.rgb.end());
    p.env.w = append_environment_distribution(env, t.floats);
    p.env_xform = glm::vec4(glm::radians(o.env_rotate_deg), o.env_scale, 0, 0);
    if (o.preconvolved) p.env_xform.z = std::bit_cast<float>(append_preconvolved(*o.preconvolved, t.floats));
  }
  if (o.area_light) {
    const AreaLight& a = *o.area_light;
    validate_area_light(a);
    if (o.preconvolved) throw std::invalid_argument("area light: not with the pre-convolved environment");
    const auto texels = uint32_t(t.floats.size());
    t.floats.insert(t.floats.end(), a.rgb.begin(), a.rgb.end());
    std::vector<float> f(size_t(a.width) * a.height);
    for (size_t i = 0; i < f.size(); ++i) f[i] = sampling_weight(&a.rgb[3 * i]);
    p.area = glm::uvec4(a.width, a.height, 0, append_distribution(f, a.width, a.height, t.floats));
    p.area_centre = glm::vec4(a.centre, std::bit_cast<float>(texels));
    p.area_u = glm::vec4(a.edge_u, 0);
    p.area_v = glm::vec4(a.edge_v, 0);
  }
  // A measured BRDF's tables, once per material: its values, sampling
  // tables and SG fit (lobe_filter.glsl: count, then sharpness and
  // amplitude per lobe).
  auto merl_offsets = [&](const Material& m) {
    if (m.kind != BrdfKind::Merl) return std::array<uint32_t, 3>{0, 0, 0};
    if (!m.merl) throw std::invalid_argument("material '" + m.name + "': a MERL BRDF without its data");
    const auto tables = append_merl_tables(*m.merl, t.floats);
    const std::vector<MerlSgLobe> lobes = fit_merl_sg(*m.merl);
    const auto fit = uint32_t(t.floats.size());
    t.floats.push_back(float(lobes.size()));
    for (const MerlSgLobe& l : lobes) t.floats.insert(t.floats.end(), {l.sharpness, l.amplitude});
    return std::array<uint32_t, 3>{tables[0], tables[1], fit};
  };
  const bool scene = !o.material && !o.scene_materials.empty();
  const Material& m = o.material ? *o.material : scene ? *o.scene_materials[0] : default_material;
  const auto offsets = merl_offsets(m);
  p.material = glm::uvec4(uint32_t(m.kind), offsets[0], offsets[1], 0);
  p.env_xform.w = std::bit_cast<float>(offsets[2]);
  p.diffuse = glm::vec4(m.diffuse, m.roughness);
  p.specular = glm::vec4(m.f0, m.exponent);
  p.sampling = glm::uvec4(std::max(o.spp, 1u), o.seed, shade_flags(o, light_shadows), 0);
  if (scene && o.scene_materials.size() > 1) {
    // The scene's table (svo_scene_material): records after every MERL table.
    std::vector<std::array<uint32_t, 3>> merl(o.scene_materials.size());
    for (size_t i = 0; i < merl.size(); ++i) merl[i] = i == 0 ? offsets : merl_offsets(*o.scene_materials[i]);
    p.material.w = uint32_t(o.scene_materials.size());
    p.sampling.w = uint32_t(t.floats.size());
    for (size_t i = 0; i < merl.size(); ++i) {
      const Material& s = *o.scene_materials[i];
      // clang-format off
      const float record[svo::math::SVO_MATERIAL_FLOATS] = {
          std::bit_cast<float>(uint32_t(s.kind)), std::bit_cast<float>(merl[i][0]), std::bit_cast<float>(merl[i][1]),
          s.exponent, s.diffuse.x, s.diffuse.y, s.diffuse.z, s.roughness, s.f0.x, s.f0.y, s.f0.z,
          std::bit_cast<float>(merl[i][2])};
      // clang-format on
      t.floats.insert(t.floats.end(), std::begin(record), std::end(record));
    }
  }
  if (t.floats.empty()) t.floats.push_back(0.0f);
  return t;
}

}  // namespace svo::render
