// Node program evaluation (render/svm/evaluate.h): the cost per hit of a material input's compiled node graph.
//
//  BM_NodeProgram20  one EvalNodeProgram per iteration of a 20-node graph like a procedurally masked material's
//                    (Texture Coordinate, Separate XYZ, Mapping, 8 Math, 2 ColorRamps of 256 entries, 2 Mix,
//                    Map Range, Clamp, Invert, Combine XYZ, RGB to BW), at hits cycled from a table of 1024.
//  BM_NodeProgramConstant  the floor: a one-constant program.
//  BM_NodeProgramBump  a Bump node of a 3D Noise Texture (detail 2) of Generated: the Noise at the point and at
//                    P + dx, P + dy (the hits' shifted inputs set), then the bumped normal.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "render/svm/evaluate.h"
#include "render/svm/math_nodes.h"
#include "render/svm/mix_nodes.h"
#include "render/svm/vector_nodes.h"

namespace sphrect::render::svm {
namespace {

struct Builder {
    NodeProgram p;
    uint16_t Emit(NodeOp op, std::initializer_list<uint16_t> in, int outs = 1, int mode = 0, int flags = 0) {
        NodeInstruction i;
        i.op = op;
        i.mode = uint8_t(mode);
        i.flags = uint8_t(flags);
        int k = 0;
        for (uint16_t r : in) i.reg[k++] = r;
        const uint16_t first = uint16_t(p.num_registers);
        for (int o = 0; o < outs; ++o) i.reg[k++] = uint16_t(p.num_registers++);
        p.code.push_back(i);
        return first;
    }
    uint16_t Constant(float x, float y = 0, float z = 0) {
        NodeInstruction i;
        i.op = NodeOp::kConstant;
        i.value = {x, y, z};
        i.reg[0] = uint16_t(p.num_registers++);
        p.code.push_back(i);
        return i.reg[0];
    }
    uint16_t Ramp(uint16_t fac) {
        const int offset = int(p.data.size());
        for (int i = 0; i < 256; ++i)
            for (float c : {i / 255.0f, 0.5f * i / 255.0f, 1 - i / 255.0f, 1.0f}) p.data.push_back(c);
        const uint16_t out = Emit(NodeOp::kColorRamp, {fac}, 2, 0, 1);
        p.code.back().data = offset;
        p.code.back().size = 256;
        return out;
    }
};

NodeProgram TwentyNodeProgram() {
    Builder b;
    auto math = [&](MathOp op, uint16_t x, uint16_t y, uint16_t z) {
        return b.Emit(NodeOp::kMath, {x, y, z}, 1, int(op));
    };
    const uint16_t gen = b.Emit(NodeOp::kGlobal, {}, 1, int(ShaderGlobal::kGenerated));  // 1
    const uint16_t loc = b.Constant(0.1f, 0.2f, 0), rot = b.Constant(0, 0, 0.3f), scale = b.Constant(3, 3, 3);
    const uint16_t mapped = b.Emit(NodeOp::kMapping, {gen, loc, rot, scale}, 1, int(MappingType::kPoint));  // 2
    const uint16_t xyz = b.Emit(NodeOp::kSeparate, {mapped}, 3);                                            // 3
    const uint16_t half = b.Constant(0.5f), two = b.Constant(2), third = b.Constant(0.3f);
    const uint16_t s = math(MathOp::kSine, xyz, half, half);                                            // 4
    const uint16_t c = math(MathOp::kCosine, uint16_t(xyz + 1), half, half);                            // 5
    const uint16_t m = math(MathOp::kMultiplyAdd, s, c, half);                                          // 6
    const uint16_t p = math(MathOp::kPower, m, two, half);                                              // 7
    const uint16_t f = math(MathOp::kFract, uint16_t(xyz + 2), half, half);                             // 8
    const uint16_t w = math(MathOp::kWrap, p, two, third);                                              // 9
    const uint16_t sm = math(MathOp::kSmoothMin, w, f, third);                                          // 10
    const uint16_t mx = math(MathOp::kMaximum, sm, third, half);                                        // 11
    const uint16_t ramp1 = b.Ramp(mx);                                                                  // 12
    const uint16_t ramp2 = b.Ramp(f);                                                                   // 13
    const uint16_t mix1 = b.Emit(NodeOp::kMixColor, {p, ramp1, ramp2}, 1, int(MixBlend::kOverlay), 3);  // 14
    const uint16_t range =
        b.Emit(NodeOp::kMapRange, {s, half, two, third, two, two}, 1, int(MapRangeType::kSmootherstep), 1);  // 15
    const uint16_t clamp = b.Emit(NodeOp::kClamp, {range, third, two}, 1, int(ClampType::kRange));           // 16
    const uint16_t inv = b.Emit(NodeOp::kInvert, {clamp, mix1}, 1);                                          // 17
    const uint16_t comb = b.Emit(NodeOp::kCombine, {s, c, f}, 1, int(ColorModel::kHsv));                     // 18
    const uint16_t mix2 = b.Emit(NodeOp::kMixColor, {w, inv, comb}, 1, int(MixBlend::kMultiply), 1);         // 19
    const uint16_t bw = b.Emit(NodeOp::kConvert, {mix2}, 1, int(NodeConversion::kColorToFloat));             // 20
    b.p.output = b.Emit(NodeOp::kScale, {mix2, bw}, 1);
    CheckNodeProgram(b.p, 0);
    return b.p;
}

std::vector<ShaderGlobals> Hits() {
    std::mt19937 g(7);
    std::uniform_real_distribution<float> u(0, 1);
    std::vector<ShaderGlobals> hits(1024);
    for (ShaderGlobals& h : hits) {
        h.generated = h.uv = h.p = {u(g), u(g), u(g)};
        h.n = h.ng = h.incoming = {0, 0, 1};
        h.dP = 1e-3f;
        h.shifted = true;
        for (int k = 0; k < 2; ++k)
            h.shift[k].p = h.shift[k].uv = h.shift[k].generated = h.p + Vec3f(1e-3f, k * 1e-3f, 0);
    }
    return hits;
}

void Run(benchmark::State& state, const NodeProgram& program) {
    const std::vector<ShaderGlobals> hits = Hits();
    const std::vector<Image> images;
    size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(EvalNodeProgram(program, images, hits[i++ & 1023]));
    }
    state.counters["instructions"] = double(program.code.size());
}

void BM_NodeProgram20(benchmark::State& state) { Run(state, TwentyNodeProgram()); }
BENCHMARK(BM_NodeProgram20);

void BM_NodeProgramConstant(benchmark::State& state) {
    NodeProgram p;
    p.code.resize(1);
    p.code[0].reg[0] = 0;
    p.num_registers = 1;
    Run(state, p);
}
BENCHMARK(BM_NodeProgramConstant);

void BM_NodeProgramBump(benchmark::State& state) {
    Builder b;
    const uint16_t w = b.Constant(0), settings = b.Constant(5, 2, 0.5f), distortion = b.Constant(0);
    uint16_t height[3];
    for (int k = 0; k < 3; ++k) {
        const uint16_t gen = b.Emit(NodeOp::kGlobal, {}, 1, int(ShaderGlobal::kGenerated), k);
        height[k] = b.Emit(NodeOp::kNoiseTexture, {gen, w, settings, distortion}, 2, 2);
        b.p.code.back().reg[5] = kNoRegister;  // the colour unread
    }
    const uint16_t strength = b.Constant(1), distance = b.Constant(0.1f);
    const uint16_t normal = b.Emit(NodeOp::kGlobal, {}, 1, int(ShaderGlobal::kNormal));
    b.p.output = b.Emit(NodeOp::kBump, {height[0], height[1], height[2], strength, distance, normal});
    CheckNodeProgram(b.p, 0);
    Run(state, b.p);
}
BENCHMARK(BM_NodeProgramBump);

}  // namespace
}  // namespace sphrect::render::svm

BENCHMARK_MAIN();
