// Solid angles (solid_angle.h) against the __float128 reference over the hard-case suite,
// through RectangleSolidAngle, the function the bindings expose as sphrect.solid_angle.
#include <gtest/gtest.h>

#include "sampling_test_util.h"

using namespace sphrect;
using namespace sphrect_test;

// The solid angle the bindings expose, against the reference, over the suite.
TEST(SolidAngle, MatchesTheReferenceOverTheHardCases) {
    for (const HardCase& hc : HardCaseSuite()) {
        const double ref = ReferenceSolidAngle(hc.origin, hc.light);
        const double w = RectangleSolidAngle(hc.origin, hc.light);
        // The rotated light's float edges are orthogonal only to ~1e-7 (the reference
        // integrates that parallelogram, the map a rectangle); the others are exact.
        const double tol = hc.name.rfind("rotated", 0) == 0 ? 1e-6 : 1e-13;
        if (ref > 0)
            EXPECT_LE(std::abs(w - ref) / ref, tol) << hc.name;
        else
            EXPECT_EQ(w, 0) << hc.name;
    }
}
