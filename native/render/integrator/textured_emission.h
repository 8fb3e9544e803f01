// Emission an image drives (Material::textures[kEmission]): the radiance Material::emission x the lookup's colour at
// a point of the emitter, as Cycles 3.4 evaluates the emission closure's colour per shading point.  Camera rays read
// it at their hit's texture coordinates, BSDF rays at the barycentrics of the triangle they hit, light samples at
// their point (its triangle's barycentrics).  Out of line and cold, as HitSpecificBsdf: scenes without textured
// emission pay one test of AreaLight::texture per light sample and BSDF hit on an emitter.
#pragma once

#include <algorithm>

#include "render/scene.h"
#include "surface_hit.h"  // InterpolateTextureCoordinates

namespace sphrect::render {

// Material `material`'s emitted radiance at texture coordinates tc (the colour clamped to >= 0, as a base colour).
inline Spectrum EmissionAtCoordinates(const RenderScene& scene, int material, const TextureCoordinates& tc) {
    const Material& r = scene.materials[size_t(material)];
    const Spectrum c = TextureColor(EvalTextureAt(scene.images, r.textures[int(TexturedInput::kEmission)], tc));
    return r.emission * Spectrum(std::max(c.x, 0.0f), std::max(c.y, 0.0f), std::max(c.z, 0.0f));
}

// The texture coordinates at barycentrics (b1, b2) of triangle `prim` of the emitter's mesh.
inline TextureCoordinates EmitterCoordinates(const RenderScene& scene, const TexturedEmitter& e, uint32_t prim,
                                             float b1, float b2) {
    const MeshData& m = scene.meshes[e.mesh];
    const uint32_t* t = &m.triangles[3 * size_t(prim)];
    return InterpolateTextureCoordinates(m, t[0], t[1], t[2], 1 - b1 - b2, b1, b2);
}

// The texture coordinates at point p of the emitter: in the triangle of the light that holds it (of a rectangle's two,
// the one p lies deeper in), from its barycentrics (the 2x2 Gram system of its edges, as IntersectAreaLight).
inline TextureCoordinates EmitterCoordinatesAt(const RenderScene& scene, const TexturedEmitter& e, const Vec3f& p) {
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
    return EmitterCoordinates(scene, e, best, best_b1, best_b2);
}

// Light samples: the radiance a textured mesh light l sends from its point p (both sides, as every mesh light).
[[gnu::noinline, gnu::cold]] inline Spectrum TexturedEmissionAtPoint(const RenderScene& scene, const AreaLight& l,
                                                                     const Vec3f& p) {
    const TexturedEmitter& e = scene.textured_emitters[size_t(l.texture)];
    return EmissionAtCoordinates(scene, e.material, EmitterCoordinatesAt(scene, e, p));
}

// BSDF rays: the radiance of textured mesh light l at barycentrics (b1, b2) of its triangle `prim` (Embree's hit).
[[gnu::noinline, gnu::cold]] inline Spectrum TexturedEmissionAtHit(const RenderScene& scene, const AreaLight& l,
                                                                   uint32_t prim, float b1, float b2) {
    const TexturedEmitter& e = scene.textured_emitters[size_t(l.texture)];
    return EmissionAtCoordinates(scene, e.material, EmitterCoordinates(scene, e, prim, b1, b2));
}

// Camera rays: the emission of the hit's material, at its texture coordinates when an image drives it.
static inline Spectrum EmissionSeenAtHit(const RenderScene& scene, const SurfaceHit& h) {
    const Spectrum& le = scene.bsdfs[size_t(h.material)].emission;
    if (scene.textured_emitters.empty() ||
        !scene.materials[size_t(h.material)].textures[int(TexturedInput::kEmission)].bound())
        return le;
    return EmissionAtCoordinates(scene, h.material, h.tc);
}

}  // namespace sphrect::render
