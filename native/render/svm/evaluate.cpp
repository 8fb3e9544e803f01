// The node program interpreter: one case per instruction, each calling its node family's pure function.
#include "evaluate.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "math_nodes.h"
#include "mix_nodes.h"
#include "vector_nodes.h"

namespace sphrect::render::svm {

namespace {

Vec3f Global(ShaderGlobal g, const ShaderGlobals& sg) {
    switch (g) {
        case ShaderGlobal::kPosition: return sg.p;
        case ShaderGlobal::kNormal: return sg.n;
        case ShaderGlobal::kTrueNormal: return sg.ng;
        case ShaderGlobal::kIncoming: return sg.incoming;
        case ShaderGlobal::kUv: return sg.uv;
        case ShaderGlobal::kGenerated: return sg.generated;
        case ShaderGlobal::kObject: return sg.object;
        case ShaderGlobal::kObjectNormal: return sg.object_normal;
        case ShaderGlobal::kReflection: return sg.n * (2.0f * Dot(sg.n, sg.incoming)) - sg.incoming;
        case ShaderGlobal::kBackfacing: return Vec3f(sg.backfacing ? 1.0f : 0.0f, 0, 0);
        case ShaderGlobal::kRayLength: return Vec3f(sg.ray_length, 0, 0);
        case ShaderGlobal::kCount: break;
    }
    return {};
}

Vec3f Convert(NodeConversion c, const Vec3f& v) {
    switch (c) {
        case NodeConversion::kColorToFloat: return Vec3f(Luminance(v), 0, 0);
        case NodeConversion::kVectorToFloat: return Vec3f((v.x + v.y + v.z) * (1.0f / 3.0f), 0, 0);
        case NodeConversion::kFloatToVector: return Vec3f(v.x, v.x, v.x);
        case NodeConversion::kCount: break;
    }
    return {};
}

// Cycles' rgb_ramp_lookup without extrapolation: the table of `size` RGBA rows at f in [0, 1].
void RampLookup(const float* rows, int size, float f, bool interpolate, float out[4]) {
    f = Saturate(f) * float(size - 1);
    const int i = std::clamp(int(f), 0, size - 1);
    const float t = f - float(i);
    for (int c = 0; c < 4; ++c) out[c] = rows[4 * i + c];
    if (interpolate && t > 0.0f)
        for (int c = 0; c < 4; ++c) out[c] = (1.0f - t) * out[c] + t * rows[4 * (i + 1) + c];
}

}  // namespace

Vec3f EvalNodeProgram(const NodeProgram& program, const std::vector<Image>& images, const ShaderGlobals& sg) {
    // Left uninitialised (CheckNodeProgram: every register is written before it is read): a zeroed file of Vec3fs
    // cost 3 KB of stores per evaluation.
    float file[3 * kMaxNodeRegisters];
    auto put = [&](uint16_t reg, const Vec3f& v) {
        if (reg == kNoRegister) return;
        float* f = file + 3 * size_t(reg);
        f[0] = v.x, f[1] = v.y, f[2] = v.z;
    };
    auto r = [&](uint16_t reg) {
        const float* f = file + 3 * size_t(reg);
        return Vec3f(f[0], f[1], f[2]);
    };
    auto scalar = [&](float v) { return Vec3f(v, 0, 0); };
    for (const NodeInstruction& in : program.code) {
        const uint16_t* a = in.reg;
        switch (in.op) {
            case NodeOp::kConstant: put(a[0], in.value); break;
            case NodeOp::kGlobal: put(a[0], Global(ShaderGlobal(in.mode), sg)); break;
            case NodeOp::kConvert: put(a[1], Convert(NodeConversion(in.mode), r(a[0]))); break;
            case NodeOp::kMath: {
                float v = EvalMath(MathOp(in.mode), r(a[0]).x, r(a[1]).x, r(a[2]).x);
                if (in.flags & 1) v = Saturate(v);
                put(a[3], scalar(v));
                break;
            }
            case NodeOp::kMixColor: {
                const float t = (in.flags & 1) ? Saturate(r(a[0]).x) : r(a[0]).x;
                const Vec3f c = EvalMixColor(MixBlend(in.mode), t, r(a[1]), r(a[2]));
                put(a[3], (in.flags & 2) ? Saturate3(c) : c);
                break;
            }
            case NodeOp::kMixFloat: {
                const float t = (in.flags & 1) ? Saturate(r(a[0]).x) : r(a[0]).x;
                put(a[3], scalar(r(a[1]).x * (1.0f - t) + r(a[2]).x * t));
                break;
            }
            case NodeOp::kMixVector: {
                Vec3f t = in.mode == 1 ? r(a[0]) : Vec3f(r(a[0]).x, r(a[0]).x, r(a[0]).x);
                if (in.flags & 1) t = Saturate3(t);
                put(a[3], r(a[1]) * (Vec3f(1, 1, 1) - t) + r(a[2]) * t);
                break;
            }
            case NodeOp::kColorRamp: {
                float c[4];
                RampLookup(program.data.data() + in.data, in.size, r(a[0]).x, in.flags & 1, c);
                put(a[1], Vec3f(c[0], c[1], c[2]));
                put(a[2], scalar(c[3]));
                break;
            }
            case NodeOp::kInvert: put(a[2], EvalInvert(r(a[0]).x, r(a[1]))); break;
            case NodeOp::kClamp:
                put(a[3], scalar(EvalClamp(ClampType(in.mode), r(a[0]).x, r(a[1]).x, r(a[2]).x)));
                break;
            case NodeOp::kMapRange:
                put(a[6], scalar(EvalMapRange(MapRangeType(in.mode), in.flags & 1, r(a[0]).x, r(a[1]).x, r(a[2]).x,
                                              r(a[3]).x, r(a[4]).x, r(a[5]).x)));
                break;
            case NodeOp::kSeparate: {
                const Vec3f c = ToColorModel(ColorModel(in.mode), r(a[0]));
                put(a[1], scalar(c.x));
                put(a[2], scalar(c.y));
                put(a[3], scalar(c.z));
                break;
            }
            case NodeOp::kCombine:
                put(a[3], FromColorModel(ColorModel(in.mode), Vec3f(r(a[0]).x, r(a[1]).x, r(a[2]).x)));
                break;
            case NodeOp::kMapping:
                put(a[4], EvalMapping(MappingType(in.mode), r(a[0]), r(a[1]), r(a[2]), r(a[3])));
                break;
            case NodeOp::kImage: {
                const Vec3f v = r(a[0]);
                const Rgba c = LookupImage(images[size_t(in.data)], v.x, v.y, TextureInterpolation(in.mode),
                                           TextureExtension(in.flags));
                put(a[1], c.rgb());
                put(a[2], scalar(c.a));
                break;
            }
            case NodeOp::kTransform: {
                const float* m = program.data.data() + in.data;
                const Vec3f v = r(a[0]);
                put(a[1],
                    Vec3f(m[0] * v.x + m[1] * v.y + m[2] * v.z + m[3], m[4] * v.x + m[5] * v.y + m[6] * v.z + m[7],
                          m[8] * v.x + m[9] * v.y + m[10] * v.z + m[11]));
                break;
            }
            case NodeOp::kScale: put(a[2], r(a[0]) * r(a[1]).x); break;
            case NodeOp::kProject: {
                const float* m = program.data.data() + in.data;
                const Vec3f v = r(a[0]);
                const float w = m[12] * v.x + m[13] * v.y + m[14] * v.z + m[15];
                const float inv = w != 0.0f ? 1.0f / w : 0.0f;
                put(a[1],
                    Vec3f(m[0] * v.x + m[1] * v.y + m[2] * v.z + m[3], m[4] * v.x + m[5] * v.y + m[6] * v.z + m[7],
                          m[8] * v.x + m[9] * v.y + m[10] * v.z + m[11]) *
                        inv);
                break;
            }
            case NodeOp::kCount: break;
        }
    }
    return r(uint16_t(program.output));
}

void CheckNodeProgram(const NodeProgram& p, size_t num_images) {
    auto fail = [](size_t i, const std::string& what) {
        throw std::invalid_argument("node program instruction " + std::to_string(i) + ": " + what);
    };
    if (p.num_registers < 1 || p.num_registers > kMaxNodeRegisters)
        throw std::invalid_argument("node program: num_registers must be in [1, " + std::to_string(kMaxNodeRegisters) +
                                    "]");
    if (p.output < 0 || p.output >= p.num_registers)
        throw std::invalid_argument("node program: output is not one of its registers");
    // How many modes each op takes (0: mode unused), and its operand count.
    struct Shape {
        int modes, operands;
    };
    auto shape = [](NodeOp op) -> Shape {
        switch (op) {
            case NodeOp::kConstant: return {0, 1};
            case NodeOp::kGlobal: return {int(ShaderGlobal::kCount), 1};
            case NodeOp::kConvert: return {int(NodeConversion::kCount), 2};
            case NodeOp::kMath: return {int(MathOp::kCount), 4};
            case NodeOp::kMixColor: return {int(MixBlend::kCount), 4};
            case NodeOp::kMixFloat: return {0, 4};
            case NodeOp::kMixVector: return {2, 4};
            case NodeOp::kColorRamp: return {0, 3};
            case NodeOp::kInvert: return {0, 3};
            case NodeOp::kClamp: return {int(ClampType::kCount), 4};
            case NodeOp::kMapRange: return {int(MapRangeType::kCount), 7};
            case NodeOp::kSeparate: return {int(ColorModel::kCount), 4};
            case NodeOp::kCombine: return {int(ColorModel::kCount), 4};
            case NodeOp::kMapping: return {int(MappingType::kCount), 5};
            case NodeOp::kImage: return {2, 3};
            case NodeOp::kTransform: return {0, 2};
            case NodeOp::kScale: return {0, 3};
            case NodeOp::kProject: return {0, 2};
            case NodeOp::kCount: break;
        }
        return {-1, 0};
    };
    std::vector<bool> written(size_t(p.num_registers), false);  // registers are read only after they are written
    for (size_t i = 0; i < p.code.size(); ++i) {
        const NodeInstruction& in = p.code[i];
        const Shape s = shape(in.op);
        if (s.modes < 0) fail(i, "unknown op " + std::to_string(int(in.op)));
        if (s.modes > 0 ? int(in.mode) >= s.modes : in.mode != 0) fail(i, "mode out of range");
        for (int k = 0; k < kMaxNodeOperands; ++k) {
            const uint16_t reg = in.reg[k];
            if (reg == kNoRegister) continue;
            if (k >= s.operands) fail(i, "too many operands");
            if (int(reg) >= p.num_registers) fail(i, "register out of range");
        }
        // Inputs must be given; the outputs may be kNoRegister (nobody reads them).
        const int inputs = in.op == NodeOp::kSeparate || in.op == NodeOp::kColorRamp || in.op == NodeOp::kImage ||
                                   in.op == NodeOp::kConvert || in.op == NodeOp::kTransform || in.op == NodeOp::kProject
                               ? 1
                               : s.operands - 1;
        const int num_inputs = in.op == NodeOp::kConstant || in.op == NodeOp::kGlobal ? 0 : inputs;
        for (int k = 0; k < num_inputs; ++k) {
            if (in.reg[k] == kNoRegister) fail(i, "an input has no register");
            if (!written[in.reg[k]]) fail(i, "an input reads a register nothing wrote before");
        }
        for (int k = num_inputs; k < s.operands; ++k)
            if (in.reg[k] != kNoRegister) written[in.reg[k]] = true;
        if (in.op == NodeOp::kImage) {
            if (in.data < 0 || size_t(in.data) >= num_images) fail(i, "image index out of range");
            if (in.flags > 2) fail(i, "image extension out of range");
        }
        if (in.op == NodeOp::kColorRamp &&
            (in.size < 1 || in.data < 0 || size_t(in.data) + 4 * size_t(in.size) > p.data.size()))
            fail(i, "ramp table out of range");
        if (in.op == NodeOp::kTransform && (in.data < 0 || size_t(in.data) + 12 > p.data.size()))
            fail(i, "transform out of range");
        if (in.op == NodeOp::kProject && (in.data < 0 || size_t(in.data) + 16 > p.data.size()))
            fail(i, "projection out of range");
        if (in.op == NodeOp::kConstant &&
            !(std::isfinite(in.value.x) && std::isfinite(in.value.y) && std::isfinite(in.value.z)))
            fail(i, "constant must be finite");
    }
    if (!written[size_t(p.output)]) throw std::invalid_argument("node program: nothing writes its output");
    for (float v : p.data)
        if (!std::isfinite(v)) throw std::invalid_argument("node program: data must be finite");
}

}  // namespace sphrect::render::svm
