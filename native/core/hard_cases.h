// The hard-case suite: the configurations (light, shading point, normal) on which the
// techniques' robustness is checked (tests/native/test_hard_cases.cpp, test_rectangle.cpp) and
// measured (the study's accuracy table, python/sphrect/study/sampler_table.py, through
// sphrect._native._study_hard_cases), and the (u, v) values they are sampled at.  One list for
// both, so the study reports on exactly what the tests check.
//
// All cases keep the light near the world origin and move the shading point: with float
// world coordinates, a light 1e6 sizes from the world origin cannot even be represented to
// 1e-5 of its size, so "far" is only meaningful relative to o.  Coordinates are built in
// double and rounded to float; references use the rounded values, so every case is exactly
// the configuration the code sees.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "rect_light.h"

namespace sphrect {

struct HardCase {
    std::string name;
    RectLight<float> light;  // near the world origin (see above)
    Vec3f origin;
    Vec3f normal;  // a shading normal facing the light (for rectangle_cosine)
    double size;   // the light's larger edge
};

// Distances (in light sizes) of the shading point, and heights (in sizes) above the plane.
inline constexpr double kHardCaseDistances[] = {1e-6, 1e-3, 1.0, 1e2, 1e3, 1e4, 1e6};
inline constexpr double kHardCaseHeights[] = {1e-9, 1e-7, 1e-6, 1e-5, 1e-3, 1e-1};

inline std::string HardCaseNumber(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

inline std::vector<HardCase> HardCaseSuite() {
    std::vector<HardCase> cases;
    struct LightDef {
        std::string name;
        Vec3d center, ex, ey;
    };
    const double s2 = std::sqrt(0.5);
    // A rotated light: edges along (1,1,0)/sqrt2 and (-1,1,1)/sqrt3 scaled (orthogonal to rounding).
    const Vec3d rx = Vec3d(s2, s2, 0), ry = Normalize(Vec3d(-1, 1, 1));
    const std::vector<LightDef> lights = {
        {"unit", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
        {"rotated", {0.3, -0.2, 0.7}, rx * 0.8, ry * 1.3},
        {"aspect1e3", {0, 0, 0}, {1, 0, 0}, {0, 1e-3, 0}},
        {"aspect1e5", {0, 0, 0}, {0, 1e-5, 0}, {1, 0, 0}},
        {"small", {0.25, 0.5, -0.125}, {1e-3, 0, 0}, {0, 0, 2e-3}},
    };
    for (const LightDef& ld : lights) {
        const Vec3d n = Normalize(Cross(ld.ex, ld.ey));
        const double lx = Length(ld.ex), ly = Length(ld.ey), size = std::max(lx, ly);
        const RectLight<float> L{Vec3f(ld.center - ld.ex * 0.5 - ld.ey * 0.5), Vec3f(ld.ex), Vec3f(ld.ey), true};
        const Vec3d xh = ld.ex / lx, yh = ld.ey / ly;
        auto push = [&](const std::string& what, const Vec3d& o) {
            cases.push_back({ld.name + "/" + what, L, Vec3f(o), Vec3f(Normalize(ld.center - o)), size});
        };
        // (a, b): position in light fractions, z: height in sizes (negative: the other side).
        auto add = [&](const std::string& what, double a, double b, double z) {
            push(what, ld.center + ld.ex * (a - 0.5) + ld.ey * (b - 0.5) + n * (z * size));
        };
        for (double d : kHardCaseDistances) {
            const std::string ds = HardCaseNumber(d);
            add("above_center_d" + ds, 0.5, 0.5, d);
            add("below_center_d" + ds, 0.5, 0.5, -d);
            push("diagonal_d" + ds, ld.center + (xh + yh + n) * (d * size / std::sqrt(3.0)));  // d sizes away
            add("side_d" + ds, 0.5 + d * size / lx, 0.5, 1e-3);
        }
        for (double hgt : kHardCaseHeights) {
            const std::string hs = HardCaseNumber(hgt);
            add("interior_h" + hs, 0.3, 0.6, hgt);
            add("center_h" + hs, 0.5, 0.5, hgt);
            add("edge_h" + hs, 1.0, 0.4, hgt);
            add("corner_h" + hs, 0.0, 1.0, hgt);
            add("beside_h" + hs, 0.5 + 2 * size / lx, 0.5, hgt);
            add("beside_diag_h" + hs, 1 + size / lx, 1 + size / ly, hgt);
            add("near_edge_h" + hs, 1 + 1e-4, 0.5, hgt);
            // Beside a corner, outside both edges' extents and off the diagonal's line (issue 12:
            // Arvo's closed form lost u on these thin triangles).
            add("beside_corner_h" + hs, 1 + 0.5 * size / lx, 1 + 0.2 * size / ly, hgt);
            add("beside_far_corner_h" + hs, -0.3 * size / lx, -0.5 * size / ly, hgt);
        }
        // Far in a direction of no symmetry of the light (issue 12: thin far triangles).
        const Vec3d oblique = Normalize(xh + yh * 0.3 + n * 0.2);
        for (double d : kHardCaseDistances) push("oblique_d" + HardCaseNumber(d), ld.center + oblique * (d * size));
    }
    // A long light (1e5 x 1) seen from 1 above its centre: 1e-5 of its size, but 1 of its width.
    const RectLight<float> long_light{{-5e4f, -0.5f, 0}, {1e5f, 0, 0}, {0, 1, 0}, true};
    cases.push_back({"long1e5/above_center_h1", long_light, {0, 0, 1}, {0, 0, -1}, 1e5});
    return cases;
}

// (u, v) values of the suite: 0, the largest float below 1, 1, and interior ones; the suite
// samples their 9 x 9 grid.
inline std::vector<float> HardCaseUV() {
    return {0.f, 1e-7f, 0.1f, 0.25f, 0.5f, 0.75f, 0.9f, std::nextafter(1.f, 0.f), 1.f};
}

}  // namespace sphrect
