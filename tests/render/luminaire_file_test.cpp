// Light-field luminaires (luminaire.h, docs/luminaire.md): the .lfl file's
// round trip and every hostile input as one line naming the problem, the
// basis on U, the procedural emitters, the radiance and the flux against
// an integral done here independently.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <xxhash.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "svo/render/luminaire.h"
#include "temp_dir.h"

namespace svo::render {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

// Offsets of the header's fields (docs/luminaire.md).
constexpr size_t kVersionAt = 8, kHeaderBytesAt = 12, kDeltaAt = 16, kWidthAt = 28, kHeightAt = 32, kGridWAt = 36,
                 kGridHAt = 40, kBasisAt = 48, kUnitsAt = 84;

void set_u32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
  for (int k = 0; k < 4; ++k) b[at + size_t(k)] = uint8_t(v >> (8 * k));
}
uint32_t get_u32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t(b[at]) | uint32_t(b[at + 1]) << 8 | uint32_t(b[at + 2]) << 16 | uint32_t(b[at + 3]) << 24;
}
void set_f32(std::vector<uint8_t>& b, size_t at, float v) { set_u32(b, at, std::bit_cast<uint32_t>(v)); }
float get_f32(const std::vector<uint8_t>& b, size_t at) { return std::bit_cast<float>(get_u32(b, at)); }

// Rewrites the trailing XXH64 over the bytes before it.
void reseal(std::vector<uint8_t>& b) {
  const uint64_t sum = XXH64(b.data(), b.size() - 8, 0);
  for (int k = 0; k < 8; ++k) b[b.size() - 8 + size_t(k)] = uint8_t(sum >> (8 * k));
}

LightField small_panel() { return make_panel_luminaire(8, 2, 100.0f, 2); }

// Where image m's luminance and chromaticity start in the file's bytes.
size_t luminance_at(const std::vector<uint8_t>& b, const LightField& f, uint32_t m) {
  return get_u32(b, kHeaderBytesAt) + size_t(m) * 12 * f.width * f.height;
}
size_t chroma_at(const std::vector<uint8_t>& b, const LightField& f, uint32_t m) {
  return luminance_at(b, f, m) + 4 * size_t(f.width) * f.height;
}

// The message of parse_light_field on `bytes`: one line, naming the input.
std::string refusal(const std::vector<uint8_t>& bytes) {
  try {
    parse_light_field(bytes.data(), bytes.size(), "hostile.lfl");
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.rfind("luminaire: hostile.lfl: ", 0), 0u) << what;
    return what;
  }
  ADD_FAILURE() << "accepted";
  return "";
}

#define EXPECT_REFUSED(bytes, part) EXPECT_NE(refusal(bytes).find(part), std::string::npos) << refusal(bytes)

void expect_same(const LightField& a, const LightField& b) {
  EXPECT_EQ(a.delta, b.delta);
  EXPECT_EQ(a.extent, b.extent);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.grid_w, b.grid_w);
  EXPECT_EQ(a.grid_h, b.grid_h);
  EXPECT_EQ(a.spacing, b.spacing);
  EXPECT_EQ(a.basis, b.basis);
  EXPECT_EQ(a.units, b.units);
  EXPECT_EQ(a.metres_per_unit, b.metres_per_unit);
  EXPECT_EQ(a.pose.at, b.pose.at);
  EXPECT_EQ(a.pose.aim, b.pose.aim);
  EXPECT_EQ(a.pose.size, b.pose.size);
  EXPECT_EQ(a.source, b.source);
  ASSERT_EQ(a.images.size(), b.images.size());
  double worst = 0;
  for (size_t m = 0; m < a.images.size(); ++m) {
    ASSERT_EQ(a.images[m].size(), b.images[m].size());
    for (size_t t = 0; t < a.images[m].size(); t += 3) {
      const float* x = &a.images[m][t];
      const float* y = &b.images[m][t];
      const double scale = std::max({x[0], x[1], x[2]});
      for (int c = 0; c < 3; ++c) {
        if (scale == 0) {
          EXPECT_EQ(y[c], 0.0f);
        } else {
          worst = std::max(worst, std::abs(double(x[c]) - y[c]) / scale);
        }
      }
    }
  }
  EXPECT_LE(worst, 1e-5) << "largest error relative to the texel's largest component";
}

