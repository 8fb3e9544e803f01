// The node program interpreter: one case per instruction, each calling its node family's pure function.
#include "evaluate.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "attribute_nodes.h"
#include "color_nodes.h"
#include "image_projection.h"
#include "math_nodes.h"
#include "mix_nodes.h"
#include "procedural_textures.h"
#include "shading_nodes.h"
#include "vector_nodes.h"

namespace sphrect::render::svm {

namespace {

// Object Info's outputs (svm_node_object_info); zero without an object.
Vec3f ObjectGlobal(ShaderGlobal g, const ObjectInfo* o) {
    if (o == nullptr) return {};
    switch (g) {
        case ShaderGlobal::kObjectLocation: return o->location;
        case ShaderGlobal::kObjectColor: return o->color;
        case ShaderGlobal::kObjectAlpha: return Vec3f(o->alpha, 0, 0);
        case ShaderGlobal::kObjectIndex: return Vec3f(o->index, 0, 0);
        case ShaderGlobal::kObjectRandom: return Vec3f(o->random, 0, 0);
        default: break;
    }
    return {};
}

Vec3f RayFlagValue(const ShaderGlobals& sg, RayFlag f) { return Vec3f(sg.ray.flags & f ? 1.0f : 0.0f, 0, 0); }

Vec3f Global(ShaderGlobal g, const ShaderGlobals& sg, int shift) {
    if (shift > 0 && sg.shifted && IsShiftedGlobal(g)) {  // a Bump's Height copy at P + dx (1) or P + dy (2)
        const ShaderGlobals::Shifted& s = sg.shift[shift - 1];
        switch (g) {
            case ShaderGlobal::kPosition: return s.p;
            case ShaderGlobal::kUv: return s.uv;
            case ShaderGlobal::kGenerated: return s.generated;
            default: return s.object;
        }
    }
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
        case ShaderGlobal::kParametric:  // svm_node_geometry's (1 - u - v, u, 0) of Blender's corner order
            return Vec3f(sg.object_info && sg.object_info->reversed ? sg.b[2] : sg.b[0], sg.b[1], 0);
        case ShaderGlobal::kIsCameraRay: return RayFlagValue(sg, kRayIsCamera);
        case ShaderGlobal::kIsShadowRay: return RayFlagValue(sg, kRayIsShadow);
        case ShaderGlobal::kIsDiffuseRay: return RayFlagValue(sg, kRayIsDiffuse);
        case ShaderGlobal::kIsGlossyRay: return RayFlagValue(sg, kRayIsGlossy);
        case ShaderGlobal::kIsSingularRay: return RayFlagValue(sg, kRayIsSingular);
        case ShaderGlobal::kIsReflectionRay: return RayFlagValue(sg, kRayIsReflection);
        case ShaderGlobal::kIsTransmissionRay: return RayFlagValue(sg, kRayIsTransmission);
        case ShaderGlobal::kIsVolumeScatterRay: return RayFlagValue(sg, kRayIsVolumeScatter);
        case ShaderGlobal::kRayDepth: return Vec3f(float(sg.ray.depth), 0, 0);
        case ShaderGlobal::kDiffuseDepth: return Vec3f(float(sg.ray.diffuse_depth), 0, 0);
        case ShaderGlobal::kGlossyDepth: return Vec3f(float(sg.ray.glossy_depth), 0, 0);
        case ShaderGlobal::kTransparentDepth: return Vec3f(float(sg.ray.transparent_depth), 0, 0);
        case ShaderGlobal::kTransmissionDepth: return Vec3f(float(sg.ray.transmission_depth), 0, 0);
        default: return ObjectGlobal(g, sg.object_info);
    }
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
            case NodeOp::kGlobal: put(a[0], Global(ShaderGlobal(in.mode), sg, in.flags)); break;
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
                if (in.flags & 2) {
                    put(a[6], EvalVectorMapRange(MapRangeType(in.mode), in.flags & 1, r(a[0]), r(a[1]), r(a[2]),
                                                 r(a[3]), r(a[4]), r(a[5])));
                    break;
                }
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
                const Image& im = images[size_t(in.data)];
                const auto interpolation = TextureInterpolation(in.mode);
                const auto extension = TextureExtension(in.flags & 3);
                auto lookup = [&](const Vec3f& uv) { return LookupImage(im, uv.x, uv.y, interpolation, extension); };
                const Vec3f v = r(a[0]);
                Rgba c;
                switch (ImageProjection(in.flags >> 2)) {
                    case ImageProjection::kSphere: c = lookup(MapToSphere(RemapSquare(v))); break;
                    case ImageProjection::kTube: c = lookup(MapToTube(RemapSquare(v))); break;
                    case ImageProjection::kBox: {
                        const Vec3f w = BoxProjectionWeights(sg.object_normal, in.value.x);
                        for (int axis = 0; axis < 3; ++axis)
                            if (w[axis] > 0.0f) c = c + lookup(BoxProjectionPoint(axis, v, sg.object_normal)) * w[axis];
                        break;
                    }
                    default: c = lookup(v); break;
                }
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
            case NodeOp::kNoiseTexture: {
                const Vec3f a2 = r(a[2]);
                NoiseTextureParams p;
                p.dimensions = in.mode + 1;
                p.scale = a2.x, p.detail = a2.y, p.roughness = a2.z, p.distortion = r(a[3]).x;
                const NoiseTextureOutput o = NoiseTexture(p, r(a[0]), r(a[1]).x, a[5] != kNoRegister);
                put(a[4], scalar(o.fac));
                put(a[5], o.color);
                break;
            }
            case NodeOp::kVoronoiTexture: {
                const Vec3f a2 = r(a[2]);
                VoronoiTextureParams p;
                p.dimensions = in.mode % 4 + 1;
                p.metric = VoronoiMetric(in.mode / 4 % 4);
                p.feature = VoronoiFeature(in.mode / 16);
                p.scale = a2.x, p.smoothness = a2.y, p.exponent = a2.z, p.randomness = r(a[3]).x;
                const VoronoiTextureOutput o = VoronoiTexture(p, r(a[0]), r(a[1]).x);
                const float s = p.feature == VoronoiFeature::kNSphereRadius ? o.radius
                                : (in.flags & 1)                            ? o.w
                                                                            : o.distance;
                put(a[4], scalar(s));
                put(a[5], o.color);
                put(a[6], o.position);
                break;
            }
            case NodeOp::kMusgraveTexture: {
                const Vec3f a2 = r(a[2]), a3 = r(a[3]);
                MusgraveTextureParams p;
                p.dimensions = in.mode % 4 + 1;
                p.type = MusgraveType(in.mode / 4);
                p.scale = a2.x, p.detail = a2.y, p.dimension = a2.z;
                p.lacunarity = a3.x, p.offset = a3.y, p.gain = a3.z;
                put(a[4], scalar(MusgraveTexture(p, r(a[0]), r(a[1]).x)));
                break;
            }
            case NodeOp::kWhiteNoiseTexture: {
                const WhiteNoiseTextureOutput o = WhiteNoiseTexture({in.mode + 1}, r(a[0]), r(a[1]).x);
                put(a[2], scalar(o.value));
                put(a[3], o.color);
                break;
            }
            case NodeOp::kGradientTexture: put(a[1], scalar(GradientTexture({GradientType(in.mode)}, r(a[0])))); break;
            case NodeOp::kCheckerTexture: {
                CheckerTextureParams p;
                p.color1 = r(a[1]), p.color2 = r(a[2]), p.scale = r(a[3]).x;
                const ColorFacOutput o = CheckerTexture(p, r(a[0]));
                put(a[4], o.color);
                put(a[5], scalar(o.fac));
                break;
            }
            case NodeOp::kWaveTexture: {
                const Vec3f a1 = r(a[1]), a2 = r(a[2]);
                WaveTextureParams p;
                p.type = WaveType(in.mode % 2);
                p.bands_direction = WaveBandsDirection(in.mode / 2 % 4);
                p.rings_direction = WaveRingsDirection(in.mode / 2 % 4);
                p.profile = WaveProfile(in.mode / 8);
                p.scale = a1.x, p.distortion = a1.y, p.detail = a1.z;
                p.detail_scale = a2.x, p.detail_roughness = a2.y, p.phase_offset = a2.z;
                put(a[3], scalar(WaveTexture(p, r(a[0]))));
                break;
            }
            case NodeOp::kMagicTexture: {
                const Vec3f a1 = r(a[1]);
                MagicTextureParams p;
                p.depth = in.mode, p.scale = a1.x, p.distortion = a1.y;
                const ColorFacOutput o = MagicTexture(p, r(a[0]));
                put(a[2], o.color);
                put(a[3], scalar(o.fac));
                break;
            }
            case NodeOp::kBrickTexture: {
                const float* d = program.data.data() + in.data;
                const Vec3f a4 = r(a[4]), a5 = r(a[5]);
                BrickTextureParams p;
                p.offset = d[0], p.offset_frequency = int(d[1]), p.squash = d[2], p.squash_frequency = int(d[3]);
                p.color1 = r(a[1]), p.color2 = r(a[2]), p.mortar = r(a[3]);
                p.scale = a4.x, p.mortar_size = a4.y, p.mortar_smooth = a4.z;
                p.bias = a5.x, p.brick_width = a5.y, p.row_height = a5.z;
                const ColorFacOutput o = BrickTexture(p, r(a[0]));
                put(a[6], (in.flags & 1) ? scalar(o.fac) : o.color);
                break;
            }
            case NodeOp::kLayerWeight: {
                const float blend = r(a[0]).x;
                const Vec3f n = r(a[1]);
                put(a[2], scalar(LayerWeightFresnel(blend, sg.incoming, n, sg.backfacing)));
                put(a[3], scalar(LayerWeightFacing(blend, sg.incoming, n)));
                break;
            }
            case NodeOp::kFresnel:
                put(a[2], scalar(FresnelNode(r(a[0]).x, sg.incoming, r(a[1]), sg.backfacing)));
                break;
            case NodeOp::kLightFalloff: {
                const float strength = r(a[0]).x, smooth = r(a[1]).x;
                put(a[2], scalar(LightFalloff(LightFalloffKind::kQuadratic, strength, smooth, sg.ray_length)));
                put(a[3], scalar(LightFalloff(LightFalloffKind::kLinear, strength, smooth, sg.ray_length)));
                put(a[4], scalar(LightFalloff(LightFalloffKind::kConstant, strength, smooth, sg.ray_length)));
                break;
            }
            case NodeOp::kBlackbody: put(a[1], Blackbody(r(a[0]).x)); break;
            case NodeOp::kWavelength: put(a[1], Wavelength(r(a[0]).x)); break;
            case NodeOp::kHueSaturation:
                put(a[5], HueSaturationValue(r(a[4]), r(a[0]).x, r(a[1]).x, r(a[2]).x, r(a[3]).x));
                break;
            case NodeOp::kBrightContrast: put(a[3], BrightContrast(r(a[0]), r(a[1]).x, r(a[2]).x)); break;
            case NodeOp::kGamma: put(a[2], GammaColor(r(a[0]), r(a[1]).x)); break;
            case NodeOp::kVectorMath: {
                const VectorMathResult o = VectorMath(VectorMathOp(in.mode), r(a[0]), r(a[1]), r(a[2]), r(a[3]).x);
                put(a[4], o.vector);
                put(a[5], scalar(o.value));
                break;
            }
            case NodeOp::kVectorRotate:
                put(a[5], VectorRotate(VectorRotateType(in.mode), in.flags & 1, r(a[0]), r(a[1]), r(a[2]), r(a[3]).x,
                                       r(a[4])));
                break;
            case NodeOp::kCurves: {
                const float* d = program.data.data() + in.data;
                CurveTable t;
                t.min_x = d[0], t.max_x = d[1], t.extrapolate = d[2] != 0.0f;
                t.values = d + 3, t.size = in.size, t.stride = in.mode == 0 ? 3 : 1;
                const float fac = r(a[0]).x;
                put(a[2], in.mode == 0 ? CurvesRgb(t, fac, r(a[1])) : scalar(CurveFloat(t, fac, r(a[1]).x)));
                break;
            }
            case NodeOp::kBump:
                put(a[6], BumpNormal(r(a[5]), sg.ng, sg.incoming, BumpDifferentials(sg.ng, sg.dP), r(a[0]).x, r(a[1]).x,
                                     r(a[2]).x, r(a[3]).x, r(a[4]).x, in.flags & 1));
                break;
            case NodeOp::kObjectSpace: {
                Vec3f v = r(a[0]);
                if (sg.object_linear != nullptr) {
                    const float(*L)[3] = sg.object_linear;
                    if (in.mode == 0) {
                        v = Vec3f(L[0][0] * v.x + L[1][0] * v.y + L[2][0] * v.z,
                                  L[0][1] * v.x + L[1][1] * v.y + L[2][1] * v.z,
                                  L[0][2] * v.x + L[1][2] * v.y + L[2][2] * v.z);
                        const float len = Length(v);
                        if (len > 0) v = v / len;
                    } else {
                        v = Vec3f(L[0][0] * v.x + L[0][1] * v.y + L[0][2] * v.z,
                                  L[1][0] * v.x + L[1][1] * v.y + L[1][2] * v.z,
                                  L[2][0] * v.x + L[2][1] * v.y + L[2][2] * v.z);
                    }
                }
                put(a[1], v);
                break;
            }
            case NodeOp::kAttribute: {
                const std::vector<MeshAttribute>* list = sg.attributes;
                const MeshAttribute* attr =
                    list != nullptr && size_t(in.data) < list->size() ? &(*list)[size_t(in.data)] : nullptr;
                const AttributeOutput o = InterpolateAttribute(attr, AttributeNode(in.mode), sg.v, sg.b);
                put(a[0], o.color);
                put(a[1], scalar(o.fac));
                put(a[2], scalar(o.alpha));
                break;
            }
            case NodeOp::kRadialTangent: {
                static const ObjectInfo kWorld;
                const ObjectInfo& o = sg.object_info != nullptr ? *sg.object_info : kWorld;
                put(a[1], RadialTangent(in.mode, r(a[0]), sg.n, o.normal_to_world));
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
        int modes, operands, outputs = 1;
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
            case NodeOp::kNoiseTexture: return {4, 6, 2};
            case NodeOp::kVoronoiTexture: return {kVoronoiModes, 7, 3};
            case NodeOp::kMusgraveTexture: return {4 * 5, 5};
            case NodeOp::kWhiteNoiseTexture: return {4, 4, 2};
            case NodeOp::kGradientTexture: return {7, 2};
            case NodeOp::kCheckerTexture: return {0, 6, 2};
            case NodeOp::kWaveTexture: return {2 * 4 * 3, 4};
            case NodeOp::kMagicTexture: return {kMaxMagicDepth + 1, 4, 2};
            case NodeOp::kBrickTexture: return {0, 7};
            case NodeOp::kLayerWeight: return {0, 4, 2};
            case NodeOp::kFresnel: return {0, 3};
            case NodeOp::kLightFalloff: return {0, 5, 3};
            case NodeOp::kBlackbody: return {0, 2};
            case NodeOp::kWavelength: return {0, 2};
            case NodeOp::kHueSaturation: return {0, 6};
            case NodeOp::kBrightContrast: return {0, 4};
            case NodeOp::kGamma: return {0, 3};
            case NodeOp::kVectorMath: return {int(std::size(kVectorMathOpNames)), 6, 2};
            case NodeOp::kVectorRotate: return {int(std::size(kVectorRotateTypeNames)), 6};
            case NodeOp::kCurves: return {2, 3};
            case NodeOp::kBump: return {0, 7};
            case NodeOp::kObjectSpace: return {2, 2};
            case NodeOp::kAttribute: return {int(AttributeNode::kCount), 3, 3};
            case NodeOp::kRadialTangent: return {4, 2};
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
                               : s.operands - s.outputs;
        const int num_inputs =
            in.op == NodeOp::kConstant || in.op == NodeOp::kGlobal || in.op == NodeOp::kAttribute ? 0 : inputs;
        for (int k = 0; k < num_inputs; ++k) {
            if (in.reg[k] == kNoRegister) fail(i, "an input has no register");
            if (!written[in.reg[k]]) fail(i, "an input reads a register nothing wrote before");
        }
        for (int k = num_inputs; k < s.operands; ++k)
            if (in.reg[k] != kNoRegister) written[in.reg[k]] = true;
        if (in.op == NodeOp::kImage) {
            if (in.data < 0 || size_t(in.data) >= num_images) fail(i, "image index out of range");
            if ((in.flags & 3) > 2) fail(i, "image extension out of range");
            if ((in.flags >> 2) >= int(ImageProjection::kCount)) fail(i, "image projection out of range");
            if (!std::isfinite(in.value.x)) fail(i, "box projection blend must be finite");
        }
        if (in.op == NodeOp::kColorRamp &&
            (in.size < 1 || in.data < 0 || size_t(in.data) + 4 * size_t(in.size) > p.data.size()))
            fail(i, "ramp table out of range");
        if (in.op == NodeOp::kTransform && (in.data < 0 || size_t(in.data) + 12 > p.data.size()))
            fail(i, "transform out of range");
        if (in.op == NodeOp::kProject && (in.data < 0 || size_t(in.data) + 16 > p.data.size()))
            fail(i, "projection out of range");
        if (in.op == NodeOp::kBrickTexture && (in.data < 0 || size_t(in.data) + 4 > p.data.size()))
            fail(i, "brick settings out of range");
        if (in.op == NodeOp::kCurves &&
            (in.size < 2 || in.data < 0 ||
             size_t(in.data) + 3 + size_t(in.size) * (in.mode == 0 ? 3 : 1) > p.data.size()))
            fail(i, "curve table out of range");
        if ((in.op == NodeOp::kBrickTexture || in.op == NodeOp::kVoronoiTexture || in.op == NodeOp::kBump) &&
            in.flags > 1)
            fail(i, "flags out of range");
        if (in.op == NodeOp::kGlobal && in.flags > 2) fail(i, "flags out of range");
        if (in.op == NodeOp::kConstant &&
            !(std::isfinite(in.value.x) && std::isfinite(in.value.y) && std::isfinite(in.value.z)))
            fail(i, "constant must be finite");
    }
    if (!written[size_t(p.output)]) throw std::invalid_argument("node program: nothing writes its output");
    for (float v : p.data)
        if (!std::isfinite(v)) throw std::invalid_argument("node program: data must be finite");
}

}  // namespace sphrect::render::svm
