// Carlson's symmetric elliptic integral of the third kind,
//   R_J(x, y, z, p) = 3/2 int_0^inf dt / ((t + p) sqrt((t + x)(t + y)(t + z))),
// by Carlson's duplication algorithm (B. C. Carlson, "Numerical computation of real or complex
// elliptic integrals", Numerical Algorithms 10, 1995, algorithm for R_J with R_C in closed form),
// for x, y, z >= 0 (at most one 0) and p > 0: all that spherical_ellipse.h needs.
//
// Why not Boost.Math's ellint_rj (which the tests use as the reference): this one skips Boost's
// argument checks, reordering and p < 0 branch, so it is faster and agrees with Boost to rounding over
// the map's argument range (tests/native/test_spherical_ellipse.cpp; the timings and the agreement:
// docs/ellipse_map.md section 5).  Every term of the algorithm is positive for these arguments
// except R_C's, which is computed without cancellation.
#pragma once

#include <algorithm>
#include <cmath>

namespace sphrect {

// R_C(1, 1 + t) for t > -1: atan(sqrt t) / sqrt t (t > 0), atanh(sqrt -t) / sqrt -t (t < 0), by its
// Taylor series near 0 (where both lose digits); the series' first omitted term is t^6 / 13 < 1e-19.
inline double CarlsonRC1(double t) {
    if (std::abs(t) < 1e-3)
        return 1 + t * (-1.0 / 3 + t * (1.0 / 5 + t * (-1.0 / 7 + t * (1.0 / 9 + t * (-1.0 / 11)))));
    if (t > 0) {
        const double s = std::sqrt(t);
        return std::atan(s) / s;
    }
    const double s = std::sqrt(-t);
    return std::atanh(s) / s;
}

inline double CarlsonRJ(double x, double y, double z, double p) {
    const double x0 = x, y0 = y, z0 = z, A0 = (x + y + z + 2 * p) / 5;
    const double delta = (p - x) * (p - y) * (p - z);
    // Duplicate until the arguments agree to (4 r)^(1/6) with r = 1e-16 (Carlson's bound on the
    // fifth-order series' error): 368 = (1 / (4e-16))^(1/6).
    const double Q = 368.0 * std::max({std::abs(A0 - x), std::abs(A0 - y), std::abs(A0 - z), std::abs(A0 - p)});
    double A = A0, sum = 0, fm = 1;  // fm = 4^-m
    for (int m = 0; m < 64; ++m) {
        const double sx = std::sqrt(x), sy = std::sqrt(y), sz = std::sqrt(z), sp = std::sqrt(p);
        const double lambda = sx * sy + sx * sz + sy * sz;
        const double d = (sp + sx) * (sp + sy) * (sp + sz);
        sum += fm * CarlsonRC1(fm * fm * fm * delta / (d * d)) / d;
        A = (A + lambda) / 4;
        x = (x + lambda) / 4;
        y = (y + lambda) / 4;
        z = (z + lambda) / 4;
        p = (p + lambda) / 4;
        fm /= 4;
        if (fm * Q < std::abs(A)) break;
    }
    const double X = fm * (A0 - x0) / A, Y = fm * (A0 - y0) / A, Z = fm * (A0 - z0) / A, P = -(X + Y + Z) / 2;
    const double E2 = X * Y + X * Z + Y * Z - 3 * P * P, E3 = X * Y * Z + 2 * E2 * P + 4 * P * P * P;
    const double E4 = (2 * X * Y * Z + E2 * P + 3 * P * P * P) * P, E5 = X * Y * Z * P * P;
    const double series = 1 - 3 * E2 / 14 + E3 / 6 + 9 * E2 * E2 / 88 - 3 * E4 / 22 - 9 * E2 * E3 / 52 + 3 * E5 / 26;
    return fm * series / (A * std::sqrt(A)) + 6 * sum;
}

}  // namespace sphrect
