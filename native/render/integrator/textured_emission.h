// Emission an image drives (textured_emitter.h): the radiance multiplier x the lookup's colour at a point of the
// emitter, as Cycles 3.4 evaluates the emission closure's colour per shading point.  An emissive mesh's
// (Material::textures[kEmission]) is read by camera rays at their hit's texture coordinates, by BSDF rays at the
// barycentrics of the triangle they hit, by light samples at their point (its triangle's barycentrics); a rectangle or
// ellipse light's own at the point's coordinates along the light's edges.  Out of line and cold, as HitSpecificBsdf:
// scenes without textured emission pay one test of AreaLight::texture per light sample and emitter a ray finds.
#pragma once

#include <algorithm>

#include "render/scene.h"
#include "shader_globals.h"
#include "surface_hit.h"  // InterpolateTextureCoordinates

namespace sphrect::render {

// A lookup's colour times the emitter's multiplier (the colour clamped to >= 0, as a base colour).
inline Spectrum ScaledEmission(const Spectrum& multiplier, const Rgba& lookup) {
    const Spectrum c = TextureColor(lookup);
    return multiplier * Spectrum(std::max(c.x, 0.0f), std::max(c.y, 0.0f), std::max(c.z, 0.0f));
}

// Material `material`'s emitted radiance at texture coordinates tc.
inline Spectrum EmissionAtCoordinates(const RenderScene& scene, int material, const TextureCoordinates& tc) {
    const Material& r = scene.materials[size_t(material)];
    return ScaledEmission(r.emission, EvalTextureAt(scene.images, r.textures[int(TexturedInput::kEmission)], tc));
}

// Emitter e's radiance where its lookup's input coordinates are `coords`.
inline Spectrum EmitterRadianceAt(const RenderScene& scene, const TexturedEmitter& e, const Vec3f& coords) {
    return ScaledEmission(e.multiplier, EvalTextureLookup(scene.images, e.lookup, coords));
}

// The texture coordinates at barycentrics (b1, b2) of triangle `prim` of the emitter's mesh.
inline TextureCoordinates EmitterCoordinates(const RenderScene& scene, const TexturedEmitter& e, uint32_t prim,
                                             float b1, float b2) {
    const MeshData& m = scene.meshes[e.mesh];
    const uint32_t* t = &m.triangles[3 * size_t(prim)];
    return InterpolateTextureCoordinates(m, t[0], t[1], t[2], 1 - b1 - b2, b1, b2);
}

// Where point p of a mesh emitter lies: the triangle of the light that holds it (of a rectangle's two, the one p lies
// deeper in) and its barycentrics there (the 2x2 Gram system of its edges, as IntersectAreaLight).
struct EmitterTrianglePoint {
    uint32_t prim;
    float b1, b2;
};
inline EmitterTrianglePoint EmitterTrianglePointAt(const RenderScene& scene, const TexturedEmitter& e, const Vec3f& p) {
    const MeshData& m = scene.meshes[e.mesh];
    uint32_t best = e.triangles[0];
    float best_depth = -kInf, best_b1 = 0, best_b2 = 0;
    for (int k = 0; k < e.num_triangles; ++k) {
        const uint32_t* t = &m.triangles[3 * size_t(e.triangles[k])];
        auto vertex = [&](uint32_t v) {
            return Vec3f(m.vertices[3 * v], m.vertices[3 * v + 1], m.vertices[3 * v + 2]);
        };
        const Vec3f v0 = vertex(t[0]), e1 = vertex(t[1]) - v0, e2 = vertex(t[2]) - v0, q = p - v0;
        const float g11 = Dot(e1, e1), g12 = Dot(e1, e2), g22 = Dot(e2, e2);
        const float r1 = Dot(q, e1), r2 = Dot(q, e2), det = g11 * g22 - g12 * g12;
        if (!(det > 0)) continue;
        const float b1 = (g22 * r1 - g12 * r2) / det, b2 = (g11 * r2 - g12 * r1) / det;
        const float depth = std::min({b1, b2, 1 - b1 - b2});
        if (depth > best_depth) best = e.triangles[k], best_depth = depth, best_b1 = b1, best_b2 = b2;
    }
    return {best, best_b1, best_b2};
}

// The texture coordinates at point p of a mesh emitter.
inline TextureCoordinates EmitterCoordinatesAt(const RenderScene& scene, const TexturedEmitter& e, const Vec3f& p) {
    const EmitterTrianglePoint q = EmitterTrianglePointAt(scene, e, p);
    return EmitterCoordinates(scene, e, q.prim, q.b1, q.b2);
}

// A program's emission colour times the emitter's multiplier (the colour clamped to >= 0, as a lookup's).
inline Spectrum ScaledProgramEmission(const Spectrum& multiplier, const Vec3f& c) {
    return multiplier * Spectrum(std::max(c.x, 0.0f), std::max(c.y, 0.0f), std::max(c.z, 0.0f));
}

// A node program's emitter (TexturedEmitter::programmed): its radiance at point p, barycentrics (b1, b2) of triangle
// `prim`, seen from direction `toward` at distance `distance` (0 where no ray measured one) by a ray of context `ray`
// (a light sample's unless given).
inline Spectrum ProgramEmitterRadianceAt(const RenderScene& scene, const TexturedEmitter& e, uint32_t prim, float b1,
                                         float b2, const Vec3f& p, const Vec3f& toward, float distance,
                                         const svm::RayContext& ray = svm::LightSampleContext(0)) {
    const svm::NodeProgram& program = scene.materials[size_t(e.material)].programs[int(TexturedInput::kEmission)];
    const svm::ShaderGlobals sg = TriangleShaderGlobals(scene.meshes[e.mesh], prim, b1, b2, p, toward, distance, ray);
    return ScaledProgramEmission(e.multiplier, svm::EvalNodeProgram(program, scene.images, sg));
}

// A rectangle or ellipse light's coordinates at point p of its plane: (a, b, 0), p's fractions along its edges from
// its corner (an ellipse's: along its bounding rectangle's), [0, 1]^2 on the light.
inline Vec3f LightPlaneCoordinates(const AreaLight& l, const Vec3f& p) {
    const float k = l.shape == AreaShape::Ellipse ? 0.5f : 1.0f;  // inv_x, inv_y: an ellipse's semi-axes
    const Vec3f q = p - l.center;
    return {k * Dot(q, l.inv_x) + 0.5f, k * Dot(q, l.inv_y) + 0.5f, 0.0f};
}

// The lookup's input coordinates at point p of textured emitter e (area light l).
inline Vec3f EmitterLookupCoordinates(const RenderScene& scene, const TexturedEmitter& e, const AreaLight& l,
                                      const Vec3f& p) {
    if (e.on_light_plane) return LightPlaneCoordinates(l, p);
    const TextureCoordinates tc = EmitterCoordinatesAt(scene, e, p);
    return e.lookup.generated ? tc.generated : tc.uv;
}

// The radiance textured light l sends from its point p towards `toward` (pointing away from the light): a mesh's on
// both sides, a light's own on the sides it emits on, with its spread (as EmittedRadiance).  Light samples, and the
// BSDF and camera rays that cross a rectangle or ellipse light.  distance: a light sample's, from its shading point
// (Cycles' ls->t, the ray length its shader reads).
[[gnu::noinline, gnu::cold]] inline Spectrum TexturedEmissionAtPoint(const RenderScene& scene, const AreaLight& l,
                                                                     const Vec3f& p, const Vec3f& toward,
                                                                     float distance = 0) {
    const TexturedEmitter& e = scene.textured_emitters[size_t(l.texture)];
    if (e.programmed) {
        const EmitterTrianglePoint q = EmitterTrianglePointAt(scene, e, p);
        return ProgramEmitterRadianceAt(scene, e, q.prim, q.b1, q.b2, p, toward, distance);
    }
    if (!e.on_light_plane) return EmitterRadianceAt(scene, e, EmitterLookupCoordinates(scene, e, l, p));
    const float share = EmissionTowards(l, toward);
    return share > 0 ? EmitterRadianceAt(scene, e, LightPlaneCoordinates(l, p)) * share : Spectrum();
}

// BSDF rays: the radiance of textured mesh light l at barycentrics (b1, b2) of its triangle `prim` (Embree's hit of
// the ray from o along d at distance t, a ray of context `ray`).
[[gnu::noinline, gnu::cold]] inline Spectrum TexturedEmissionAtHit(const RenderScene& scene, const AreaLight& l,
                                                                   uint32_t prim, float b1, float b2, const Vec3f& o,
                                                                   const Vec3f& d, float t,
                                                                   const svm::RayContext& ray) {
    const TexturedEmitter& e = scene.textured_emitters[size_t(l.texture)];
    if (e.programmed) return ProgramEmitterRadianceAt(scene, e, prim, b1, b2, o + d * t, -d, t, ray);
    const TextureCoordinates tc = EmitterCoordinates(scene, e, prim, b1, b2);
    return EmitterRadianceAt(scene, e, e.lookup.generated ? tc.generated : tc.uv);
}

// What a ray from o along d finds of rectangle or ellipse light l crossed at distance t.
inline Spectrum RadianceOfCrossedLight(const RenderScene& scene, const AreaLight& l, const Vec3f& o, const Vec3f& d,
                                       float t) {
    return l.texture < 0 ? EmittedRadiance(l, -d) : TexturedEmissionAtPoint(scene, l, o + d * t, -d);
}

// A camera ray's hit on a textured emitter: its image at the hit's texture coordinates, or its program at the hit.
[[gnu::noinline, gnu::cold]] inline Spectrum EmissionSeenAtTexturedHit(const RenderScene& scene, const SurfaceHit& h) {
    const Material& r = scene.materials[size_t(h.material)];
    const svm::NodeProgram& program = r.programs[int(TexturedInput::kEmission)];
    if (program.empty()) return EmissionAtCoordinates(scene, h.material, h.tc);
    return ScaledProgramEmission(r.emission, svm::EvalNodeProgram(program, scene.images, HitShaderGlobals(h)));
}

// Camera rays: the emission of the hit's material, at its texture coordinates when an image drives it.
static inline Spectrum EmissionSeenAtHit(const RenderScene& scene, const SurfaceHit& h) {
    const Spectrum& le = scene.bsdfs[size_t(h.material)].emission;
    if (scene.textured_emitters.empty() || !scene.materials[size_t(h.material)].EmissionVaries()) return le;
    return EmissionSeenAtTexturedHit(scene, h);
}

}  // namespace sphrect::render
