// MERL measured BRDFs (Matusik et al. 2003; DESIGN 10.2): the database's
// binary files, their tabulation from an analytic BRDF (for tests and
// synthetic materials), and their place in the shading tables, where
// shaders/common/merl.glsl evaluates and importance samples them.
//
// The file format (the reference code BRDFRead.cpp): three int32
// little-endian dimensions 90 90 180, then the R, G and B blocks of
// 90 x 90 x 180 float64 each, phi_d fastest, then theta_d, then theta_h
// (theta_h index floor(90 sqrt(theta_h / (pi/2))), theta_d and phi_d one
// degree apart, phi_d in [0, 180) degrees). Stored values times the scales
// 1/1500, 1.15/1500, 1.66/1500 are the BRDF (1/sr); -1 marks a missing sample.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <glm/vec3.hpp>
#include <vector>

namespace svo::render {

inline constexpr uint32_t kMerlThetaH = 90;
inline constexpr uint32_t kMerlThetaD = 90;
inline constexpr uint32_t kMerlPhiD = 180;
inline constexpr uint32_t kMerlSamples = kMerlThetaH * kMerlThetaD * kMerlPhiD;
// The size of a MERL file: the 12-byte header and 3 blocks of doubles.
inline constexpr uint64_t kMerlFileBytes = 12 + 3 * 8 * uint64_t(kMerlSamples);
// Stored value times the scale of its channel = BRDF value.
inline constexpr std::array<double, 3> kMerlScale = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

// A measured BRDF: 3 * kMerlSamples values, RGB interleaved by sample
// (sample k = phi_d + 180 (theta_d + 90 theta_h)), already scaled (1/sr),
// missing samples 0.
struct MerlBrdf {
  std::vector<float> rgb;
};

// Reads a MERL .binary file. Safe for untrusted input: the path must name a
// regular file (a FIFO, a device or a directory is refused before it is
// opened for reading) of exactly kMerlFileBytes with dimensions 90 90 180.
// Negative samples (the format's -1) read as 0.
// @throw std::runtime_error "merl: PATH: why", one line (missing file, not a
//        regular file, wrong size, wrong dimensions, a NaN or infinite value
//        named by channel and index, a read error).
MerlBrdf load_merl(const std::filesystem::path& path);

// Writes `brdf` in the MERL format (values divided by the scales again),
// atomically: a temporary file in the same directory renamed over `path`.
// @throw std::runtime_error "merl: PATH: why" (brdf.rgb not 3 * kMerlSamples
//        values, or the write failed; `path` is then left as it was).
void write_merl(const std::filesystem::path& path, const MerlBrdf& brdf);

// The directions (wi, wo) of sample k (< kMerlSamples) in the local frame
// (normal +z): the table's own angles theta_h = (i_h / 90)^2 pi/2,
// theta_d = i_d pi/180, phi_d = i_p pi/180, with phi_h = 0. One of them may
// lie at or below the surface at grazing theta_h and theta_d.
std::array<glm::dvec3, 2> merl_sample_directions(uint32_t k);

// Tabulates an analytic BRDF (RGB, 1/sr; `brdf(wi, wo)` in the local frame,
// called concurrently from several threads) at each sample's directions
// (merl_sample_directions); samples with a direction at or below the surface
// are 0, like the database's missing ones.
// @throw std::invalid_argument if `brdf` returns a negative or non-finite value.
MerlBrdf tabulate_merl(const std::function<glm::dvec3(glm::dvec3 wi, glm::dvec3 wo)>& brdf);

// The number of floats of a BRDF's sampling tables (merl.glsl's layout).
uint32_t merl_sampling_floats();

// Appends the RGB values (kMerlSamples * 3 floats, merl.glsl's svo_merl_eval
// reads them) and then the sampling tables (merl_sampling_floats() floats,
// for svo_merl_sample and svo_merl_pdf) to the shading tables. Returns their
// offsets in `tables`: {values, sampling}.
// @throw std::invalid_argument if brdf.rgb has the wrong size or a negative
//        or non-finite value, or the tables would outgrow 32-bit offsets.
std::array<uint32_t, 2> append_merl_tables(const MerlBrdf& brdf, std::vector<float>& tables);

// One lobe of a measured BRDF's SG fit, in half-vector space about the
// normal: the BRDF's specular part near theta_d = 0 is approximately
// sum_k amplitude_k exp(sharpness_k (cos theta_h - 1)) (luminance, 1/sr).
// Tokuyoshi 2015 (section 4.1) fits measured BRDFs once, in preprocessing,
// for the lobe-aware weight of Eq. 11 (shaders/common/sg.glsl).
struct MerlSgLobe {
  float sharpness;
  float amplitude;
};

// Fits at most `max_lobes` (1..3) lobes, once per BRDF (render/src/merl_sg_fit.cpp):
// the luminance (0.2126 R + 0.7152 G + 0.0722 B) of the samples with
// theta_d index 0..5 (all phi_d averaged; samples with a direction at or
// below the surface, or missing, i.e. all channels 0, left out) as a
// function of theta_h, minus a constant diffuse floor (fitted too, not
// returned), least squares weighted by each theta_h bin's solid angle.
// NNLS over every set of up to max_lobes values of a log-spaced dictionary
// (64 values from 1 to 1e5), then golden-section steps in log-sharpness; a
// lobe is added only while it lowers the weighted squared error by more
// than 1e-5 of the data's weighted squared norm. Lobes sorted by sharpness,
// descending; lobes whose amplitude is not positive are dropped (a
// Lambertian BRDF gives none). Deterministic. Never NaN; sharpness within
// [1e-2, 1e5]. Takes a few tens of milliseconds.
// @throw std::invalid_argument if max_lobes is outside 1..3 or brdf.rgb
//        does not hold 3 * kMerlSamples values.
std::vector<MerlSgLobe> fit_merl_sg(const MerlBrdf& brdf, int max_lobes = 3);

// The relative RMS error of `lobes` plus the best non-negative floor over
// the samples fit_merl_sg uses: sqrt(sum w r^2 / sum w y^2) over the
// theta_h bins (weights w their solid angles, y the mean luminance); 0 for
// a BRDF without such samples.
// @throw std::invalid_argument if brdf.rgb does not hold 3 * kMerlSamples values.
double merl_sg_fit_error(const MerlBrdf& brdf, const std::vector<MerlSgLobe>& lobes);

}  // namespace svo::render
