// Object volumes (render/object_volumes.h): transmittance and stretches along rays through closed meshes, against
// closed forms -- a slab, overlapping boxes (coefficients add), origins inside, rays through edges and corners.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "render/object_volumes.h"

namespace sphrect::render {
namespace {

// An axis-aligned box as 8 vertices and 12 triangles counter-clockwise seen from outside (flipped: inside out).
struct BoxMesh {
    std::vector<float> vertices;
    std::vector<int32_t> triangles;
};

BoxMesh Box(Vec3f lo, Vec3f hi, bool flipped = false) {
    BoxMesh b;
    for (int i = 0; i < 8; ++i) {  // vertex index = x + 2 y + 4 z
        b.vertices.push_back(i & 1 ? hi.x : lo.x);
        b.vertices.push_back(i & 2 ? hi.y : lo.y);
        b.vertices.push_back(i & 4 ? hi.z : lo.z);
    }
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        const int tri[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
        for (const auto& t : tri) {
            b.triangles.push_back(t[0]);
            b.triangles.push_back(flipped ? t[2] : t[1]);
            b.triangles.push_back(flipped ? t[1] : t[2]);
        }
    }
    return b;
}

class ObjectVolumesTest : public ::testing::Test {
  protected:
    void SetUp() override { device_ = rtcNewDevice(nullptr); }
    void TearDown() override {
        volumes_.reset();
        rtcReleaseDevice(device_);
    }
    void Add(const BoxMesh& b, Spectrum sigma_s, Spectrum sigma_a, float g = 0) {
        if (!volumes_) volumes_ = std::make_unique<ObjectVolumes>();
        volumes_->Add(device_, "box", b.vertices.data(), b.vertices.size() / 3, b.triangles.data(),
                      b.triangles.size() / 3, sigma_s, sigma_a, g);
    }
    const ObjectVolumes& Committed() {
        volumes_->Commit(device_);
        return *volumes_;
    }
    RTCDevice device_ = nullptr;
    std::unique_ptr<ObjectVolumes> volumes_;
};

void ExpectSpectrumNear(const Spectrum& a, const Spectrum& b, float rel = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, rel * std::max(1.0f, std::abs(b.x)));
    EXPECT_NEAR(a.y, b.y, rel * std::max(1.0f, std::abs(b.y)));
    EXPECT_NEAR(a.z, b.z, rel * std::max(1.0f, std::abs(b.z)));
}

Spectrum Exp(const Spectrum& tau) { return {std::exp(-tau.x), std::exp(-tau.y), std::exp(-tau.z)}; }

TEST_F(ObjectVolumesTest, SlabTransmittanceIsExpOfSigmaTTimesTheLengthInside) {
    const Spectrum ss(0.2f, 0.4f, 0.1f), sa(0.3f, 0.0f, 1.0f);
    Add(Box({-1, -1, 1}, {1, 1, 2}), ss, sa);
    const ObjectVolumes& v = Committed();
    const Spectrum st = ss + sa;
    // Straight through (1 m), obliquely (1 / cos), stopping inside, starting inside, never reaching it, missing it.
    ExpectSpectrumNear(v.Transmittance({0, 0, 0}, {0, 0, 1}, 5), Exp(st * 1.0f));
    const Vec3f d = Normalize(Vec3f(0.3f, 0, 1));
    ExpectSpectrumNear(v.Transmittance({0, 0, 0}, d, kInf), Exp(st * (1 / d.z)));
    ExpectSpectrumNear(v.Transmittance({0, 0, 0}, {0, 0, 1}, 1.25f), Exp(st * 0.25f));
    ExpectSpectrumNear(v.Transmittance({0, 0, 1.5f}, {0, 0, 1}, kInf), Exp(st * 0.5f));
    ExpectSpectrumNear(v.Transmittance({0, 0, 1.5f}, {0, 0, -1}, 0.2f), Exp(st * 0.2f));
    ExpectSpectrumNear(v.Transmittance({0, 0, 0}, {0, 0, 1}, 0.9f), {1, 1, 1});
    ExpectSpectrumNear(v.Transmittance({0, 0, 0}, {0, 0, -1}, kInf), {1, 1, 1});
    ExpectSpectrumNear(v.Transmittance({5, 0, 0}, {0, 0, 1}, kInf), {1, 1, 1});
}

TEST_F(ObjectVolumesTest, OverlappingBoxesAddTheirCoefficients) {
    const Spectrum a(0.5f, 0.5f, 0.5f), b(0.25f, 1.0f, 2.0f);
    Add(Box({-1, -1, 0}, {1, 1, 2}), a, {});
    Add(Box({-1, -1, 1}, {1, 1, 3}), {}, b);
    const ObjectVolumes& v = Committed();
    // z in [0, 1): a; [1, 2): a + b; [2, 3): b.
    ExpectSpectrumNear(v.Transmittance({0, 0, -1}, {0, 0, 1}, kInf), Exp(a * 2.0f + b * 2.0f));
    ExpectSpectrumNear(v.Transmittance({0, 0, 1.5f}, {0, 0, 1}, 1.0f), Exp(a * 0.5f + b * 1.0f));
    VolumeSegments s;
    v.Segments({0, 0, -1}, {0, 0, 1}, s);
    ASSERT_EQ(s.count, 5);  // outside, a, a + b, b, outside
    const float bounds[6] = {0, 1, 2, 3, 4, kInf};
    for (int i = 0; i < 5; ++i) {
        EXPECT_NEAR(s.segment[i].t0, bounds[i], 1e-5f);
        if (std::isinf(bounds[i + 1]))
            EXPECT_EQ(s.segment[i].t1, kInf);
        else
            EXPECT_NEAR(s.segment[i].t1, bounds[i + 1], 1e-5f);
    }
    ExpectSpectrumNear(s.segment[2].coefficients.sigma_t, a + b);
    ExpectSpectrumNear(s.segment[2].coefficients.sigma_s, a);
    ExpectSpectrumNear(s.segment[3].coefficients.sigma_t, b);
    ExpectSpectrumNear(s.TransmittanceTo(2.5f), Exp(a * 1.5f + b * 0.5f));  // to z = 1.5
    ExpectSpectrumNear(s.TransmittanceTo(kInf), Exp(a * 2.0f + b * 2.0f));
}

TEST_F(ObjectVolumesTest, StretchesStartWhereTheCameraRayDoes) {
    // A camera inside a box with clip start 0.5: the medium begins at 0.5 (Cycles moves the ray's origin there), also
    // where the clip start is past the box's near face.
    const Spectrum st(1, 1, 1);
    Add(Box({-1, -1, -1}, {1, 1, 1}), st, {});
    const ObjectVolumes& v = Committed();
    VolumeSegments s;
    v.Segments({0, 0, 0}, {0, 0, 1}, s, 0.5f);
    ExpectSpectrumNear(s.TransmittanceTo(kInf), Exp(st * 0.5f));
    ExpectSpectrumNear(s.TransmittanceTo(0.75f), Exp(st * 0.25f));
    EXPECT_TRUE(IsBlack(s.segment[0].coefficients.sigma_t));
    v.Segments({0, 0, -1.5f}, {0, 0, 1}, s, 1.0f);  // starts inside, 0.5 past the near face
    ExpectSpectrumNear(s.TransmittanceTo(kInf), Exp(st * 1.5f));
}

TEST_F(ObjectVolumesTest, NestedBoxesAndAnOriginInsideBoth) {
    const Spectrum outer(0.1f, 0.1f, 0.1f), inner(1, 1, 1);
    Add(Box({-4, -4, -4}, {4, 4, 4}), outer, {});
    Add(Box({-1, -1, -1}, {1, 1, 1}), inner, {});
    const ObjectVolumes& v = Committed();
    ExpectSpectrumNear(v.Transmittance({0, 0, 0}, {1, 0, 0}, kInf), Exp(outer * 4.0f + inner * 1.0f));
    ExpectSpectrumNear(v.Transmittance({2, 0, 0}, {-1, 0, 0}, 4), Exp(outer * 4.0f + inner * 2.0f));
}

TEST_F(ObjectVolumesTest, RaysThroughEdgesAndCornersCountEachCrossingOnce) {
    // The diagonal of each face's two triangles, a box edge and a corner: a crossing reported by two or three
    // triangles still enters or leaves once.
    const Spectrum st(1, 1, 1);
    Add(Box({-1, -1, -1}, {1, 1, 1}), st, {});
    const ObjectVolumes& v = Committed();
    ExpectSpectrumNear(v.Transmittance({-3, -3, 0}, Normalize(Vec3f(1, 1, 0)), kInf), Exp(st * (2 * std::sqrt(2.0f))),
                       1e-4f);  // enters at an edge, leaves at the opposite one
    ExpectSpectrumNear(v.Transmittance({-3, -3, -3}, Normalize(Vec3f(1, 1, 1)), kInf), Exp(st * (2 * std::sqrt(3.0f))),
                       1e-4f);                                                               // corner to corner
    ExpectSpectrumNear(v.Transmittance({0.3f, 0.3f, -3}, {0, 0, 1}, kInf), Exp(st * 2.0f));  // a face's diagonal
}

TEST_F(ObjectVolumesTest, AnInsideOutMeshHoldsWhatLiesOutsideIt) {
    // Cycles reads the faces' orientation: a box with inward normals is entered at its back faces.
    Add(Box({-1, -1, -1}, {1, 1, 1}, /*flipped=*/true), {1, 1, 1}, {});
    const ObjectVolumes& v = Committed();
    VolumeSegments s;
    v.Segments({0, 0, -3}, {0, 0, 1}, s);
    ASSERT_GE(s.count, 2);
    EXPECT_FALSE(IsBlack(s.segment[0].coefficients.sigma_t));  // the camera's side counts as inside
}

TEST_F(ObjectVolumesTest, AddRefusesBadVolumes) {
    const BoxMesh b = Box({0, 0, 0}, {1, 1, 1});
    volumes_ = std::make_unique<ObjectVolumes>();
    EXPECT_THROW(volumes_->Add(device_, "neg", b.vertices.data(), 8, b.triangles.data(), 12, {-1, 0, 0}, {}, 0),
                 std::invalid_argument);
    EXPECT_THROW(volumes_->Add(device_, "g", b.vertices.data(), 8, b.triangles.data(), 12, {1, 1, 1}, {}, 1),
                 std::invalid_argument);
    EXPECT_THROW(volumes_->Add(device_, "empty", b.vertices.data(), 8, b.triangles.data(), 0, {1, 1, 1}, {}, 0),
                 std::invalid_argument);
    std::vector<int32_t> bad = b.triangles;
    bad[4] = 8;
    EXPECT_THROW(volumes_->Add(device_, "index", b.vertices.data(), 8, bad.data(), 12, {1, 1, 1}, {}, 0),
                 std::invalid_argument);
    for (int i = 0; i < kMaxObjectVolumes; ++i)
        volumes_->Add(device_, "ok", b.vertices.data(), 8, b.triangles.data(), 12, {1, 1, 1}, {}, 0);
    EXPECT_THROW(volumes_->Add(device_, "one more", b.vertices.data(), 8, b.triangles.data(), 12, {1, 1, 1}, {}, 0),
                 std::invalid_argument);
}

}  // namespace
}  // namespace sphrect::render
