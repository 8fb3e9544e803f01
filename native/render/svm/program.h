// A node program: a material input's shader node graph compiled once (by the Blender exporter,
// addon/sphrect_blender/io/exporter/node_program.py) into a flat list of instructions over a register file, which
// the renderer runs per hit (evaluate.h), as Cycles 3.4 compiles a shader graph into SVM code (scene/svm.cpp) and
// runs it per shading point (kernel/svm/svm.h).  Each register holds a float3 (a float in x); constants are
// instructions of their own; every node is compiled once however many paths reach it.
//
// Adding a node: a value in NodeOp (and its name in kNodeOpNames, the scene format's), its operand layout in the
// table below, a case in EvalNodeInstruction (evaluate.cpp) calling the node family's pure function (a header here:
// math_nodes.h, mix_nodes.h, ... procedural_textures.h, shading_nodes.h, color_nodes.h), and a compiler function in
// node_program.py's _NODE_COMPILERS.
#pragma once

#include <cstdint>
#include <vector>

#include "render/sampling_util.h"

namespace sphrect::render::svm {

// The instructions.  Operands are register indices in NodeInstruction::reg, inputs first, then outputs
// (kNoRegister: an output nobody reads); `mode` selects the node's operation, `flags` its options.
enum class NodeOp : uint8_t {
    kConstant,   // out0 = value
    kGlobal,     // out0 = the hit's input `mode` (ShaderGlobal); flags 1 / 2: read at P + dx / P + dy (a Bump node's
                 // shifted copies of its Height; only the position-dependent ones move: IsShiftedGlobal)
    kConvert,    // out1 = in0 converted (mode: NodeConversion), as Cycles converts a link between socket types
    kMath,       // out3 = Math (mode: kMathOpNames) of in0, in1, in2; flags & 1: clamp to [0, 1]
    kMixColor,   // out3 = Mix (mode: kMixBlendNames) of factor in0, colours in1, in2; flags: 1 clamp factor, 2 result
    kMixFloat,   // out3 = in1 (1 - t) + in2 t, t = factor in0 (flags & 1: clamped)
    kMixVector,  // out3 = in1 (1 - t) + in2 t per component, t = in0 (mode 1: per component); flags & 1: clamped
    kColorRamp,  // out1 colour, out2 alpha of a ramp table (data: offset, size RGBA rows) at in0; flags & 1: lerp
    kInvert,     // out2 = in1 mixed with 1 - in1 by factor in0
    kClamp,      // out3 = in0 clamped to [in1, in2] (mode 1, 'RANGE': the bounds swapped if reversed)
    kMapRange,   // out6 = Map Range (mode: kMapRangeNames) of value in0, from in1..in2 to in3..in4, steps in5;
                 // flags: 1 clamp, 2 per vector component
    kSeparate,   // out1, out2, out3 = components of in0 (mode: kColorModelNames; XYZ and RGB are 'RGB')
    kCombine,    // out3 = (in0, in1, in2) in colour model `mode` (kColorModelNames)
    kMapping,    // out4 = Mapping (mode: kMappingTypeNames) of vector in0, location in1, rotation in2, scale in3
    kImage,      // out1 colour, out2 alpha of image `data` at in0 (mode: interpolation, flags: extension + 4
                 // projection (image_projection.h); value.x: the box projection's blend)
    kTransform,  // out1 = the 3x4 affine map at data (12 floats, row-major) applied to point in0
    kScale,      // out2 = in0 * in1.x (an emission's colour times its strength)
    kProject,    // out1 = (M (in0, 1)).xyz / (M (in0, 1)).w, M the 4x4 map at data (16 floats, row-major)
    // Procedural textures (procedural_textures.h) at point in0 (after the node's Texture Mapping); their float
    // inputs packed three to a register (a Combine or one constant), in their socket order.
    kNoiseTexture,       // out4 fac, out5 colour of in0, w in1, (scale, detail, roughness) in2, (distortion) in3;
                         // mode: dimensions - 1
    kVoronoiTexture,     // out4 distance (flags & 1: W; n-sphere radius: radius), out5 colour, out6 position of in0, w
                         // in1, (scale, smoothness, exponent) in2, (randomness) in3; mode: kVoronoiMode
    kMusgraveTexture,    // out4 fac of in0, w in1, (scale, detail, dimension) in2, (lacunarity, offset, gain) in3;
                         // mode: dimensions - 1 + 4 type
    kWhiteNoiseTexture,  // out2 value, out3 colour of in0, w in1; mode: dimensions - 1
    kGradientTexture,    // out1 fac of in0; mode: GradientType
    kCheckerTexture,     // out4 colour, out5 fac of in0, colours in1, in2, scale in3
    kWaveTexture,   // out3 fac of in0, (scale, distortion, detail) in1, (detail scale, roughness, phase) in2; mode:
                    // type + 2 direction (bands' or rings') + 8 profile
    kMagicTexture,  // out2 colour, out3 fac of in0, (scale, distortion) in1; mode: depth
    kBrickTexture,  // out6 colour (flags & 1: fac) of in0, colours in1, in2, mortar in3, (scale, mortar size, mortar
                    // smooth) in4, (bias, brick width, row height) in5; data: offset, its frequency, squash, its
                    // frequency (4 floats)
    // Shading inputs (shading_nodes.h) and colour nodes (color_nodes.h).
    kLayerWeight,     // out2 fresnel, out3 facing of blend in0, normal in1
    kFresnel,         // out2 of IOR in0, normal in1
    kLightFalloff,    // out2 quadratic, out3 linear, out4 constant of strength in0, smooth in1
    kBlackbody,       // out1 colour of temperature in0
    kWavelength,      // out1 colour of wavelength in0
    kHueSaturation,   // out5 = HSV of hue in0, saturation in1, value in2, fac in3, colour in4
    kBrightContrast,  // out3 of colour in0, bright in1, contrast in2
    kGamma,           // out2 of colour in0, gamma in1
    kVectorMath,      // out4 vector, out5 value of in0, in1, in2, scale in3; mode: VectorMathOp
    kVectorRotate,    // out5 of vector in0, center in1, axis in2, angle in3, rotation in4; mode: type, flags: invert
    kCurves,          // out2 = curves (mode 0: 3 channels, RGB / Vector Curves; 1: Float Curve) of fac in0, value
                      // in1; data: min x, max x, extrapolate, then `size` entries of 3 (or 1) floats
    kBump,         // out6 = Bump (BumpNormal) of heights in0 (centre), in1 (at P + dx), in2 (at P + dy), strength in3,
                   // distance in4, normal in5; flags & 1: invert
    kObjectSpace,  // out1 = in0 through the hit's object transform L (ShaderGlobals::object_linear; none: as is):
                   // mode 0 a world normal into object space, L^T n normalised; mode 1 an object direction into
                   // the world, L v (the Displacement node's Object space)
    // Mesh attributes (attribute_nodes.h): out0 colour / vector, out1 fac, out2 alpha of the hit mesh's attribute
    // `data` (ShaderGlobals::attributes); mode: AttributeNode.
    kAttribute,
    kRadialTangent,  // out1 = the Tangent node's radial tangent about axis `mode` (0 X, 1 Y, 2 Z) of Generated in0,
                     // or (mode 3) in0 an object-space tangent (a UV map's)
    kCount
};
constexpr const char* kNodeOpNames[] = {"constant",
                                        "global",
                                        "convert",
                                        "math",
                                        "mix_color",
                                        "mix_float",
                                        "mix_vector",
                                        "color_ramp",
                                        "invert",
                                        "clamp",
                                        "map_range",
                                        "separate",
                                        "combine",
                                        "mapping",
                                        "image",
                                        "transform",
                                        "scale",
                                        "project",
                                        "noise_texture",
                                        "voronoi_texture",
                                        "musgrave_texture",
                                        "white_noise_texture",
                                        "gradient_texture",
                                        "checker_texture",
                                        "wave_texture",
                                        "magic_texture",
                                        "brick_texture",
                                        "layer_weight",
                                        "fresnel",
                                        "light_falloff",
                                        "blackbody",
                                        "wavelength",
                                        "hue_saturation",
                                        "bright_contrast",
                                        "gamma",
                                        "vector_math",
                                        "vector_rotate",
                                        "curves",
                                        "bump",
                                        "object_space",
                                        "attribute",
                                        "radial_tangent"};
static_assert(sizeof(kNodeOpNames) / sizeof(*kNodeOpNames) == size_t(NodeOp::kCount));

// What a hit gives a program (kGlobal's mode), as Cycles' ShaderData does: position, shading normal (facing the
// incoming ray), true (geometric) normal, incoming direction I (towards where the ray came from), the mesh's UV
// (u, v, 0) and Generated coordinates, the position and shading normal in the object's space (Texture Coordinate's
// Object and Normal), the reflected incoming direction 2 (N.I) N - I, backfacing (1 or 0), the ray's length; then the
// Light Path node's outputs of the ray that found the hit (ShaderGlobals::ray, RayContext below).
enum class ShaderGlobal : uint8_t {
    kPosition,
    kNormal,
    kTrueNormal,
    kIncoming,
    kUv,
    kGenerated,
    kObject,
    kObjectNormal,
    kReflection,
    kBackfacing,
    kRayLength,
    kParametric,
    kObjectLocation,
    kObjectColor,
    kObjectAlpha,
    kObjectIndex,
    kObjectRandom,
    kIsCameraRay,
    kIsShadowRay,
    kIsDiffuseRay,
    kIsGlossyRay,
    kIsSingularRay,
    kIsReflectionRay,
    kIsTransmissionRay,
    kIsVolumeScatterRay,
    kRayDepth,
    kDiffuseDepth,
    kGlossyDepth,
    kTransparentDepth,
    kTransmissionDepth,
    kCount
};
constexpr const char* kShaderGlobalNames[] = {"position",
                                              "normal",
                                              "true_normal",
                                              "incoming",
                                              "uv",
                                              "generated",
                                              "object",
                                              "object_normal",
                                              "reflection",
                                              "backfacing",
                                              "ray_length",
                                              "parametric",
                                              "object_location",
                                              "object_color",
                                              "object_alpha",
                                              "object_index",
                                              "object_random",
                                              "is_camera_ray",
                                              "is_shadow_ray",
                                              "is_diffuse_ray",
                                              "is_glossy_ray",
                                              "is_singular_ray",
                                              "is_reflection_ray",
                                              "is_transmission_ray",
                                              "is_volume_scatter_ray",
                                              "ray_depth",
                                              "diffuse_depth",
                                              "glossy_depth",
                                              "transparent_depth",
                                              "transmission_depth"};
static_assert(sizeof(kShaderGlobalNames) / sizeof(*kShaderGlobalNames) == size_t(ShaderGlobal::kCount));
constexpr bool IsShiftedGlobal(ShaderGlobal g) {
    return g == ShaderGlobal::kPosition || g == ShaderGlobal::kUv || g == ShaderGlobal::kGenerated ||
           g == ShaderGlobal::kObject;
}

// A link between sockets of different types (Cycles' svm_node_convert): a colour to a float by its luminance
// (linear_rgb_to_gray), a vector to a float by its components' mean, a float to a colour or vector by repeating it.
enum class NodeConversion : uint8_t { kColorToFloat, kVectorToFloat, kFloatToVector, kCount };
constexpr const char* kNodeConversionNames[] = {"color_to_float", "vector_to_float", "float_to_vector"};

// kVoronoiTexture's mode: its dimensions, metric and feature in one byte.
constexpr int kVoronoiModes = 4 * 4 * 5;
constexpr uint8_t VoronoiMode(int dimensions, int metric, int feature) {
    return uint8_t(dimensions - 1 + 4 * (metric + 4 * feature));
}

constexpr uint16_t kNoRegister = 0xFFFF;
constexpr int kMaxNodeOperands = 7;
constexpr int kMaxNodeRegisters = 255;  // as Cycles' SVM_STACK_SIZE (floats there, float3s here)

struct NodeInstruction {
    NodeOp op = NodeOp::kConstant;
    uint8_t mode = 0;
    uint8_t flags = 0;
    uint16_t reg[kMaxNodeOperands] = {kNoRegister, kNoRegister, kNoRegister, kNoRegister,
                                      kNoRegister, kNoRegister, kNoRegister};
    int32_t data = 0, size = 0;  // an image's index; a table's offset into NodeProgram::data and its rows
    Vec3f value;                 // kConstant
};

// One material input's program: its instructions in order, their tables, the register holding the result (a float
// input reads its x) and how many registers it uses.  Empty: the input is not driven by a program.
struct NodeProgram {
    std::vector<NodeInstruction> code;
    std::vector<float> data;
    int output = 0;
    int num_registers = 0;
    bool empty() const { return code.empty(); }
    // Whether it reads the Light Path node's ray kinds or depths (its value differs between the rays finding a hit).
    bool ReadsRayContext() const {
        for (const NodeInstruction& in : code)
            if (in.op == NodeOp::kGlobal && in.mode >= uint8_t(ShaderGlobal::kIsCameraRay)) return true;
        return false;
    }
    // It has a Bump node: its hits need their ray differential and shifted inputs (ShaderGlobals::dP, shift).
    bool Bumps() const {
        for (const NodeInstruction& in : code)
            if (in.op == NodeOp::kBump) return true;
        return false;
    }
};

// A mesh attribute as kAttribute reads it (Cycles' Attribute node over Blender's attributes): four floats per vertex
// of the mesh, the value as the node's Color / Vector gives it and its Alpha (1 for attributes without one); the node's
// Fac is the mean of the three (x for a two-component attribute, Cycles' float2: fac_is_x).  Empty: the mesh lacks it.
struct MeshAttribute {
    std::vector<float> values;
    bool fac_is_x = false;
};

// kAttribute's mode: Cycles' Attribute node (a missing attribute reads colour 0, fac 0, alpha 1) or its Color
// Attribute node (colour 0, alpha 0).
enum class AttributeNode : uint8_t { kAttribute, kColorAttribute, kCount };
constexpr const char* kAttributeNodeNames[] = {"attribute", "color_attribute"};

// The object a hit lies on: Object Info's location, Blender's object colour and alpha, pass index and random number
// (Cycles' object_random_number), and the map of object-space normals to the world (L^-T, row-major) that Geometry's
// Tangent takes its radial direction through; `reversed`: the mesh's triangles list Blender's corners in reverse (a
// mirroring object's, to keep the winding outward), which Parametric undoes.
struct ObjectInfo {
    Vec3f location, color = Vec3f(1, 1, 1);
    float alpha = 1, index = 0, random = 0;
    bool reversed = false;
    float normal_to_world[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
};

// The Light Path node's view of the ray that found a hit (Cycles 3.4's path_flag handed to the shader's evaluation
// and the path state's bounce counters, kernel/svm/light_path.h).  The flags are Cycles' PATH_RAY_* the node tests;
// the depths are what the node reports (Ray Depth already one more for a light sample or a shadow ray, as Cycles
// adds).  The default is a camera ray's first hit.
enum RayFlag : uint8_t {
    kRayIsCamera = 1,
    kRayIsShadow = 2,
    kRayIsDiffuse = 4,
    kRayIsGlossy = 8,
    kRayIsSingular = 16,
    kRayIsReflection = 32,
    kRayIsTransmission = 64,
    kRayIsVolumeScatter = 128
};
struct RayContext {
    uint8_t flags = kRayIsCamera;
    uint8_t depth = 0, diffuse_depth = 0, glossy_depth = 0, transparent_depth = 0, transmission_depth = 0;
};

// The contexts under direct lighting (a camera ray, its hit's light samples and one BSDF or phase ray):
// A camera ray's hit past `transparent` transparent surfaces (PATH_RAY_CAMERA, bounce 0).
constexpr RayContext CameraRayContext(int transparent) { return {kRayIsCamera, 0, 0, 0, uint8_t(transparent), 0}; }
// An emitter's point a light sample lands on: light_sample_shader_eval passes PATH_RAY_EMISSION alone (no flag the
// node reads) with the shading point's state, and Ray Depth counts one more.
constexpr RayContext LightSampleContext(int transparent) { return {0, 1, 0, 0, uint8_t(transparent), 0}; }
// A surface a shadow ray crosses: PATH_RAY_SHADOW alone (integrate_transparent_surface_shadow), Ray Depth one more,
// the transparent depth counting the surfaces the shadow ray crossed before it.
constexpr RayContext ShadowRayContext(int transparent) { return {kRayIsShadow, 1, 0, 0, uint8_t(transparent), 0}; }
// The surface a BSDF or phase ray from a camera ray's hit finds: path_state_next's flags of the sampled lobe's label
// (kRayIsDiffuse / kRayIsGlossy (+ kRayIsSingular), kRayIsReflection / kRayIsTransmission, or kRayIsVolumeScatter)
// and its counters after one bounce.
constexpr RayContext ScatteredRayContext(uint8_t flags, int transparent) {
    const bool scatter = flags & kRayIsVolumeScatter;
    const bool transmit = flags & kRayIsTransmission;
    return {flags,
            1,
            uint8_t(!scatter && !transmit && (flags & kRayIsDiffuse) ? 1 : 0),
            uint8_t(!scatter && !transmit && !(flags & kRayIsDiffuse) ? 1 : 0),
            uint8_t(transparent),
            uint8_t(!scatter && transmit ? 1 : 0)};
}

// A hit as a program sees it (the evaluator reads what its kGlobal instructions ask for).  Where a hit kind lacks
// one, Cycles' choice: an emitter found by a light sample has I towards the shading point and ray length the
// distance; missing coordinates read zero.
struct ShaderGlobals {
    Vec3f p, n, ng, incoming;
    Vec3f uv, generated;
    Vec3f object, object_normal;
    bool backfacing = false;
    float ray_length = 0;
    // Bump: the point's compact ray differential (Cycles' sd->dP; 0 where a hit has none: BumpNormal then keeps
    // its normal) and, where `shifted` is set, the position-dependent inputs at P + dx ([0]) and P + dy ([1])
    // (BumpDifferentials: UV and Generated extrapolated linearly over the triangle's plane, as Cycles' du / dv).
    // Filled only for materials whose programs bump (RenderScene::normal_maps' differentials).
    float dP = 0;
    bool shifted = false;
    const float (*object_linear)[3] = nullptr;  // the hit's object transform's linear part (kObjectSpace), if any
    struct Shifted {
        Vec3f p, uv, generated, object;
    } shift[2];
    // Attributes (attribute_nodes.h): the hit mesh's attributes (null: none), the triangle's vertices and
    // barycentrics (the weights of v[0], v[1], v[2]), its object (null: Object Info reads zeros).
    const std::vector<MeshAttribute>* attributes = nullptr;
    uint32_t v[3] = {0, 0, 0};
    float b[3] = {0, 0, 0};
    const ObjectInfo* object_info = nullptr;
    RayContext ray;
};

}  // namespace sphrect::render::svm
