// Meshes into Embree (Cycles: scene/mesh.cpp): their arrays checked and copied, and the occlusion filter that
// lets shadow rays through transparent materials.
#include <cmath>
#include <cstring>
#include <string>

#include "embree_rays.h"
#include "scene.h"
#include "scene_checks.h"

namespace sphrect::render {

void RenderScene::SetLastMeshShadowTerminatorOffset(float offset) {
    RequireNotCommitted();
    if (meshes.empty()) Fail("no mesh to set the shadow terminator offset of");
    if (!(offset >= 0 && offset <= 1))
        Fail("mesh '" + meshes.back().name + "': shadow_terminator_offset must be in [0, 1]");
    meshes.back().shadow_terminator_offset = offset;
}

void RenderScene::SetLastMeshObjectLinear(const float linear[3][3], const float inverse[3][3],
                                          const Vec3f& translation) {
    RequireNotCommitted();
    if (meshes.empty()) return;
    MeshData& m = meshes.back();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            if (!std::isfinite(linear[r][c]) || !std::isfinite(inverse[r][c])) Fail("object_linear must be finite");
            m.object_linear[r][c] = linear[r][c];
            m.object_linear_inverse[r][c] = inverse[r][c];
        }
    if (!std::isfinite(translation.x) || !std::isfinite(translation.y) || !std::isfinite(translation.z))
        Fail("object_translation must be finite");
    m.object_translation = translation;
    m.has_object_linear = true;
    m.object_info.location = translation;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) m.object_info.normal_to_world[r][c] = inverse[c][r];  // L^-T
}

void RenderScene::SetLastMeshAttribute(size_t slot, std::vector<float> values, bool fac_is_x) {
    RequireNotCommitted();
    if (meshes.empty()) return;
    MeshData& m = meshes.back();
    if (values.size() != 4 * m.num_vertices) Fail("mesh '" + m.name + "': an attribute needs 4 values per vertex");
    for (float v : values)
        if (!std::isfinite(v)) Fail("mesh '" + m.name + "': an attribute value is not finite");
    if (slot > (size_t(1) << 20)) Fail("mesh '" + m.name + "': attribute slot out of range");
    if (m.attributes.size() <= slot) m.attributes.resize(slot + 1);
    m.attributes[slot].values = std::move(values);
    m.attributes[slot].fac_is_x = fac_is_x;
}

void RenderScene::SetLastMeshObjectInfo(const Vec3f& color, float alpha, float index, float random, bool reversed) {
    RequireNotCommitted();
    if (meshes.empty()) return;
    if (!IsFinite(color) || !std::isfinite(alpha) || !std::isfinite(index) || !std::isfinite(random))
        Fail("mesh '" + meshes.back().name + "': object info must be finite");
    svm::ObjectInfo& o = meshes.back().object_info;
    o.color = color, o.alpha = alpha, o.index = index, o.random = random, o.reversed = reversed;
}

void CheckTriangleMesh(const std::string& who, const float* vertices, size_t nv, const int32_t* triangles, size_t nt) {
    if (nv > (size_t(1) << 31) || nt > (size_t(1) << 31)) Fail(who + " is too large");
    // Embree silently drops triangles with a coordinate beyond its valid range, +-1.844e18.
    constexpr float kEmbreeMaxCoordinate = 1.844e18f;
    for (size_t i = 0; i < 3 * nv; ++i) {
        if (!std::isfinite(vertices[i]))
            Fail(who + ": vertex " + std::to_string(i / 3) + " is not finite (NaN or inf)");
        if (std::abs(vertices[i]) >= kEmbreeMaxCoordinate)
            Fail(who + ": vertex " + std::to_string(i / 3) + " lies beyond +-1.844e18, outside Embree's range");
    }
    for (size_t i = 0; i < 3 * nt; ++i)
        if (triangles[i] < 0 || size_t(triangles[i]) >= nv)
            Fail(who + ": triangle " + std::to_string(i / 3) + " has vertex index " + std::to_string(triangles[i]) +
                 " outside [0, " + std::to_string(nv) + ")");
}

RTCGeometry NewTriangleGeometry(RTCDevice device, const std::string& who, const float* vertices, size_t nv,
                                const int32_t* triangles, size_t nt, const float** vertex_buffer,
                                const uint32_t** index_buffer) {
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree pads its own buffers for its SIMD loads; one memcpy each.
    auto* vb = static_cast<float*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
    auto* ib = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), nt));
    if (!vb || !ib) {
        rtcReleaseGeometry(geom);
        throw std::runtime_error(who + ": Embree could not allocate its buffers");
    }
    if (nv) std::memcpy(vb, vertices, 3 * nv * sizeof(float));
    if (nt) std::memcpy(ib, triangles, 3 * nt * sizeof(uint32_t));
    if (vertex_buffer) *vertex_buffer = vb;
    if (index_buffer) *index_buffer = ib;
    return geom;
}

