// The surface a camera ray hits, from Embree's answer: point, normals facing the ray, material.
#pragma once

#include "render/camera.h"
#include "render/embree_rays.h"
#include "render/scene.h"

namespace sphrect::render {

struct SurfaceHit {
    Vec3f p;      // hit point
    Vec3f ng;     // unit geometric normal, on the side the camera ray came from
    Vec3f ns;     // unit shading normal, flipped with ng
    float t = 0;  // distance along the camera ray
    int material = 0;
};

static inline SurfaceHit MakeSurfaceHit(const RenderScene& scene, const Ray& ray, const RTCRayHit& rh) {
    const MeshData& m = scene.meshes[rh.hit.geomID];
    const uint32_t tri = rh.hit.primID;
    SurfaceHit s;
    s.t = rh.ray.tfar;
    Vec3f ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);  // Embree's unnormalised geometric normal
    const float len = Length(ng);
    ng = len > 0 ? ng / len : -ray.d;
    Vec3f ns = ng;
    if (m.normals.empty()) {
        s.p = ray.o + ray.d * s.t;  // flat shading: no vertex fetch needed
    } else {
        // Interpolated shading normal (and the point from the barycentrics, which is more precise).
        const uint32_t i0 = m.triangles[3 * tri], i1 = m.triangles[3 * tri + 1], i2 = m.triangles[3 * tri + 2];
        auto vertex = [&](uint32_t i) {
            return Vec3f(m.vertices[3 * i], m.vertices[3 * i + 1], m.vertices[3 * i + 2]);
        };
        const float b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1 - b1 - b2;
        s.p = vertex(i0) * b0 + vertex(i1) * b1 + vertex(i2) * b2;
        const Vec3f n = m.normals[i0] * b0 + m.normals[i1] * b1 + m.normals[i2] * b2;
        const float ln = Length(n);
        if (ln > 0) ns = n / ln;
        if (Dot(ns, ng) < 0) ns = -ns;  // shading normal on the geometric normal's side
    }
    // Surfaces are two-sided: both normals face the incoming ray.
    if (Dot(ng, ray.d) > 0) {
        ng = -ng;
        ns = -ns;
    }
    s.ng = ng;
    s.ns = ns;
    s.material = m.material_ids.empty() ? 0 : m.material_ids[tri];
    return s;
}

}  // namespace sphrect::render