TEST(LuminaireFile, ProceduralEmittersRoundTrip) {
  TempDir dir;
  for (const LightField& f : {make_panel_luminaire(16, 3, 1000.0f), make_headlight_luminaire(16, 5, 5000.0f)}) {
    const fs::path path = dir.path() / "f.lfl";
    save_light_field(f, path);
    EXPECT_EQ(fs::file_size(path), 104 + f.source.size() + 12ull * 16 * 16 * f.image_count() + 8);
    expect_same(f, load_light_field(path));
  }
}

TEST(LuminaireFile, EveryHeaderFieldRoundTrips) {
  LightField f = make_headlight_luminaire(7, 2, 30.0f);
  f.height = 5;
  for (auto& image : f.images) image.resize(3 * 7 * 5);
  f.grid_w = 1;
  f.images.resize(2);
  f.delta = 12.5f;
  f.extent = {80.0f, 60.0f};
  f.spacing = 3.25f;
  f.basis = LuminaireBasis::Quadratic;
  f.units = "mm";
  f.metres_per_unit = 0.001f;
  f.pose = {{1.0f, -2.0f, 3.0f}, {0.5f, 0.25f, -4.0f}, 0.75f};
  f.source = "a test, \xc3\xa9t\xc3\xa9";  // UTF-8 is allowed
  const std::vector<uint8_t> bytes = encode_light_field(f);
  expect_same(f, parse_light_field(bytes.data(), bytes.size(), "t.lfl"));
  // The units field: 16 bytes, NUL padded.
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(&bytes[kUnitsAt]), 3), std::string("mm\0", 3));
}

TEST(LuminaireFile, BlackTexelStoresOneThirdAndDecodesToZero) {
  LightField f = small_panel();
  f.images[1][3 * 5 + 0] = f.images[1][3 * 5 + 1] = f.images[1][3 * 5 + 2] = 0.0f;
  const std::vector<uint8_t> bytes = encode_light_field(f);
  EXPECT_EQ(get_f32(bytes, luminance_at(bytes, f, 1) + 4 * 5), 0.0f);
  EXPECT_EQ(get_f32(bytes, chroma_at(bytes, f, 1) + 8 * 5), float(1.0 / 3.0));
  EXPECT_EQ(get_f32(bytes, chroma_at(bytes, f, 1) + 8 * 5 + 4), float(1.0 / 3.0));
  const LightField g = parse_light_field(bytes.data(), bytes.size(), "t.lfl");
  for (int c = 0; c < 3; ++c) EXPECT_EQ(g.images[1][3 * 5 + size_t(c)], 0.0f);
  // Stored luminance is Rec. 709's.
  const float* t = &f.images[0][0];
  EXPECT_NEAR(get_f32(bytes, luminance_at(bytes, f, 0)), 0.2126f * t[0] + 0.7152f * t[1] + 0.0722f * t[2], 1e-4);
}

