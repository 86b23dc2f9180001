// Heitz & Neyret Eq. 17 against Monte Carlo integration of Eq. 15 over a
// synthetic Gaussian height field with a(h) = abar + a_s s(h): the closed
// form is exact there, so the two must agree up to the Monte Carlo noise.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "common/shared_math.h"

namespace {
using namespace svo::math;

struct Estimate {
  double mean;
  double stderr_;
};

// Self-normalised Monte Carlo of Eq. 15 with V(v,h) V(l,h) = g(h)^L, heights
// h ~ N(0, sigma_h^2) drawn in double with std::erfc (independent of ours).
// Weights are formed in log space so that L = 1e6 keeps its tail.
Estimate monte_carlo_eq15(double abar, double a_s, double sigma_h, double L, int samples, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma_h);
  std::vector<double> log_w(samples), a(samples);
  double max_log_w = -INFINITY;
  for (int i = 0; i < samples; ++i) {
    double h = normal(rng);
    double x = h / (std::sqrt(2.0) * sigma_h);
    double g = 0.5 * std::erfc(-x);
    a[i] = abar + a_s * std::erf(x);
    log_w[i] = L == 0 ? 0.0 : L * std::log(g);
    max_log_w = std::max(max_log_w, log_w[i]);
  }
  double sw = 0, swa = 0, sww = 0;
  for (int i = 0; i < samples; ++i) {
    double w = std::exp(log_w[i] - max_log_w);
    sw += w;
    swa += w * a[i];
    sww += w * w;
  }
  double mean = swa / sw;
  double var = 0;
  for (int i = 0; i < samples; ++i) {
    double w = std::exp(log_w[i] - max_log_w) / sw;
    var += w * w * (a[i] - mean) * (a[i] - mean);
  }
  return {mean, std::sqrt(var)};
}

class AttributeEq17 : public ::testing::TestWithParam<double> {};

TEST_P(AttributeEq17, MatchesMonteCarloOfEq15Within0005) {
  const double L = GetParam();
  const double abar = 0.45, a_s = 0.3, sigma_h = 0.7;
  Estimate mc = monte_carlo_eq15(abar, a_s, sigma_h, L, 2000000, 1234);
  float closed = svo_attribute_vl(float(abar), float(a_s), float(L));
  EXPECT_NEAR(closed, mc.mean, 0.005) << "L = " << L << ", Monte Carlo standard error " << mc.stderr_;
  // The estimate itself must be precise enough for the bound to mean something.
  EXPECT_LT(mc.stderr_, 0.002) << "L = " << L;
  std::printf("L = %-8g Eq.17 %.6f  Monte Carlo %.6f +- %.6f\n", L, closed, mc.mean, mc.stderr_);
}

std::string l_name(const ::testing::TestParamInfo<double>& info) {
  std::ostringstream name;
  name << "L" << info.param;
  std::string text = name.str();
  for (char& c : text) c = (c == '.' || c == '+' || c == '-') ? '_' : c;
  return text;
}

INSTANTIATE_TEST_SUITE_P(PaperValues, AttributeEq17, ::testing::Values(0.0, 0.01, 0.1, 1.0, 10.0, 100.0, 1e6), l_name);

// The whole chain from (mu, sigma) of view and light: our Lambdas give L,
// Eq. 17 gives abar(v, l), Monte Carlo of Eq. 15 with that L must agree.
TEST(AttributeEq17, FromViewAndLightLambdas) {
  const float sigma = 0.3f;
  for (float mu_v : {0.05f, 0.3f, 1.0f}) {
    for (float mu_l : {0.1f, 0.6f, 3.0f}) {
      float L = svo_smith_lambda(mu_v, sigma) + svo_smith_lambda(mu_l, sigma);
      Estimate mc = monte_carlo_eq15(0.5, -0.25, 1.0, L, 400000, 99);
      EXPECT_NEAR(svo_attribute_vl(0.5f, -0.25f, L), mc.mean, 0.005) << mu_v << " " << mu_l;
    }
  }
}

}  // namespace
