// Independent references for the numerics tests: long double, std library
// special functions, no code shared with shaders/common/.
#pragma once

#include <cmath>
#include <limits>

namespace svo::test {

constexpr long double kPi = 3.141592653589793238462643383279502884L;

// Smith Lambda(a), a = mu / (sqrt(2) sigma), in long double. The cancellation
// of Eq. 6 costs at most log10(2 a^2 + 1) digits of the 19 we have here, and
// past a = 12 the first terms of the asymptotic series take over.
inline long double lambda_ref(long double a) {
  if (a <= 0) return std::numeric_limits<long double>::infinity();
  if (a > 12) {
    long double a2 = a * a;
    // Lambda = exp(-a^2) / (2 a sqrt(pi)) * (1/(2a^2) - 3/(4a^4) + 15/(8a^6) - 105/(16 a^8))
    return std::exp(-a2) / (2 * a * std::sqrt(kPi)) *
           (1 / (2 * a2) - 3 / (4 * a2 * a2) + 15 / (8 * a2 * a2 * a2) - 105 / (16 * a2 * a2 * a2 * a2));
  }
  return 0.5L * (std::exp(-a * a) / (a * std::sqrt(kPi)) - std::erfc(a));
}

inline long double lambda_ref(long double mu, long double sigma) {
  if (mu <= 0) return std::numeric_limits<long double>::infinity();
  if (sigma <= 0) return 0;
  return lambda_ref(mu / (std::sqrt(2.0L) * sigma));
}

}  // namespace svo::test