TEST(LuminaireFile, HostileBytesAreOneLineErrors) {
  const LightField f = small_panel();
  const std::vector<uint8_t> good = encode_light_field(f);
  auto edited = [&](auto edit, bool seal = true) {
    std::vector<uint8_t> b = good;
    edit(b);
    if (seal) reseal(b);
    return b;
  };
  EXPECT_REFUSED(std::vector<uint8_t>(good.begin(), good.end() - 1), "truncated: ");
  EXPECT_REFUSED(std::vector<uint8_t>(good.begin(), good.begin() + 50), "truncated: 50 bytes");
  EXPECT_REFUSED(std::vector<uint8_t>(good.begin(), good.begin() + 3), "truncated: 3 bytes");
  EXPECT_REFUSED(std::vector<uint8_t>(), "truncated: 0 bytes");
  EXPECT_REFUSED(edited([&](auto& b) { b[luminance_at(b, f, 2) + 17] ^= 0x10; }, false), "checksum mismatch");
  EXPECT_REFUSED(edited([](auto& b) { b[2] = 'X'; }), "bad magic");
  EXPECT_REFUSED(edited([](auto& b) { set_u32(b, kVersionAt, 2); }),
                 "unsupported version 2 (this build reads version 1)");
  EXPECT_REFUSED(edited([](auto& b) { set_u32(b, kWidthAt, 0); }), "image size 0 x 8 is outside 1 to 1024");
  EXPECT_REFUSED(edited([](auto& b) { set_u32(b, kWidthAt, 1025); }), "image size 1025 x 8 is outside 1 to 1024");
  EXPECT_REFUSED(edited([](auto& b) { set_u32(b, kGridWAt, 17); }), "basis grid 17 x 2 is outside 1 to 16");
  EXPECT_REFUSED(edited([](auto& b) {
                   set_u32(b, kWidthAt, 1024), set_u32(b, kHeightAt, 1024), set_u32(b, kGridWAt, 16),
                       set_u32(b, kGridHAt, 16);
                 }),
                 "texels, more than the limit of 67108864");
  // A size lie: the header says 3 x 2 images, the bytes hold 2 x 2.
  EXPECT_REFUSED(edited([](auto& b) { set_u32(b, kGridWAt, 3); }), "truncated: ");
  EXPECT_REFUSED(edited([](auto& b) { set_u32(b, kGridWAt, 3); }), "the header implies");
  EXPECT_REFUSED(edited([](auto& b) { b.insert(b.end() - 8, 0); }), "bytes, the header implies");
  EXPECT_REFUSED(edited([](auto& b) { set_u32(b, kHeaderBytesAt, get_u32(b, kHeaderBytesAt) + 4); }), "header of ");
  // Values, behind a valid checksum.
  EXPECT_REFUSED(edited([&](auto& b) { set_f32(b, luminance_at(b, f, 1) + 4 * 9, std::nanf("")); }),
                 "image 1 texel (1, 1): luminance NaN");
  EXPECT_REFUSED(edited([&](auto& b) { set_f32(b, luminance_at(b, f, 3), -1.0f); }),
                 "image 3 texel (0, 0): luminance -1");
  EXPECT_REFUSED(edited([&](auto& b) { set_f32(b, luminance_at(b, f, 0), INFINITY); }), "luminance inf");
  EXPECT_REFUSED(edited([&](auto& b) { set_f32(b, chroma_at(b, f, 0) + 8 * 2, 1.5f); }),
                 "image 0 texel (2, 0): chromaticity (1.5, ");
  EXPECT_REFUSED(
      edited([&](auto& b) { set_f32(b, chroma_at(b, f, 0), 0.6f), set_f32(b, chroma_at(b, f, 0) + 4, 0.6f); }),
      "chromaticity (0.600000024, 0.600000024)");
  EXPECT_REFUSED(edited([&](auto& b) { set_f32(b, chroma_at(b, f, 0) + 4, -0.1f); }), "chromaticity");
  // Far past the float range once decoded (pure blue at the largest luminance).
  EXPECT_REFUSED(edited([&](auto& b) {
                   set_f32(b, luminance_at(b, f, 0), 3e38f), set_f32(b, chroma_at(b, f, 0), 0.0f),
                       set_f32(b, chroma_at(b, f, 0) + 4, 0.0f);
                 }),
                 "decodes past the float range");
  EXPECT_REFUSED(edited([](auto& b) { set_f32(b, kDeltaAt, 0.0f); }), "delta 0 is not finite and > 0");
  EXPECT_REFUSED(edited([](auto& b) { set_f32(b, kDeltaAt + 4, std::nanf("")); }), "extent x NaN");
  EXPECT_REFUSED(edited([](auto& b) { set_u32(b, kBasisAt, 7); }), "unknown basis 7");
  EXPECT_REFUSED(edited([](auto& b) { b[kUnitsAt] = 0x07; }), "units hold byte 7");
  EXPECT_REFUSED(edited([](auto& b) { b[kUnitsAt + 5] = 'x'; }), "units field holds byte 120 after its NUL");
  EXPECT_REFUSED(edited([](auto& b) { b[kUnitsAt] = 0; }), "units '' must be 1 to 15");
  EXPECT_REFUSED(edited([](auto& b) { b[104] = '\n'; }), "source holds control byte 10");
  // The good bytes still parse (the edits above were on copies).
  EXPECT_NO_THROW(parse_light_field(good.data(), good.size(), "good.lfl"));
}

