// The surface a camera ray hits, from Embree's answer: point, normals facing the ray, material, and for
// textured or normal-mapped materials the texture coordinates (the normal map or Bump applied to ns).
#pragma once

#include "render/camera.h"
#include "render/embree_rays.h"
#include "render/scene.h"
#include "render/svm/shading_nodes.h"
#include "terminator.h"

namespace sphrect::render {

struct SurfaceHit {
    Vec3f p;      // hit point
    Vec3f ng;     // unit geometric normal, on the side the camera ray came from
    Vec3f ns;     // unit shading normal, flipped with ng
    float t = 0;  // distance along the camera ray
    int material = 0;
    TextureCoordinates tc;    // set only for a textured or normal-mapped material
    Vec3f ns_unmapped;        // where `mapped`: the shading normal before it was replaced (flipped with ns)
    bool mapped = false;      // a normal map, a Bump or ensure_valid_reflection replaced ns (ns_unmapped is set)
    bool backfacing = false;  // materials with a dielectric lobe: the ray hit the side its winding faces away from
    Vec3f tangent;            // anisotropic materials: the mesh's radial tangent (RadialTangent; zero without one)
    // A smooth mesh with a shadow terminator offset (MeshData::shadow_terminator_offset, terminator.h): the offset
    // (0: none) and the smooth surface's lift above p.
    float terminator_offset = 0;
    Vec3f terminator_lift;
    // Textured materials (set by AddHitExtras, left uninitialised otherwise so that other hits pay nothing): the hit's
    // mesh and the direction back along the ray, which node programs read (shader_globals.h).
    const MeshData* mesh;
    float incoming[3];
    float ray_start;            // the ray's tmin: Cycles measures a camera ray's length from the near clipping plane
    uint32_t prim;              // the triangle hit
    float dP;                   // the compact ray differential where the material bumps (CameraFootprint), else 0
    uint8_t transparent_depth;  // the transparent surfaces the camera ray went through before (Light Path node)
    uint32_t corner[3];         // the triangle's vertices and their barycentric weights (mesh attributes)
    float bary[3];
};

// A normal program's world-space normal at hit s, whose geometric and shading normals are ng and ns (on one side,
// either); the result on that side (integrator/bump.cpp: cold, out of line).
Vec3f BumpedShadingNormal(const RenderScene& scene, const svm::NodeProgram& program, const SurfaceHit& s,
                          const Vec3f& ng, const Vec3f& ns);

// The mesh's texture coordinates at barycentrics (b0, b1, b2) of triangle (i0, i1, i2); zero where it has none.
static inline TextureCoordinates InterpolateTextureCoordinates(const MeshData& m, uint32_t i0, uint32_t i1, uint32_t i2,
                                                               float b0, float b1, float b2) {
    TextureCoordinates tc;
    if (!m.uvs.empty()) {
        const Point2<float>& a = m.uvs[i0];
        const Point2<float>& b = m.uvs[i1];
        const Point2<float>& c = m.uvs[i2];
        tc.uv = {a.u * b0 + b.u * b1 + c.u * b2, a.v * b0 + b.v * b1 + c.v * b2, 0};
    }
    if (!m.generated.empty()) tc.generated = m.generated[i0] * b0 + m.generated[i1] * b1 + m.generated[i2] * b2;
    return tc;
}

// m v, and m^T v, for a row-major 3x3 m.
static inline Vec3f Apply3x3(const float (&m)[3][3], const Vec3f& v) {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}
static inline Vec3f Apply3x3Transposed(const float (&m)[3][3], const Vec3f& v) {
    return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z, m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
            m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
}

// Blender's Normal Map node in tangent space (Cycles' svm_node_normal_map): the map's colour c read as
// 2 c - 1 in the frame of the tangent T, the bitangent B = sign cross(N, T) and the normal N (the shading
// normal before it faces the ray), in the object's space, then brought to the world as a normal and mixed with
// N by the strength: normalize(N + (N_map - N) strength).  T is the triangle's dp/du made orthogonal to N and
// sign the handedness of (dp/du, dp/dv): on a triangle with affine UVs, what MikkTSpace's per-vertex tangents
// give (smoothly curved meshes differ slightly).  Object space: with the object's linear map L, a direction
// maps by L^-1 and a normal by L^T (and back by L^-T), which matters where L scales non-uniformly.  A triangle
// with degenerate UVs keeps N.
[[gnu::noinline, gnu::cold]] static Vec3f ApplyNormalMap(const RenderScene& scene, const MeshData& mesh,
                                                         const NormalMap& map, const Vec3f p[3],
                                                         const Point2<float> uv[3], const TextureCoordinates& tc,
                                                         const Vec3f& n_world) {
    const Vec3f e1 = p[1] - p[0], e2 = p[2] - p[0];
    const float du1 = uv[1].u - uv[0].u, dv1 = uv[1].v - uv[0].v, du2 = uv[2].u - uv[0].u, dv2 = uv[2].v - uv[0].v;
    const float det = du1 * dv2 - du2 * dv1;
    if (!(std::abs(det) > 0)) return n_world;
    Vec3f dpdu = (e1 * dv2 - e2 * dv1) / det, dpdv = (e2 * du1 - e1 * du2) / det, n = n_world;
    if (mesh.has_object_linear) {
        dpdu = Apply3x3(mesh.object_linear_inverse, dpdu);
        dpdv = Apply3x3(mesh.object_linear_inverse, dpdv);
        n = Apply3x3Transposed(mesh.object_linear, n);
        const float ln = Length(n);
        if (!(ln > 0)) return n_world;
        n = n / ln;
    }
    Vec3f t = dpdu - n * Dot(n, dpdu);
    const float lt = Length(t);
    if (!(lt > 0)) return n_world;
    t = t / lt;
    const Vec3f b = Cross(n, t) * (Dot(Cross(n, t), dpdv) < 0 ? -1.0f : 1.0f);
    const Spectrum c = TextureColor(EvalTextureAt(scene.images, map.lookup, tc));
    Vec3f mapped = t * (2 * c.x - 1) + b * (2 * c.y - 1) + n * (2 * c.z - 1);
    if (mesh.has_object_linear) mapped = Apply3x3Transposed(mesh.object_linear_inverse, mapped);
    float lm = Length(mapped);
    if (!(lm > 0)) return n_world;
    mapped = mapped / lm;
    if (map.strength != 1) mapped = n_world + (mapped - n_world) * map.strength;
    lm = Length(mapped);
    return lm > 0 ? mapped / lm : n_world;
}

// Cycles' default tangent (primitive_tangent: what an unlinked Tangent input reads), radial about the object's Z axis:
// (-(g.y - 0.5), g.x - 0.5, 0) of the Generated coordinates g, taken to the world as a normal
// (object_normal_transform, L^-T) and made orthogonal to the shading normal n.  Zero where it is undefined (on
// the axis).
static inline Vec3f RadialTangent(const MeshData& m, const Vec3f& generated, const Vec3f& n) {
    Vec3f t(-(generated.y - 0.5f), generated.x - 0.5f, 0);
    if (m.has_object_linear) t = Apply3x3Transposed(m.object_linear_inverse, t);
    const Vec3f across = Cross(t, n);
    const float len = Length(across);
    return len > 0 ? Cross(n, across / len) : Vec3f();
}

// What a textured, normal-mapped or dielectric material needs of the hit (out of line: cold for most scenes):
// texture coordinates, the normal map applied to ns, and which side of the triangle the ray hit.
[[gnu::noinline]] static void AddHitExtras(const RenderScene& scene, const MeshData& m, const Bsdf& material,
                                           uint32_t prim, const uint32_t (&i)[3], const Vec3f (&p)[3], float b0,
                                           float b1, float b2, const Ray& ray, const Vec3f& ng, Vec3f& ns,
                                           SurfaceHit& s) {
    // The side Blender's winding gives (Embree's Ng may point the other way).
    const float side = Dot(Cross(p[1] - p[0], p[2] - p[0]), ng) < 0 ? -1.0f : 1.0f;
    s.backfacing = Dot(ng, ray.d) * side > 0;
    if (!material.textured && !material.normal_mapped && !material.anisotropic) return;
    s.mesh = &m;
    s.incoming[0] = -ray.d.x, s.incoming[1] = -ray.d.y, s.incoming[2] = -ray.d.z;
    s.ray_start = ray.tmin;
    s.corner[0] = i[0], s.corner[1] = i[1], s.corner[2] = i[2];
    s.bary[0] = b0, s.bary[1] = b1, s.bary[2] = b2;
    s.transparent_depth = 0;
    s.tc = InterpolateTextureCoordinates(m, i[0], i[1], i[2], b0, b1, b2);
    if (material.anisotropic && !m.generated.empty()) s.tangent = RadialTangent(m, s.tc.generated, ns);
    s.prim = prim;
    const NormalMap& nm = scene.normal_maps[size_t(s.material)];
    s.dP = nm.differentials ? CameraFootprint(scene.camera, ray.d, s.t) : 0.0f;
    if (material.normal_mapped && !nm.program.empty()) {  // a Bump node's graph
        s.ns_unmapped = ns;
        s.mapped = true;
        ns = BumpedShadingNormal(scene, nm.program, s, ng, ns);
    } else if (material.normal_mapped && !m.uvs.empty()) {
        // In the frame of Blender's winding, then back.
        const Point2<float> uv[3] = {m.uvs[i[0]], m.uvs[i[1]], m.uvs[i[2]]};
        s.ns_unmapped = ns;
        s.mapped = true;
        ns = ApplyNormalMap(scene, m, scene.normal_maps[size_t(s.material)], p, uv, s.tc, ns * side) * side;
        // Cycles 3.4 hands a closure's Normal input through ensure_valid_reflection (svm_node_closure_bsdf): a map
        // that tilts the normal away from the viewer is turned back (seen from the facing side).
        const float facing = Dot(ng, ray.d) > 0 ? -1.0f : 1.0f;
        ns = svm::EnsureValidReflection(ng * facing, -ray.d, ns * facing) * facing;
    }
}

// A smooth normal that fails ensure_valid_reflection's test (seen from the ray's side, `facing`): the closures' normal
// turned as Cycles turns it, the interpolated one kept as sd->N (ns_unmapped, as under a normal map).  Out of line:
// rare.
[[gnu::noinline, gnu::cold]] static void TurnSmoothNormal(const Ray& ray, const Vec3f& ng, float facing, Vec3f& ns,
                                                          SurfaceHit& s) {
    s.ns_unmapped = ns;
    s.mapped = true;
    ns = svm::EnsureValidReflection(ng * facing, -ray.d, ns * facing) * facing;
}

// kGlossy: the kernel that can meet textured, normal-mapped and dielectric materials (RenderScene::Commit sends
// scenes using them to it); the diffuse kernel has none of their code.
template <bool kGlossy>
static inline SurfaceHit MakeSurfaceHit(const RenderScene& scene, const Ray& ray, const RTCRayHit& rh) {
    const MeshData& m = scene.meshes[rh.hit.geomID];
    const uint32_t tri = rh.hit.primID;
    SurfaceHit s;
    s.t = rh.ray.tfar;
    s.material = m.material_ids.empty() ? 0 : m.material_ids[tri];
    Vec3f ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);  // Embree's unnormalised geometric normal
    const float len = Length(ng);
    ng = len > 0 ? ng / len : -ray.d;
    Vec3f ns = ng;
    const bool from_behind = Dot(ng, ray.d) > 0;  // the normals are turned to face the ray at the end
    const Bsdf* extras = nullptr;                 // the material, when it needs AddHitExtras
    if constexpr (kGlossy) {
        const Bsdf& material = scene.bsdfs[size_t(s.material)];
        if (material.textured || material.normal_mapped || material.has_dielectric || material.anisotropic)
            extras = &material;
    }
    if (m.normals.empty() && !extras) {
        s.p = ray.o + ray.d * s.t;  // flat shading: no vertex fetch needed
    } else {
        // Interpolated shading normal (and the point from the barycentrics, which is more precise).
        const uint32_t i[3] = {m.triangles[3 * tri], m.triangles[3 * tri + 1], m.triangles[3 * tri + 2]};
        auto vertex = [&](uint32_t k) {
            return Vec3f(m.vertices[3 * k], m.vertices[3 * k + 1], m.vertices[3 * k + 2]);
        };
        const Vec3f p[3] = {vertex(i[0]), vertex(i[1]), vertex(i[2])};
        const float b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1 - b1 - b2;
        s.p = p[0] * b0 + p[1] * b1 + p[2] * b2;
        if (!m.normals.empty()) {
            const Vec3f n = m.normals[i[0]] * b0 + m.normals[i[1]] * b1 + m.normals[i[2]] * b2;
            const float ln = Length(n);
            if (ln > 0) ns = n / ln;
            if (Dot(ns, ng) < 0) ns = -ns;  // shading normal on the geometric normal's side
        }
        if (extras) AddHitExtras(scene, m, *extras, tri, i, p, b0, b1, b2, ray, ng, ns, s);
        // Cycles 3.4 passes every closure's normal through ensure_valid_reflection (svm_node_closure_bsdf), the
        // interpolated one too: where a smooth normal would reflect the viewer below the surface (grazing views
        // near a low-poly silhouette) the closures' normal is turned towards Ng, while sd->N -- what shader nodes
        // read and what tells reflection from transmission -- stays the interpolated one, as for a normal map
        // (ns_unmapped).  A mapped normal has been turned already (AddHitExtras).
        if (!m.normals.empty() && !s.mapped) {
            const float facing = from_behind ? -1.0f : 1.0f;
            if (!svm::ReflectionIsValid(ng * facing, -ray.d, ns * facing)) TurnSmoothNormal(ray, ng, facing, ns, s);
        }
        if (m.shadow_terminator_offset > 0 && !m.normals.empty()) {
            const Vec3f n[3] = {m.normals[i[0]], m.normals[i[1]], m.normals[i[2]]};
            const float b[3] = {b0, b1, b2};
            s.terminator_offset = m.shadow_terminator_offset;
            s.terminator_lift = SmoothSurfaceLift(p, n, b, from_behind ? -ng : ng);
        }
    }
    // Surfaces are two-sided: both normals face the incoming ray.
    if (from_behind) {
        ng = -ng;
        ns = -ns;
        s.ns_unmapped = -s.ns_unmapped;
    }
    s.ng = ng;
    s.ns = ns;
    return s;
}

}  // namespace sphrect::render
