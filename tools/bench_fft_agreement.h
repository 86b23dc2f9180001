// Fig. 12's bandwidth validation for svo bench bandwidth (Bagher et al.
// 2013): the predicted image bandwidth b_p against a windowed FFT of an
// image, as Spearman rank correlations.
#pragma once

#include <cstdint>
#include <vector>

#include "svo/render/renderer.h"

namespace svo::tools::bench {

// Spearman's rank correlation of two samples (ties share their mean rank);
// 0 when either is constant.
double rank_correlation(const std::vector<double>& x, const std::vector<double>& y);

// The mean of `v` over the covered pixels (coverage >= 0.999) of each
// pixel's window of `window` x `window` pixels (clipped at the frame's
// edges); 0 where the window holds none. Images are size x size.
std::vector<double> window_mean(const std::vector<float>& v, const std::vector<float>& coverage, uint32_t size,
                                uint32_t window);

// The prediction against a windowed FFT (32x32, Hann, stride 8,
// render::windowed_fft_bandwidth) of `image`'s luminance.
struct FftAgreement {
  std::vector<float> shown;  // the FFT's bandwidth on covered pixels, -1 elsewhere
  double rho = 0;            // over the covered pixels
  double rho_window = 0;     // the same with the prediction averaged over the FFT's window (bp_window)
  double rho_interior = 0;   // over the pixels whose whole window is covered surface
  size_t interior = 0;       // how many pixels those are
};
FftAgreement fft_agreement(const render::Frame& image, const std::vector<float>& bp,
                           const std::vector<double>& bp_window, const std::vector<float>& coverage, uint32_t size);

}  // namespace svo::tools::bench
