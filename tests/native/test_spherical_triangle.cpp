// Arvo's spherical-triangle map (spherical_triangle.h), the building block of `triangles`.
#include <gtest/gtest.h>

#include <quadmath.h>

#include <random>

#include "core/spherical_triangle.h"

using namespace sphrect;

TEST(SphericalTriangle, SamplesStayInsideAndCoverUniformly) {
    // An octant triangle: area pi / 2; the fraction of samples with x > y must be 1/2 by symmetry.
    const SphericalTriangle t = MakeSphericalTriangle({1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    EXPECT_NEAR(t.area, M_PI / 2, 1e-14);
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> U(0, 1);
    int above = 0, n = 100000;
    for (int i = 0; i < n; ++i) {
        const Vec3d w = SampleSphericalTriangle(t, U(rng), U(rng));
        ASSERT_NEAR(Length(w), 1, 1e-12);
        ASSERT_GE(w.x, -1e-12);
        ASSERT_GE(w.y, -1e-12);
        ASSERT_GE(w.z, -1e-12);
        above += w.x > w.y;
    }
    // Binomial(1e5, 1/2): 4 standard deviations = 632.
    EXPECT_NEAR(above, n / 2, 632);
}

namespace {

using Q = __float128;
struct Vq {
    Q x, y, z;
};
Q DotQ(const Vq& a, const Vq& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vq CrossQ(const Vq& a, const Vq& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
Vq Sub(const Vq& a, const Vq& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vq Unit(const Vq& a) {
    const Q l = sqrtq(DotQ(a, a));
    return {a.x / l, a.y / l, a.z / l};
}
Q SolidAngleQ(const Vq& a, const Vq& b, const Vq& c) {
    const Q la = sqrtq(DotQ(a, a)), lb = sqrtq(DotQ(b, b)), lc = sqrtq(DotQ(c, c));
    return 2 * atan2q(fabsq(DotQ(a, CrossQ(b, c))), la * lb * lc + DotQ(a, b) * lc + DotQ(a, c) * lb + DotQ(b, c) * la);
}

// (u, v) of Arvo's parametrisation at the point p of the planar triangle abc, in __float128:
// C' where the great circle through B and p meets the arc AC, u = W(A B C') / W(A B C),
// v = (1 - cos|BP|) / (1 - cos|BC'|) = |B - P|^2 / |B - C'|^2 on the unit sphere.
void InverseQ(const Vq& a, const Vq& b, const Vq& c, const Vq& p, Q* u, Q* v) {
    const Vq A = Unit(a), B = Unit(b), C = Unit(c), P = Unit(p);
    Vq Cp = Unit(CrossQ(CrossQ(B, P), CrossQ(A, C)));
    if (DotQ(Cp, A) + DotQ(Cp, C) < 0) Cp = {-Cp.x, -Cp.y, -Cp.z};
    *u = SolidAngleQ(A, B, Cp) / SolidAngleQ(A, B, C);
    const Vq bp = Sub(P, B), bc = Sub(Cp, B);
    *v = DotQ(bp, bp) / DotQ(bc, bc);
}

}  // namespace

// Issue 12: Arvo's closed form (cos |AC'| from cos(uA - alpha) - cos alpha) lost u on thin
// triangles: the halves of a unit square 1e-7 above its plane beside a corner (u off by up to
// 0.17), 1e-9 above it (off by 1 and more), 3000 and 1e6 sizes away (off by 1e-4 and 1e-2).
// The stable map recovers (u, v) to 1e-14 there, against a __float128 inverse of its point.
TEST(SphericalTriangle, MapIsAccurateOnThinTrianglesNearThePlaneAndFar) {
    struct Case {
        double ox, oy, h;
    };
    const Case cases[] = {{1.5, 1.2, 1e-7}, {2, 2, 1e-7},     {-0.5, -0.3, 1e-9},
                          {1.5, 1.2, 0.1},  {0.3, 0.6, 3000}, {1732.6, 1732.6, 1732.1},
                          {0.3, 0.6, 1e6}};
    const double g[] = {0, 1e-7, 0.01, 0.25, 0.5, 0.75, 0.99, 1 - 1e-7, 1};
    for (const Case& k : cases) {
        // Corners of the unit square in z = 0 relative to o: the halves (00, 10, 11), (00, 11, 01).
        const Vec3d c00(-k.ox, -k.oy, -k.h), c10(1 - k.ox, -k.oy, -k.h), c11(1 - k.ox, 1 - k.oy, -k.h),
            c01(-k.ox, 1 - k.oy, -k.h);
        const Vec3d tris[2][3] = {{c00, c10, c11}, {c00, c11, c01}};
        for (const auto& tri : tris) {
            const SphericalTriangle t = MakeSphericalTriangle(tri[0], tri[1], tri[2]);
            auto q = [](const Vec3d& v) { return Vq{v.x, v.y, v.z}; };
            const Vq a = q(tri[0]), b = q(tri[1]), c = q(tri[2]), eb = Sub(b, a), ec = Sub(c, a);
            EXPECT_NEAR(t.area / double(SolidAngleQ(a, b, c)), 1, 1e-14);
            for (double u : g)
                for (double v : g) {
                    if (v < 1e-3) continue;  // P near B: the inverse's C' is ill-determined there
                    const Point2<double> w = SampleSphericalTriangleBarycentrics(t, u, v);
                    const Vq p{a.x + Q(w.u) * eb.x + Q(w.v) * ec.x, a.y + Q(w.u) * eb.y + Q(w.v) * ec.y,
                               a.z + Q(w.u) * eb.z + Q(w.v) * ec.z};
                    Q uu, vv;
                    InverseQ(a, b, c, p, &uu, &vv);
                    EXPECT_NEAR(double(uu), u, 1e-14) << "o (" << k.ox << ", " << k.oy << ", " << k.h << ") v " << v;
                    if (u > 0) {
                        EXPECT_NEAR(double(vv), v, 1e-14)
                            << "o (" << k.ox << ", " << k.oy << ", " << k.h << ") u " << u;
                    }
                    // The unit direction is the point's.
                    const Vec3d d = SampleSphericalTriangle(t, u, v);
                    const Vq P = Unit(p);
                    EXPECT_NEAR(d.x, double(P.x), 1e-15);
                    EXPECT_NEAR(d.y, double(P.y), 1e-15);
                    EXPECT_NEAR(d.z, double(P.z), 1e-15);
                }
        }
    }
}
