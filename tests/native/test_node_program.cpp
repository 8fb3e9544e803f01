// Node programs (render/svm): the interpreter against the nodes' formulas, and CheckNodeProgram's refusals.  The
// values against Cycles 3.4 itself: tests/blender/test_node_programs.py.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "render/integrator/transparency.h"  // OcclusionRayContext
#include "render/svm/evaluate.h"
#include "render/svm/math_nodes.h"
#include "render/svm/mix_nodes.h"
#include "render/svm/vector_nodes.h"

namespace sphrect::render::svm {
namespace {

NodeInstruction Op(NodeOp op, std::initializer_list<uint16_t> regs, int mode = 0, int flags = 0) {
    NodeInstruction i;
    i.op = op;
    i.mode = uint8_t(mode);
    i.flags = uint8_t(flags);
    int k = 0;
    for (uint16_t r : regs) i.reg[k++] = r;
    return i;
}

NodeInstruction Constant(uint16_t reg, float x, float y = 0, float z = 0) {
    NodeInstruction i = Op(NodeOp::kConstant, {reg});
    i.value = {x, y, z};
    return i;
}

Vec3f Evaluate(const NodeProgram& p, const ShaderGlobals& sg = {}) {
    CheckNodeProgram(p, 0);
    return EvalNodeProgram(p, {}, sg);
}

TEST(NodeProgram, MathOfTheUvWithClamp) {
    NodeProgram p;
    p.code = {Op(NodeOp::kGlobal, {0}, int(ShaderGlobal::kUv)), Op(NodeOp::kSeparate, {0, 1, 2, kNoRegister}),
              Constant(3, 2.0f), Op(NodeOp::kMath, {1, 3, 3, 4}, int(MathOp::kPower)),
              Op(NodeOp::kMath, {4, 2, 3, 5}, int(MathOp::kAdd), 1)};
    p.num_registers = 6;
    p.output = 4;
    ShaderGlobals sg;
    sg.uv = {0.3f, 0.9f, 0};
    EXPECT_FLOAT_EQ(Evaluate(p, sg).x, 0.09f);
    p.output = 5;  // 0.09 + 0.9 clamped: 0.99; then past 1
    EXPECT_FLOAT_EQ(Evaluate(p, sg).x, 0.99f);
    sg.uv = {0.5f, 0.9f, 0};
    EXPECT_FLOAT_EQ(Evaluate(p, sg).x, 1.0f);
}

TEST(NodeProgram, SafeMathAsCycles) {
    EXPECT_EQ(EvalMath(MathOp::kDivide, 1, 0, 0), 0.0f);
    EXPECT_EQ(EvalMath(MathOp::kPower, -2, 0.5f, 0), 0.0f);
    EXPECT_EQ(EvalMath(MathOp::kPower, -2, 3, 0), -8.0f);
    EXPECT_EQ(EvalMath(MathOp::kLogarithm, -1, 2, 0), 0.0f);
    EXPECT_FLOAT_EQ(EvalMath(MathOp::kWrap, 5.5f, 2, 0), 1.5f);
    EXPECT_FLOAT_EQ(EvalMath(MathOp::kPingpong, 2.5f, 2, 0), 1.5f);
    EXPECT_EQ(EvalMath(MathOp::kSign, 0, 0, 0), 0.0f);
    EXPECT_EQ(EvalMath(MathOp::kCompare, 1, 1.05f, 0.1f), 1.0f);
}

TEST(NodeProgram, ColorModelsRoundTrip) {
    for (const Vec3f c : {Vec3f(0.2f, 0.5f, 0.9f), Vec3f(0.9f, 0.1f, 0.4f), Vec3f(0.3f, 0.3f, 0.3f)}) {
        for (ColorModel m : {ColorModel::kHsv, ColorModel::kHsl}) {
            const Vec3f back = FromColorModel(m, ToColorModel(m, c));
            EXPECT_NEAR(back.x, c.x, 1e-6f);
            EXPECT_NEAR(back.y, c.y, 1e-6f);
            EXPECT_NEAR(back.z, c.z, 1e-6f);
        }
    }
    // Mix at factor 0 is the first colour for the blends that interpolate.
    const Vec3f a(0.2f, 0.5f, 0.9f), b(0.7f, 0.1f, 0.3f);
    for (MixBlend m : {MixBlend::kMix, MixBlend::kAdd, MixBlend::kMultiply, MixBlend::kDifference, MixBlend::kHue,
                       MixBlend::kColor, MixBlend::kSoftLight, MixBlend::kLinearLight})
        EXPECT_NEAR(EvalMixColor(m, 0, a, b).y, a.y, 1e-6f) << kMixBlendNames[int(m)];
    EXPECT_NEAR(EvalMixColor(MixBlend::kScreen, 1, a, b).x, 1 - (1 - a.x) * (1 - b.x), 1e-6f);
}

TEST(NodeProgram, RampTableAndMapping) {
    NodeProgram p;
    p.data = {0, 0, 0, 1, 1, 0.5f, 0.25f, 0};  // two RGBA rows
    NodeInstruction ramp = Op(NodeOp::kColorRamp, {0, 1, 2}, 0, 1);
    ramp.size = 2;
    p.code = {Constant(0, 0.25f), ramp};
    p.num_registers = 3;
    p.output = 1;
    EXPECT_FLOAT_EQ(Evaluate(p).y, 0.125f);
    p.output = 2;
    EXPECT_FLOAT_EQ(Evaluate(p).x, 0.75f);
    p.code[1].flags = 0;  // Constant interpolation: the lower entry
    EXPECT_FLOAT_EQ(Evaluate(p).x, 1.0f);
    // Mapping: Texture is the inverse of Point.
    const Vec3f v(0.3f, -0.2f, 0.7f), loc(0.1f, 0.2f, 0.3f), rot(0.4f, -0.7f, 1.1f), scale(1.5f, 0.5f, 2.0f);
    const Vec3f back =
        EvalMapping(MappingType::kTexture, EvalMapping(MappingType::kPoint, v, loc, rot, scale), loc, rot, scale);
    EXPECT_NEAR(back.x, v.x, 1e-6f);
    EXPECT_NEAR(back.y, v.y, 1e-6f);
    EXPECT_NEAR(back.z, v.z, 1e-6f);
}

TEST(NodeProgram, BadProgramsAreRefused) {
    NodeProgram p;
    p.code = {Op(NodeOp::kMath, {0, 0, 0, 1})};  // reads register 0 before anything writes it
    p.num_registers = 2;
    p.output = 1;
    EXPECT_THROW(CheckNodeProgram(p, 0), std::invalid_argument);
    p.code = {Constant(0, 1), Op(NodeOp::kMath, {0, 0, 0, 1}, int(MathOp::kCount))};
    EXPECT_THROW(CheckNodeProgram(p, 0), std::invalid_argument);
    p.code = {Constant(0, 1), Op(NodeOp::kImage, {0, 1, kNoRegister})};
    EXPECT_THROW(CheckNodeProgram(p, 0), std::invalid_argument);  // no image 0
    EXPECT_NO_THROW(CheckNodeProgram(p, 1));
    p.output = 5;
    EXPECT_THROW(CheckNodeProgram(p, 1), std::invalid_argument);
}

// The Light Path node's view of a surface an occlusion ray crosses (transparency.h): a light sample's shadow ray is
// PATH_RAY_SHADOW alone with Ray Depth + 1; a BSDF or phase ray going on to its emitter keeps its lobe's flags and
// counters (path_state_next); both count the surfaces crossed before.
TEST(NodeProgram, LightPathContextsOfOcclusionRays) {
    using render::OcclusionRayContext;
    auto expect = [](const RayContext& c, int flags, int depth, int diffuse, int glossy, int transparent,
                     int transmission) {
        EXPECT_EQ(c.flags, flags);
        EXPECT_EQ(c.depth, depth);
        EXPECT_EQ(c.diffuse_depth, diffuse);
        EXPECT_EQ(c.glossy_depth, glossy);
        EXPECT_EQ(c.transparent_depth, transparent);
        EXPECT_EQ(c.transmission_depth, transmission);
    };
    expect(OcclusionRayContext(render::kRayShadow, 2), kRayIsShadow, 1, 0, 0, 2, 0);
    expect(OcclusionRayContext(render::kRayDiffuse, 1), kRayIsDiffuse | kRayIsReflection, 1, 1, 0, 1, 0);
    expect(OcclusionRayContext(render::kRayGlossy, 0), kRayIsGlossy | kRayIsReflection, 1, 0, 1, 0, 0);
    expect(OcclusionRayContext(render::kRayDiffuse | render::kRayTransmission, 0), kRayIsDiffuse | kRayIsTransmission,
           1, 0, 0, 0, 1);
    expect(OcclusionRayContext(render::kRayVolumeScatter, 3), kRayIsVolumeScatter, 1, 0, 0, 3, 0);
}

// Only programs reading a ray kind or depth mark a scene (RenderScene::light_path_programs): Ray Length does not.
TEST(NodeProgram, ReadsRayContextOnlyForLightPathOutputs) {
    NodeProgram p;
    p.code = {Op(NodeOp::kGlobal, {0}, int(ShaderGlobal::kRayLength))};
    p.num_registers = 1;
    EXPECT_FALSE(p.ReadsRayContext());
    p.code[0].mode = uint8_t(ShaderGlobal::kIsCameraRay);
    EXPECT_TRUE(p.ReadsRayContext());
    ShaderGlobals sg;
    EXPECT_EQ(Evaluate(p, sg).x, 1.0f);  // the default context: a camera ray's first hit
    sg.ray = ShadowRayContext(0);
    EXPECT_EQ(Evaluate(p, sg).x, 0.0f);
}

}  // namespace
}  // namespace sphrect::render::svm