TEST(LuminaireFile, FilesThatAreNotRegularAreRefusedUnread) {
  TempDir dir;
  auto message = [](const fs::path& path) -> std::string {
    try {
      load_light_field(path);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "accepted";
  };
  const fs::path fifo = dir.path() / "fifo.lfl";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(message(fifo), "luminaire: " + fifo.string() + ": is a FIFO, expected a .lfl file");
  EXPECT_EQ(message(dir.path()), "luminaire: " + dir.path().string() + ": is a directory, expected a .lfl file");
  EXPECT_EQ(message("/dev/zero"), "luminaire: /dev/zero: is a character device, expected a .lfl file");
  EXPECT_EQ(message(dir.path() / "missing.lfl"),
            "luminaire: " + (dir.path() / "missing.lfl").string() + ": no such file");
  // A file cut short on disk: the header's size check, before the images are read.
  const fs::path cut = dir.path() / "cut.lfl";
  save_light_field(small_panel(), cut);
  fs::resize_file(cut, fs::file_size(cut) - 100);
  EXPECT_NE(message(cut).find(": truncated: "), std::string::npos) << message(cut);
  // A large file of the wrong kind is refused from its first bytes.
  const fs::path big = dir.path() / "big.lfl";
  { std::ofstream(big) << std::string(1 << 20, 'x'); }
  EXPECT_NE(message(big).find("bad magic"), std::string::npos) << message(big);
}

TEST(LuminaireFile, SaveErrorsAreOneLineAndLeaveNothing) {
  TempDir dir;
  const fs::path missing = dir.path() / "no" / "such" / "f.lfl";
  try {
    save_light_field(small_panel(), missing);
    ADD_FAILURE() << "saved into a folder that does not exist";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.rfind("luminaire: " + missing.string() + ": ", 0), 0u) << what;
  }
  // An invalid field is refused before anything is written, naming the path.
  LightField bad = small_panel();
  bad.images.pop_back();
  const fs::path path = dir.path() / "bad.lfl";
  try {
    save_light_field(bad, path);
    ADD_FAILURE() << "saved an invalid field";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "luminaire: " + path.string() + ": 3 images, expected 4 (2 x 2)");
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 0);
}