void RenderScene::AddMesh(const std::string& name, const float* vertices, size_t nv, const int32_t* triangles,
                          size_t nt, const float* normals, const int32_t* material_ids, const float* uvs,
                          const float* generated, uint8_t visibility) {
    RequireNotCommitted();
    const std::string who = "mesh '" + name + "'";
    CheckTriangleMesh(who, vertices, nv, triangles, nt);
    MeshData m;
    m.name = name;
    m.num_vertices = nv;
    m.num_triangles = nt;
    if (normals) {
        m.normals.resize(nv);
        for (size_t i = 0; i < nv; ++i) {
            const Vec3f n(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
            if (!IsFinite(n)) Fail(who + ": normal " + std::to_string(i) + " is not finite");
            const float len = Length(n);
            m.normals[i] = len > 0 ? n / len : Vec3f();  // zero: fall back to the geometric normal
        }
    }
    if (uvs) {
        m.uvs.resize(nv);
        for (size_t i = 0; i < nv; ++i) {
            m.uvs[i] = {uvs[2 * i], uvs[2 * i + 1]};
            if (!std::isfinite(m.uvs[i].u) || !std::isfinite(m.uvs[i].v))
                Fail(who + ": uv " + std::to_string(i) + " is not finite");
        }
    }
    if (generated) {
        m.generated.resize(nv);
        for (size_t i = 0; i < nv; ++i) {
            m.generated[i] = {generated[3 * i], generated[3 * i + 1], generated[3 * i + 2]};
            if (!IsFinite(m.generated[i])) Fail(who + ": generated coordinate " + std::to_string(i) + " is not finite");
        }
    }
    if (material_ids) {
        m.material_ids.assign(material_ids, material_ids + nt);
        for (size_t i = 0; i < nt; ++i)
            if (material_ids[i] < 0) Fail(who + ": triangle " + std::to_string(i) + " has a negative material id");
    }
    if (visibility > kRayAll) Fail(who + ": visibility has bits beyond the ray kinds'");
    m.visibility = visibility;
    if (nt == 0) return;  // nothing to intersect (Embree refuses empty buffers)
    RTCGeometry geom = NewTriangleGeometry(device_, who, vertices, nv, triangles, nt, &m.vertices, &m.triangles);
    // Every bit for a mesh visible to every ray kind: whatever a ray's mask, it sees it.
    rtcSetGeometryMask(geom, visibility == kRayAll ? 0xffffffffu : visibility);
    rtcCommitGeometry(geom);
    const unsigned id = rtcAttachGeometry(rtc_scene, geom);
    rtcReleaseGeometry(geom);
    if (id != meshes.size()) throw std::logic_error("unexpected Embree geometry id");
    meshes.push_back(std::move(m));
}

namespace {

// The occlusion filter of meshes with transparent materials (ShadowRayContext, embree_rays.h).
void LetThroughTransparent(const RTCFilterFunctionNArguments* args) {
    const auto* ctx = reinterpret_cast<const ShadowRayContext*>(args->context);
    if (!ctx->crossed_transparent) return;
    const auto* scene = static_cast<const RenderScene*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const unsigned geom = RTCHitN_geomID(args->hit, args->N, i), prim = RTCHitN_primID(args->hit, args->N, i);
        if (!scene->MayBeTransparent(scene->meshes[geom], prim)) continue;
        args->valid[i] = 0;
        ctx->crossed_transparent[RTCRayN_id(args->ray, args->N, i)] = 1;
    }
}

}  // namespace

void RenderScene::LetRaysThroughTransparentMeshes() {
    has_transparency = false;
    for (size_t id = 0; id < meshes.size(); ++id) {
        const MeshData& m = meshes[id];
        bool transparent = false;
        for (size_t t = 0; t < m.num_triangles && !transparent; ++t) transparent = MayBeTransparent(m, uint32_t(t));
        if (!transparent) continue;
        has_transparency = true;
        RTCGeometry geom = rtcGetGeometry(rtc_scene, unsigned(id));
        rtcSetGeometryUserData(geom, this);
        rtcSetGeometryOccludedFilterFunction(geom, &LetThroughTransparent);
        rtcCommitGeometry(geom);
    }
}

}  // namespace sphrect::render
