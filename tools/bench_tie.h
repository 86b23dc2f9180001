// The speed-up claims of the bench summaries (svo bench speed-error): what
// one method's time is against a curve of another's (supersampled ray
// marching at 1 to 64 rays per pixel) at equal error, and when the errors
// are too close to tell apart, a tie instead of a claim.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace svo::tools::bench {

// The noise of an error figure (relMSE against a supersampled ground
// truth), relative: two figures that differ by less than this fraction of
// the larger cannot be told apart. The ground truth's own Monte Carlo noise
// adds the same floor to every method's relMSE, and a few percent of
// relMSE is what a change of the reference's seed or of the octree's
// resolution by one step moves; 5% is the default of --tie-tolerance.
inline constexpr double kErrorTieTolerance = 0.05;

// True when errors `a` and `b` (not negative) differ by at most
// `tolerance` of the larger (two zeros tie).
inline bool errors_tie(double a, double b, double tolerance = kErrorTieTolerance) {
  const double larger = std::max(std::abs(a), std::abs(b));
  return std::abs(a - b) <= tolerance * larger;
}

// One point of a curve of cost against error.
struct CostErrorPoint {
  std::string name;  // "raymarch-16"
  double ms = 0;
  double error = 0;
};

// What can be said of a method (ours_ms, ours_error) against a curve.
struct EqualErrorClaim {
  enum class Kind {
    Speedup,  // the curve reaches our error between two of its points: factor = its time there / ours
    AtLeast,  // below the curve's smallest error (beyond the noise): factor = its slowest point's time / ours
    Tie,      // our error ties some of the curve's points: no speed-up claimed; `against` is the cheapest of them
    Worse,    // above the curve's largest error (beyond the noise)
  };
  Kind kind = Kind::Worse;
  double factor = 0;    // Speedup, AtLeast: curve time / ours; Tie: the tied point's time / ours
  std::string against;  // Tie, AtLeast: the curve point compared with
  double against_error = 0;
};

// The claim of a method against `curve` (any order) at equal error: a tie
// when its error is within `tolerance` of any curve point's, else a
// speed-up interpolated on the log-log curve between the two points that
// bracket its error, else a lower bound below the curve or "worse" above it.
inline EqualErrorClaim claim_at_equal_error(double ours_ms, double ours_error, std::vector<CostErrorPoint> curve,
                                            double tolerance = kErrorTieTolerance) {
  EqualErrorClaim c;
  if (curve.empty() || !(ours_ms > 0)) return c;
  std::sort(curve.begin(), curve.end(), [](const auto& a, const auto& b) { return a.ms < b.ms; });
  for (const auto& p : curve) {
    if (errors_tie(ours_error, p.error, tolerance)) {
      c.kind = EqualErrorClaim::Kind::Tie;
      c.factor = p.ms / ours_ms;
      c.against = p.name;
      c.against_error = p.error;
      return c;
    }
  }
  for (size_t i = 0; i + 1 < curve.size(); ++i) {
    const double e0 = curve[i].error, e1 = curve[i + 1].error;
    if ((e0 - ours_error) * (e1 - ours_error) > 0 || e0 == e1 || e0 <= 0 || e1 <= 0 || ours_error <= 0) continue;
    const double f = (std::log(ours_error) - std::log(e0)) / (std::log(e1) - std::log(e0));
    const double ms = std::exp(std::log(curve[i].ms) + f * (std::log(curve[i + 1].ms) - std::log(curve[i].ms)));
    c.kind = EqualErrorClaim::Kind::Speedup;
    c.factor = ms / ours_ms;
    return c;
  }
  const auto best =
      std::min_element(curve.begin(), curve.end(), [](const auto& a, const auto& b) { return a.error < b.error; });
  if (ours_error < best->error) {
    c.kind = EqualErrorClaim::Kind::AtLeast;
    // The cheapest point at the curve's best error: a lower bound of the time
    // the curve needs to reach ours.
    c.factor = best->ms / ours_ms;
    c.against = best->name;
    c.against_error = best->error;
  }
  return c;
}

}  // namespace svo::tools::bench
