// Input bandwidths of Bagher et al. 2013, "Interactive Rendering of Acquired
// Materials on Dynamic Geometry Using Frequency Analysis", Sec. 2.3 and
// Fig. 6: the local 2D bandwidth of an image by Haar wavelets (Eq. 7), and
// from it the angular bandwidth of an environment map and of a material's
// BRDF slices; and the windowed-FFT reference bandwidth of Fig. 12(d), that
// validates it. CPU only; no Vulkan.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "svo/render/shading.h"

namespace svo::render {

// The parameters of wavelet_bandwidth.
struct WaveletOptions {
  // Eq. 7: a band whose largest wavelet amplitude over the whole image is
  // below epsilon x the largest amplitude of all bands is insignificant and
  // dropped; in (0, 1). The paper uses 0.01.
  float epsilon = 0.01f;
  // The share of a pixel's wavelet energy (Fig. 6's histogram) that must lie
  // in the pixel's band and coarser ones; in (0, 1]. The paper uses 0.95.
  float percentile = 0.95f;
  // Embed the image in a zero frame twice its size first, its result cropped
  // back (area lights, so that their outline counts; Sec. 2.3).
  bool zero_pad = false;
  // Periodic in x (latitude-longitude maps, BRDF slices over phi); otherwise
  // the image's border pixels repeat beyond it (edge replication). y always
  // repeats its border rows.
  bool wrap_x = false;
};

// The local bandwidth of a 2D signal (row-major, width*height floats), in
// cycles per pixel, per pixel (row-major, width*height). Bagher et al.
// Sec. 2.3, Eq. 7 and Fig. 6, made exact as follows.
//
// Bands. Band i (i = 1 finest, ..., L = ceil(log2(max(width, height))))
// holds the 2D Haar wavelets of support s x s, s = 2^i pixels: horizontal,
// vertical and diagonal details, whose frequencies lie in (2^-(i+1), 2^-i].
// A wavelet's amplitude is its orthonormal coefficient over s (the mean of
// the signal times the +-1 pattern over the support), so that an edge of
// height 1 has amplitude 1/2 in every band it straddles the middle of.
//
// Shift invariance. The decimated decomposition sees an edge only in the
// bands whose block grid it does not fall on; instead every band is taken at
// all s x s shifts of its grid (cycle spinning, Coifman & Donoho 1995), and a
// pixel's energy in band i is the mean, over the s^2 shifted wavelets of
// band i whose support covers the pixel, of the sum of the three details'
// squared amplitudes: the energy of the decimated decomposition at the pixel,
// averaged over where the grid falls. Any width and height >= 1 work; no
// power-of-two padding.
//
// Eq. 7. Bands whose largest amplitude (over all shifts) is below
// epsilon x the largest of all bands are dropped. A pixel whose remaining
// energy is below (1e-5 x the largest amplitude)^2 is locally constant: 0.
//
// Percentile (Fig. 6). Going from the coarsest band to the finest, the
// pixel's band b is the first at which the bands so far hold at least
// `percentile` of its remaining energy; t in [0, 1] is where the percentile
// falls inside band b's energy (the share still needed over band b's share).
//
// Value. 2^(t - b - 2) cycles per pixel: the position t inside band b's
// octave (2^-(b+1), 2^-b], log-linear, reported one octave lower. The Haar
// wavelets leak a quarter of a sinusoid's energy into each finer band, so the
// 95th percentile of a sinusoid of f cycles per pixel falls 1 to 3 octaves
// above f (more where its slope is steep: energies are summed without phase,
// as the paper notes); the octave down puts every pixel of a sinusoid of
// radial frequency 0 < f <= 3/16 in [f, 4f] (observed [1.07 f, 2.98 f],
// tests/render/bandwidth_test.cpp). Frequency here is the Euclidean norm of
// the frequency vector (a diagonal sinusoid of k cycles along x and y is
// sqrt(2) k / size). The largest value is 1/4 (band 1, t = 1: a
// checkerboard), the smallest nonzero one 2^-(L+2).
//
// Cost: O(width * height * L) time, O((width + 2^L) * (height + 2^L) + L *
// width * height) memory; zero_pad quadruples both (1024 x 512: ~0.26 s
// with wrap_x, one thread).
// @throw std::invalid_argument (one line): an empty image, image.size() !=
//        width * height, a NaN or Inf value, epsilon or percentile out of range.
std::vector<float> wavelet_bandwidth(std::span<const float> image, uint32_t width, uint32_t height,
                                     const WaveletOptions& options = {});

// The angular bandwidth of a latitude-longitude environment map, in cycles
// per radian (Bagher et al. Sec. 2.3, "Distant illumination": nu_a =
// 2 pi / (2^I_w lambda_max)), per texel of an out_width x out_width/2 map
// laid out as the environment (+Y up, row 0 at +Y).
struct EnvironmentBandwidth {
  uint32_t width = 0, height = 0;
  std::vector<float> cycles_per_radian;  // width * height, row-major
};

// wavelet_bandwidth of the map's luminance (wrap_x) in cycles per pixel,
// times the largest pixels per radian of the pixel's row (the largest
// eigenvalue of the Jacobian of the latitude-longitude mapping):
// max(height / pi, width / (2 pi sin(theta))), theta = pi (row + 1/2) / height,
// sin(theta) floored at sin(pi / (2 height)); then max-pooled over the map
// pixels each output texel covers. out_width must be a power of two, >= 2 and
// <= the map's width; output texel (tx, ty) covers map pixels x with
// x * out_width / width == tx (and the same in y). A constant map gives 0
// everywhere. Near the poles a column spans little angle: the pole row of a
// 512 x 256 map multiplies cycles per pixel by ~13000 pixels per radian.
// @throw std::invalid_argument (one line): an empty map, a texel count that
//        does not match, a NaN or Inf texel, a bad out_width.
EnvironmentBandwidth environment_bandwidth(const Environment& env, uint32_t out_width = 64);

// The spatial bandwidth of an area light (Sec. 2.3, "Local light sources",
// Fig. 6), in cycles per scene unit, per texel of a grid laid out as the
// light's texture: wavelet_bandwidth of the texels' luminance, zero-padded
// so that the light's outline counts, each texel first repeated k x k times
// (k the smallest with the longer side at least 32 texels, so that a solid
// light's edge is a band of its own), divided by the smaller side of a grid
// texel in scene units. A solid white light one unit across reads about
// 0.5 cycles per unit inside (the light as a whole) and about 7 at its
// outline (tests/render/bandwidth_test.cpp).
// @throw std::invalid_argument (validate_area_light's messages)
struct AreaLightBandwidth {
  uint32_t width = 0, height = 0;
  std::vector<float> cycles_per_unit;  // width * height, row-major, row 0 as the texture's
};
AreaLightBandwidth area_light_bandwidth(const AreaLight& light);

// The layout of brdf_bandwidth's table (what the shaders read).
inline constexpr uint32_t kBrdfBandwidthTheta = 16, kBrdfBandwidthSlice = 16;

// A material's angular bandwidth in cycles per radian (Bagher et al.
// Sec. 2.3, "Reflectance"): how fast f(wl, wv) cos(theta_l) varies with the
// light's direction wl around each wl for a fixed view wv, the band-limit
// the BRDF puts on the incident light (B_{t,rho} of Fig. 4).
// kBrdfBandwidthTheta * kBrdfBandwidthSlice^2 floats, index
// (ti * 16 + row) * 16 + col:
// - ti: the view's elevation theta_v = (ti + 1/2) (pi/2) / 16, phi_v = 0;
// - (col, row): the light's direction on the equal-area (Lambert azimuthal)
//   disk of the hemisphere, x = (col + 1/2) / 8 - 1, y = (row + 1/2) / 8 - 1,
//   radius r = sqrt(2) sin(theta_l / 2), azimuth atan2(y, x) relative to the
//   view's (the mirror direction is at x < 0); texels outside the disk
//   repeat its rim.
// Each slice is evaluated at 128 x 128 (8x finer) as the luminance of
// MaterialEvaluator::brdf(1, wl, wv) cos(theta_l); its wavelet_bandwidth in
// cycles per pixel times the disk's largest pixels per radian, 64 /
// (sqrt(2) cos(theta_l / 2)) (from 45 at the pole to 64 at the horizon: no
// pole singularity); then max-pooled over 8 x 8 pixels. A slice that is
// constant gives 0; the largest value is about 0.25 x 64 = 16 cycles per
// radian (a mirror-like lobe).
// @throw what MaterialEvaluator's constructor throws (a MERL material without data)
std::vector<float> brdf_bandwidth(const Material& material);

// The reference image bandwidth of Bagher et al. Fig. 12(d), in cycles per
// pixel: on a grid of window centres every `stride` pixels (centre n at
// min(n stride + stride/2, size - 1) on each axis), the window x window
// neighbourhood [c - window/2, c + window/2) (border pixels repeated beyond
// the image), its Hann-weighted mean removed, times a 2D Hann window,
// transformed by FFTW (r2c, single precision). Its bandwidth is the 95th
// percentile of the power spectrum over the radial norm sqrt(fx^2 + fy^2),
// as wavelet_bandwidth's frequency: the smallest j / window such that the
// rings of radius [0, j + 1/2) bins hold >= 95% of the power; 0 where the
// window is constant. Each pixel takes its nearest centre (n = x / stride).
// A window's spectrum is its content's convolved with the Hann window's, one
// bin wide each side, so a sinusoid of m bins reads about m + 1 bins: within
// 1.5x of its frequency from ~2.5 cycles per window on (the uncertainty the
// paper's footnote 1 mentions); use a wider window for lower frequencies.
// Bins whose amplitude is below `epsilon` of the window's largest are left
// out (Eq. 7's epsilon; 0 keeps every bin), so that a faint broadband floor
// (Monte Carlo noise, voxel-scale detail) does not read as the bandwidth.
// Cost: one window^2 FFT per centre; the planner is guarded by a mutex, so
// calls on several threads are safe.
// @throw std::invalid_argument (one line): an empty image, a size mismatch,
//        a NaN or Inf value, window odd or outside [4, 4096], stride 0.
std::vector<float> windowed_fft_bandwidth(std::span<const float> image, uint32_t width, uint32_t height,
                                          uint32_t window = 32, uint32_t stride = 8, float epsilon = 0.01f);

}  // namespace svo::render
