// What a node program reads of a hit (svm::ShaderGlobals, as Cycles' ShaderData): from a camera ray's surface hit,
// and from a point of an emissive mesh that a light sample or a BSDF ray finds.  Only materials with programs come
// here (the cold per-hit material path).
#pragma once

#include "render/svm/program.h"
#include "render/svm/shading_nodes.h"  // BumpDifferentials
#include "surface_hit.h"

namespace sphrect::render {

// The mesh's object coordinates of world point p: its object's inverse transform (the world's own without one).
inline Vec3f ObjectPoint(const MeshData& m, const Vec3f& p) {
    return m.has_object_linear ? Apply3x3(m.object_linear_inverse, p - m.object_translation) : p;
}
// A world normal n in the object's space, as Cycles' object_inverse_normal_transform: L^T n, normalised.
inline Vec3f ObjectNormal(const MeshData& m, const Vec3f& n) {
    if (!m.has_object_linear) return n;
    const Vec3f o = Apply3x3Transposed(m.object_linear, n);
    const float len = Length(o);
    return len > 0 ? o / len : o;
}

// A Bump node's shifted inputs at hit h (its dP > 0): the point moved by BumpDifferentials(h.ng, h.dP), its Object
// coordinates there, and UV and Generated extrapolated linearly over the triangle's plane (the offset's barycentric
// change, as Cycles' du / dv project it: differential_dudv).
[[gnu::noinline, gnu::cold]] inline void AddShiftedGlobals(const SurfaceHit& h, svm::ShaderGlobals& sg) {
    const MeshData& m = *h.mesh;
    const uint32_t* t = &m.triangles[3 * size_t(h.prim)];
    auto vertex = [&](uint32_t v) { return Vec3f(m.vertices[3 * v], m.vertices[3 * v + 1], m.vertices[3 * v + 2]); };
    const Vec3f p0 = vertex(t[0]), e1 = vertex(t[1]) - p0, e2 = vertex(t[2]) - p0;
    const float d00 = Dot(e1, e1), d01 = Dot(e1, e2), d11 = Dot(e2, e2);
    const float det = d00 * d11 - d01 * d01;
    const float inv = det > 0 ? 1.0f / det : 0.0f;
    const svm::BumpOffsets d = svm::BumpDifferentials(h.ng, h.dP);
    for (int k = 0; k < 2; ++k) {
        const Vec3f offset = k == 0 ? d.dx : d.dy;
        const float a = Dot(offset, e1), b = Dot(offset, e2);
        const float db1 = (d11 * a - d01 * b) * inv, db2 = (d00 * b - d01 * a) * inv;
        svm::ShaderGlobals::Shifted& s = sg.shift[k];
        s.p = h.p + offset;
        s.object = ObjectPoint(m, s.p);
        s.uv = sg.uv;
        if (!m.uvs.empty()) {
            const Point2<float>&u0 = m.uvs[t[0]], &u1 = m.uvs[t[1]], &u2 = m.uvs[t[2]];
            s.uv += Vec3f((u1.u - u0.u) * db1 + (u2.u - u0.u) * db2, (u1.v - u0.v) * db1 + (u2.v - u0.v) * db2, 0);
        }
        s.generated = sg.generated;
        if (!m.generated.empty())
            s.generated +=
                (m.generated[t[1]] - m.generated[t[0]]) * db1 + (m.generated[t[2]] - m.generated[t[0]]) * db2;
    }
    sg.shifted = true;
}

// What programs read of the mesh itself (svm/attribute_nodes.h): its attributes at barycentrics b of the triangle of
// vertices v, its object.
inline void SetMeshShaderGlobals(const MeshData& m, const uint32_t (&v)[3], const float (&b)[3],
                                 svm::ShaderGlobals& sg) {
    sg.attributes = &m.attributes;
    for (int k = 0; k < 3; ++k) sg.v[k] = v[k], sg.b[k] = b[k];
    sg.object_info = &m.object_info;
}

// Hit h of a textured material (MakeSurfaceHit ran AddHitExtras: h.mesh and h.incoming are set), found by a ray of
// context `ray` (default: the camera ray that made h).
inline svm::ShaderGlobals HitShaderGlobals(const SurfaceHit& h, const svm::RayContext* ray = nullptr) {
    svm::ShaderGlobals sg;
    sg.p = h.p;
    // The shading normal before a normal map or Bump replaced it (ns_unmapped, where one did): Cycles' sd->N,
    // which the Normal Map and Bump nodes' outputs leave alone (they feed a closure's Normal).
    sg.n = h.mapped ? h.ns_unmapped : h.ns;
    sg.ng = h.ng;
    sg.incoming = Vec3f(h.incoming[0], h.incoming[1], h.incoming[2]);
    sg.uv = h.tc.uv;
    sg.generated = h.tc.generated;
    sg.object = ObjectPoint(*h.mesh, h.p);
    sg.object_normal = ObjectNormal(*h.mesh, sg.n);
    if (h.mesh->has_object_linear) sg.object_linear = h.mesh->object_linear;
    sg.backfacing = h.backfacing;
    sg.ray_length = h.t - h.ray_start;  // Cycles' sd->ray_length: from where the ray starts (a camera's near plane)
    sg.ray = ray ? *ray : svm::CameraRayContext(h.transparent_depth);
    sg.dP = h.dP;
    if (h.dP > 0) AddShiftedGlobals(h, sg);
    SetMeshShaderGlobals(*h.mesh, h.corner, h.bary, sg);
    return sg;
}

// The unit normal of triangle `prim` of mesh m, on the side Blender's winding gives.
inline Vec3f TriangleNormal(const MeshData& m, uint32_t prim) {
    const uint32_t* t = &m.triangles[3 * size_t(prim)];
    auto vertex = [&](uint32_t v) { return Vec3f(m.vertices[3 * v], m.vertices[3 * v + 1], m.vertices[3 * v + 2]); };
    const Vec3f v0 = vertex(t[0]);
    const Vec3f n = Cross(vertex(t[1]) - v0, vertex(t[2]) - v0);
    const float len = Length(n);
    return len > 0 ? n / len : Vec3f(0, 0, 1);
}

// Point p at barycentrics (b1, b2) of triangle `prim` of mesh m, seen from direction `toward` (unit, from the
// surface towards the viewer) at distance `distance`, as Cycles sets up a light sample's or a BSDF ray's point on an
// emitter (shader_setup_from_sample / _from_ray): the flat triangle's normal Ng, the interpolated vertex normals N
// of a smooth mesh (on Ng's side, as MakeSurfaceHit turns them), both facing the viewer.
// `ray`: the context of the ray that found the point (svm::RayContext).
inline svm::ShaderGlobals TriangleShaderGlobals(const MeshData& m, uint32_t prim, float b1, float b2, const Vec3f& p,
                                                const Vec3f& toward, float distance,
                                                const svm::RayContext& ray = svm::LightSampleContext(0)) {
    const uint32_t* t = &m.triangles[3 * size_t(prim)];
    const float b0 = 1 - b1 - b2;
    Vec3f ng = TriangleNormal(m, prim), n = ng;
    if (!m.normals.empty()) {
        const Vec3f smooth = m.normals[t[0]] * b0 + m.normals[t[1]] * b1 + m.normals[t[2]] * b2;
        const float len = Length(smooth);
        if (len > 0) n = Dot(smooth, ng) < 0 ? smooth / -len : smooth / len;
    }
    svm::ShaderGlobals sg;
    sg.backfacing = Dot(ng, toward) < 0;
    if (sg.backfacing) {
        ng = -ng;
        n = -n;
    }
    sg.p = p;
    sg.n = n;
    sg.ng = ng;
    sg.incoming = toward;
    const TextureCoordinates tc = InterpolateTextureCoordinates(m, t[0], t[1], t[2], b0, b1, b2);
    sg.uv = tc.uv;
    sg.generated = tc.generated;
    sg.object = ObjectPoint(m, p);
    sg.object_normal = ObjectNormal(m, n);
    if (m.has_object_linear) sg.object_linear = m.object_linear;
    sg.ray_length = distance;
    SetMeshShaderGlobals(m, {t[0], t[1], t[2]}, {1 - b1 - b2, b1, b2}, sg);
    sg.ray = ray;
    return sg;
}

}  // namespace sphrect::render