TEST(LuminaireFile, ValidateChecksAFieldInMemory) {
  auto message = [](const LightField& f) -> std::string {
    try {
      validate_light_field(f);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "accepted";
  };
  LightField f = small_panel();
  f.source = "test";
  EXPECT_EQ(message(f), "accepted");
  LightField g = f;
  g.images.pop_back();
  EXPECT_EQ(message(g), "luminaire: test: 3 images, expected 4 (2 x 2)");
  g = f;
  g.images[2].pop_back();
  EXPECT_EQ(message(g), "luminaire: test: image 2 holds 191 values, expected 192 (3 x 8 x 8)");
  g = f;
  g.images[1][3 * 10 + 2] = std::nanf("");
  EXPECT_EQ(message(g), "luminaire: test: image 1 texel (2, 1) B is NaN, expected finite and >= 0");
  g = f;
  g.images[0][1] = -0.5f;
  EXPECT_EQ(message(g), "luminaire: test: image 0 texel (0, 0) G is -0.5, expected finite and >= 0");
  g = f;
  g.spacing = 0.0f;
  EXPECT_EQ(message(g), "luminaire: test: spacing 0 is not finite and > 0");
  g = f;
  g.units = "millimetres long";
  EXPECT_EQ(message(g), "luminaire: test: units 'millimetres long' must be 1 to 15 characters");
  g = f;
  g.source = std::string(256, 'a');
  EXPECT_EQ(message(g), "luminaire: light field: source is 256 bytes, more than 255");
  g = f;
  g.width = 0;
  EXPECT_EQ(message(g), "luminaire: test: image size 0 x 8 is outside 1 to 1024 per side");
}

// --- the model --------------------------------------------------------

TEST(Luminaire, BSplineIsAPartitionOfUnityInsideTheGrid) {
  LightField f = make_panel_luminaire(4, 5, 1.0f);
  const float h = f.spacing;
  // Inside |x| <= ((W - 1) / 2 - 1 / 2) h every basis whose support covers x exists.
  const float inner = (0.5f * float(f.grid_w - 1) - 0.5f) * h;
  double worst = 0;
  for (int j = 0; j <= 40; ++j) {
    for (int i = 0; i <= 40; ++i) {
      const glm::vec2 u(-inner + 2 * inner * float(i) / 40, -inner + 2 * inner * float(j) / 40);
      double sum = 0;
      for (uint32_t m = 0; m < f.image_count(); ++m) sum += f.basis_value(m, u);
      worst = std::max(worst, std::abs(sum - 1));
    }
  }
  EXPECT_LT(worst, 1e-6);
  // Each 1D profile integrates to one cell.
  double integral = 0;
  for (int k = 0; k < 30000; ++k)
    integral += luminaire_basis_phi(LuminaireBasis::BSpline, -1.5f + (k + 0.5f) * 1e-4f) * 1e-4;
  EXPECT_NEAR(integral, 1.0, 1e-6);
  EXPECT_EQ(luminaire_basis_cells(LuminaireBasis::BSpline), 3u);
  EXPECT_EQ(luminaire_basis_phi(LuminaireBasis::BSpline, 1.5f), 0.0f);
  EXPECT_STREQ(luminaire_basis_name(LuminaireBasis::BSpline), "bspline");
}

TEST(Luminaire, QuadraticIsNotAPartitionOfUnity) {
  LightField f = make_panel_luminaire(4, 5, 1.0f);
  f.basis = LuminaireBasis::Quadratic;
  const float h = f.spacing;
  auto sum_at = [&](glm::vec2 u) {
    double s = 0;
    for (uint32_t m = 0; m < f.image_count(); ++m) s += f.basis_value(m, u);
    return s;
  };
  EXPECT_NEAR(sum_at(glm::vec2(0.0f)), 1.0, 1e-6);                 // on a centre: 1
  EXPECT_NEAR(sum_at(glm::vec2(0.5f * h, 0.0f)), 1.5, 1e-5);       // half way in x: 2 (1 - 1/4)
  EXPECT_NEAR(sum_at(glm::vec2(0.5f * h, 0.5f * h)), 2.25, 1e-5);  // in both
  EXPECT_EQ(luminaire_basis_cells(LuminaireBasis::Quadratic), 2u);
  EXPECT_STREQ(luminaire_basis_name(LuminaireBasis::Quadratic), "quadratic");
}

TEST(Luminaire, PanelTexelsAreTheDocumentedChecker) {
  const float radiance = 200.0f;
  const LightField f = make_panel_luminaire(8, 3, radiance, 4);
  ASSERT_EQ(f.images.size(), 9u);
  const glm::vec3 bright = radiance * glm::vec3(1.0f, 0.95f, 0.85f), dark = radiance * glm::vec3(0.25f, 0.3f, 0.4f);
  for (const auto& image : f.images) {
    ASSERT_EQ(image, f.images[0]);  // every image the same
    for (uint32_t y = 0; y < 8; ++y) {
      for (uint32_t x = 0; x < 8; ++x) {
        // 4 x 4 squares of 2 x 2 texels, the one at (0, 0) bright.
        const glm::vec3 want = (x / 2 + y / 2) % 2 == 0 ? bright : dark;
        const float* t = &image[3 * (y * 8 + x)];
        EXPECT_EQ(glm::vec3(t[0], t[1], t[2]), want) << x << ", " << y;
      }
    }
  }
  EXPECT_NO_THROW(validate_light_field(f));
  EXPECT_NO_THROW(validate_light_field(make_headlight_luminaire(8, 3, radiance)));
  // The makers keep the loader's limits: 256 images of 1024^2 would be 4 x kMaxTexels.
  EXPECT_THROW(make_panel_luminaire(1024, 16, 1.0f), std::invalid_argument);
  EXPECT_THROW(make_panel_luminaire(0, 2, 1.0f), std::invalid_argument);
  EXPECT_THROW(make_headlight_luminaire(8, 17, 1.0f), std::invalid_argument);
}

TEST(Luminaire, RadianceIsTheSumOverTheBasisAndZeroOutsideS) {
  const LightField f = make_panel_luminaire(8, 3, 10.0f, 2);
  const glm::vec2 u(0.004f, -0.007f);
  double phi = 0;
  for (uint32_t m = 0; m < f.image_count(); ++m) phi += f.basis_value(m, u);
  // s in texel (1, 6): the check (0, 1), dark.
  const glm::vec2 s = (glm::vec2(1.5f, 6.5f) / 8.0f - 0.5f) * f.extent;
  const glm::vec3 l = f.radiance(u, s);
  EXPECT_NEAR(l.x, 2.5 * phi, 1e-5);
  EXPECT_NEAR(l.y, 3.0 * phi, 1e-5);
  const glm::vec2 half = 0.5f * f.extent;
  for (glm::vec2 out : {glm::vec2(half.x * 1.001f, 0.0f), glm::vec2(0.0f, -half.y * 1.001f), glm::vec2(half.x, 0.0f),
                        glm::vec2(-half.x * 3.0f, half.y * 3.0f), glm::vec2(std::nanf(""), 0.0f)}) {
    EXPECT_EQ(f.radiance(u, out), glm::vec3(0.0f)) << out.x << ", " << out.y;
  }
  EXPECT_GT(f.radiance(u, -half).x, 0.0f);  // the lower edge is inside
}

// The flux of a one-image field by tensor Gauss-Legendre quadrature, each
// factor split where phi or the texels change: the integral of
// C(s) Phi(u) delta^2 / |(s - u, delta)|^4 over U x S (luminance).
double brute_force_flux(const LightField& f) {
  static const double x8[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                               0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
  static const double w8[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066402683331, 0.3626837833783620,
                               0.3626837833783620, 0.3137066402683331, 0.2223810344533745, 0.1012285362903763};
  auto phi = [&](double x) {  // in double, from the formula (not the code under test)
    const double a = std::abs(x);
    if (f.basis == LuminaireBasis::Quadratic) return a < 1 ? 1 - a * a : 0.0;
    return a < 0.5 ? 0.75 - a * a : a < 1.5 ? 0.5 * (1.5 - a) * (1.5 - a) : 0.0;
  };
  const double h = f.spacing, d2 = double(f.delta) * f.delta;
  // Nodes and weights of one axis over [lo, hi] in `pieces` panels.
  auto nodes = [&](double lo, double hi, int pieces, std::vector<double>& x, std::vector<double>& w) {
    for (int p = 0; p < pieces; ++p) {
      const double a = lo + (hi - lo) * p / pieces, b = lo + (hi - lo) * (p + 1) / pieces;
      for (int k = 0; k < 8; ++k) {
        x.push_back(0.5 * (a + b) + 0.5 * (b - a) * x8[k]);
        w.push_back(0.5 * (b - a) * w8[k]);
      }
    }
  };
  std::vector<double> ux, uw;  // U: each of the B-spline's three pieces in 4 panels
  for (double lo : {-1.5, -0.5, 0.5}) nodes(lo * h, (lo + 1) * h, 4, ux, uw);
  double flux = 0;
  for (uint32_t ty = 0; ty < f.height; ++ty) {
    for (uint32_t tx = 0; tx < f.width; ++tx) {
      const float* c = &f.images[0][3 * (ty * f.width + tx)];
      const double lum = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
      std::vector<double> sx, sxw, sy, syw;
      const double wx = double(f.extent.x) / f.width, wy = double(f.extent.y) / f.height;
      nodes(-0.5 * f.extent.x + tx * wx, -0.5 * f.extent.x + (tx + 1) * wx, 4, sx, sxw);
      nodes(-0.5 * f.extent.y + ty * wy, -0.5 * f.extent.y + (ty + 1) * wy, 4, sy, syw);
      double sum = 0;
      for (size_t a = 0; a < sy.size(); ++a) {
        for (size_t b = 0; b < sx.size(); ++b) {
          for (size_t j = 0; j < ux.size(); ++j) {
            const double pj = phi(ux[j] / h) * uw[j];
            for (size_t i = 0; i < ux.size(); ++i) {
              const double dx = sx[b] - ux[i], dy = sy[a] - ux[j];
              const double r2 = dx * dx + dy * dy + d2;
              sum += syw[a] * sxw[b] * pj * phi(ux[i] / h) * uw[i] * d2 / (r2 * r2);
            }
          }
        }
      }
      flux += lum * sum;
    }
  }
  return flux;
}

TEST(Luminaire, FluxOfOnePanelImageMatchesTheIntegral) {
  // One basis function, a 4 x 4 texel panel of 2 x 2 checks, at the
  // emitters' proportions (delta half the extent: strongly near-field).
  LightField f = make_panel_luminaire(4, 1, 100.0f, 2);
  const double reference = brute_force_flux(f);
  // The far field, in closed form: as delta grows, delta^2 / r^4 -> 1 / delta^2 and
  // the flux -> sum(lum * texel area) * (integral of Phi = h^2) / delta^2.
  const double bright = 100 * (0.2126 + 0.7152 * 0.95 + 0.0722 * 0.85),
               dark = 100 * (0.2126 * 0.25 + 0.7152 * 0.3 + 0.0722 * 0.4);
  const double texel = double(f.extent.x) * f.extent.y / 16;
  const double far = 8 * (bright + dark) * texel * double(f.spacing) * f.spacing / (double(f.delta) * f.delta);
  EXPECT_LT(reference, far);  // obliquity only takes away
  EXPECT_GT(reference, 0.2 * far);
  const double flux = light_field_flux(f, 4);
  EXPECT_NEAR(flux / reference, 1.0, 2e-3) << "flux " << flux << ", reference " << reference;
  // And far away, where the closed form holds.
  f.delta = 10.0f;
  const double far10 = 8 * (bright + dark) * texel * double(f.spacing) * f.spacing / 100.0;
  EXPECT_NEAR(brute_force_flux(f) / far10, 1.0, 1e-3);
  EXPECT_NEAR(light_field_flux(f, 2) / far10, 1.0, 1e-3);
}

}  // namespace
}  // namespace svo::render
