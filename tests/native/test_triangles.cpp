// Technique `triangles` (triangles.h): uniform in solid angle, pdf 1 / Omega, in the
// configurations where Arvo's closed form used to lose u (issue 12): thin triangles seen
// from near the light's plane beside a corner, and from thousands of sizes away; and where
// Van Oosterom & Strackee's solid angle of a triangle cancels (o on the diagonal near the plane).
#include <gtest/gtest.h>

#include "sampling_test_util.h"

using namespace sphrect;
using namespace sphrect_test;

namespace {

// Solid angle of the triangle of light corners i, j, k (0 = corner, 1 = +ex, 2 = +ex+ey,
// 3 = +ey) seen from o: Van Oosterom & Strackee in __float128 (its eps / h weak spot stays
// below 1e-20 for h >= 1e-12).
template <class T>
double ReferenceTriangleSolidAngle(const Vec3<T>& o, const RectLight<T>& L, int i, int j, int k) {
    Vec3q c[4];
    CornersQ(o, L, c);
    const Vec3q &a = c[i], &b = c[j], &cc = c[k];
    const Q la = LenQ(a), lb = LenQ(b), lc = LenQ(cc);
    const Q den = la * lb * lc + DotQ(a, b) * lc + DotQ(a, cc) * lb + DotQ(b, cc) * la;
    return double(2 * atan2q(fabsq(DotQ(a, CrossQ(b, cc))), den));
}

// Mean of 1 / pdf over a stratified grid (every pdf must be the same, 1 / Omega).
template <class T>
void ExpectUniform(const Vec3<T>& o, const RectLight<T>& L, double tolerance) {
    const double ref = ReferenceSolidAngle(o, L);
    const LightSampler<Technique::Triangles, T> s(o, Vec3<T>(0, 0, -1), L);
    ASSERT_TRUE(s.Valid());
    EXPECT_NEAR(double(s.r.tri[0].area + s.r.tri[1].area) / ref, 1, tolerance);
    for (float u : HardCaseUV())
        for (float v : HardCaseUV()) {
            const LightSample<T> ls = s.Sample({T(u), T(v)});
            EXPECT_NEAR(double(ls.pdf) * ref, 1, tolerance) << "u " << u << " v " << v;
            EXPECT_LE(DistanceToLight(ls.point, L), 1e-6);
        }
}

}  // namespace

// The configurations of issue 12: 1e-7 above the plane beside a corner, outside both edges'
// extents (both triangles' solid angles ~1e-8, below the old switch to area sampling, where
// its pdf was 1.6-4.4 times off 1/Omega), and 3000 sizes away (pdf 5e-4 off).
TEST(Triangles, UniformBesideACornerNearThePlaneAndFar) {
    const RectLight<float> Lf{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, true};
    const RectLight<double> Ld{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, true};
    for (const Vec3d o : {Vec3d(1.5, 1.2, 1e-7), Vec3d(-0.5, -0.3, 1e-7), Vec3d(1.1, 3, 1e-9), Vec3d(2, 2, 1e-7),
                          Vec3d(0.5 + 3000 / std::sqrt(1.13), 0.5 + 900 / std::sqrt(1.13), 600 / std::sqrt(1.13)),
                          Vec3d(1732.6, 1732.6, 1732.1)}) {
        SCOPED_TRACE("o = (" + std::to_string(o.x) + ", " + std::to_string(o.y) + ", " + std::to_string(o.z) + ")");
        ExpectUniform(Vec3f(o), Lf, 2e-7);  // float pdf rounding
        ExpectUniform(o, Ld, 1e-12);
    }
}

// o 1e-9 above the centre (on the diagonal) and above a corner: each triangle is seen edge-on
// with W ~ pi or pi/2, where Van Oosterom & Strackee on the whole triangle loses ~1e-7; the
// setup uses the solid angle by quadrant pieces there.
TEST(Triangles, TriangleSolidAnglesStableOnTheDiagonalNearThePlane) {
    const RectLight<double> L{{0, 0, 0}, {1, 0, 0}, {0, 1e-3, 0}, true};
    for (const Vec3d o : {Vec3d(0.5, 0.5e-3, 1e-9), Vec3d(0, 1e-3, 1e-9), Vec3d(0.25, 0.25e-3, 1e-12)}) {
        const TrianglesSetup<double> t = MakeTrianglesSetup(o, L);
        ASSERT_TRUE(t.valid);
        const double ref = ReferenceSolidAngle(o, L);
        EXPECT_NEAR((t.tri[0].area + t.tri[1].area) / ref, 1, 1e-13) << o.x << " " << o.y << " " << o.z;
        // Each on its own: the quadrant pieces of the rectangle's half against the half's
        // reference (__float128 Van Oosterom & Strackee, accurate to 1e-20 here).
        EXPECT_NEAR(t.tri[0].area / ReferenceTriangleSolidAngle(o, L, 0, 1, 2), 1, 1e-13);
        EXPECT_NEAR(t.tri[1].area / ReferenceTriangleSolidAngle(o, L, 0, 2, 3), 1, 1e-13);
    }
}
