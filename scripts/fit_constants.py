#!/usr/bin/env python3
"""Derives the polynomial coefficients of shaders/common/{erf,trig}.glsl.

Needs mpmath (Debian: python3-mpmath); not part of the build. Run it to check
or refit the constants; it prints them in the order the GLSL Horner loops use.

- |x| < 0.84375: erf(x) = x * P(x^2), P the Maclaurin series of erf(x)/x to
  z^10 (truncation error below 5e-10 on the range); the shader sums it as
  x + x (P - 1), with c0 - 1 printed last.
- x >= 0.84375:  erfc(x) = t * exp(-x^2 + Q(t)), t = 1 / (1 + x/2), Q a
  Chebyshev fit of degree 10 of log(erfcx(x) / t) over t in [0, 1/(1+0.421875)]
  (the form of Numerical Recipes' erfcc, refitted on the narrower range).
- atan(t) = t * A(t^2) for t in [0, 1], A a Chebyshev fit of degree 9 of
  atan(sqrt(z)) / sqrt(z) over z in [0, 1] (svo_atan2 reduces to that range).
"""
import mpmath as mp

mp.mp.dps = 50
X0 = mp.mpf("0.84375")
P = mp.mpf("0.5")


def q_target(t):
    if t == 0:
        return mp.log(1 / (2 * mp.sqrt(mp.pi)))  # erfcx(x) ~ 1/(x sqrt(pi)), t ~ 2/x
    x = (1 / t - 1) / P
    return mp.log(mp.erfc(x) * mp.exp(x * x) / t)


def main():
    small = [2 / mp.sqrt(mp.pi) * (-1) ** n / (mp.factorial(n) * (2 * n + 1)) for n in range(11)]
    print("erf small, c0..c10 (z = x^2):")
    for c in small:
        print("  %.9ef" % float(c))
    print("  c0 - 1 = %.9ef" % float(small[0] - 1))
    t0 = 1 / (1 + P * X0)
    coeffs, err = mp.chebyfit(q_target, [0, t0], 11, error=True)
    print("erfc large, Q(t) highest degree first, max abs error %.2e:" % float(err))
    for c in coeffs:
        print("  %.9ef" % float(c))
    atan_ratio = lambda z: mp.atan(mp.sqrt(z)) / mp.sqrt(z) if z > 0 else mp.mpf(1)
    coeffs, err = mp.chebyfit(atan_ratio, [0, 1], 10, error=True)
    print("atan, A(z) highest degree first, max abs error %.2e:" % float(err))
    for c in coeffs:
        print("  %.9ef" % float(c))


if __name__ == "__main__":
    main()
