#include "scene.h"

#include "embree_rays.h"
#include "scene_checks.h"

#include <cmath>
#include <algorithm>
#include <array>
#include <cstring>
#include <optional>
#include <stdexcept>

namespace sphrect::render {

namespace {

// Why an area light of this area is skipped ("" if it is not).
std::string SkippedForArea(const std::string& what, float area) {
    if (!(area > 0)) return what + " with zero area skipped";
    if (!std::isfinite(area)) return what + " whose area overflows float skipped";
    return {};
}

struct Triangle {
    Vec3f v[3];
};

// The rectangle two triangles form when they share an edge (two vertices at the same positions)
// and their unshared vertices p, q are opposite corners of a rectangle: a right angle at p and
// q = p + ex + ey, both within float tolerance (a scaled Blender plane, triangulated).  ey is
// then made exactly orthogonal to ex.  nullopt otherwise.
std::optional<RectLight<float>> RectangleOfPair(const Triangle& a, const Triangle& b) {
    constexpr float kTolerance = 1e-5f;  // relative; float rounding of transformed vertices is ~1e-7
    auto same = [](const Vec3f& u, const Vec3f& v) { return u.x == v.x && u.y == v.y && u.z == v.z; };
    auto shared = [&](const Vec3f& v, const Triangle& t) {
        return same(v, t.v[0]) || same(v, t.v[1]) || same(v, t.v[2]);
    };
    int pa = -1, pb = -1, na = 0, nb = 0;
    for (int i = 0; i < 3; ++i) {
        if (!shared(a.v[i], b)) pa = i, ++na;
        if (!shared(b.v[i], a)) pb = i, ++nb;
    }
    if (na != 1 || nb != 1) return std::nullopt;
    const Vec3f p = a.v[pa], q = b.v[pb];
    Vec3f ex = a.v[(pa + 1) % 3] - p, ey = a.v[(pa + 2) % 3] - p;
    const float lx = Length(ex), ly = Length(ey);
    if (!(lx > 0 && ly > 0)) return std::nullopt;
    if (std::abs(Dot(ex, ey)) > kTolerance * lx * ly) return std::nullopt;
    if (Length(p + ex + ey - q) > kTolerance * (lx + ly)) return std::nullopt;
    ey = ey - ex * (Dot(ex, ey) / Dot(ex, ex));
    return RectLight<float>{p, ex, ey, true};
}

// How many mesh lights (area_lights[first, end)) have the centre and area of another one:
// duplicated surfaces, of which Embree reports one hit.  Sorted keys, equal neighbours counted
// (cache-friendly: ~0.1 s for a million lights, where a hash set took several times that).
size_t CountCoincidingMeshLights(const std::vector<AreaLight>& lights, size_t first) {
    std::vector<std::array<float, 4>> keys;
    keys.reserve(lights.size() - first);
    for (size_t i = first; i < lights.size(); ++i) {
        const AreaLight& l = lights[i];
        keys.push_back({l.center.x, l.center.y, l.center.z, l.area});
    }
    std::sort(keys.begin(), keys.end());
    size_t n = 0;
    for (size_t i = 1; i < keys.size(); ++i) n += keys[i] == keys[i - 1];
    return n;
}

}  // namespace

std::vector<std::string> SceneFeatures::Names() const {
    std::vector<std::string> n;
    if (glossy) n.push_back("glossy");
    if (medium) n.push_back("medium");
    if (dof) n.push_back("dof");
    if (ellipse_lights) n.push_back("ellipse_lights");
    if (delta_lights) n.push_back("delta_lights");
    if (orthographic) n.push_back("orthographic");
    if (background) n.push_back("background");
    if (emissive_meshes) n.push_back("emissive_meshes");
    if (textures) n.push_back("textures");
    if (normal_maps) n.push_back("normal_maps");
    if (transparency) n.push_back("transparency");
    return n;
}

RenderScene::RenderScene() {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("Embree: could not create a device");
    rtc_scene = rtcNewScene(device_);
    rtcSetSceneBuildQuality(rtc_scene, RTC_BUILD_QUALITY_HIGH);
}

RenderScene::~RenderScene() {
    analytic_light_finder.Release();
    if (rtc_scene) rtcReleaseScene(rtc_scene);
    if (device_) rtcReleaseDevice(device_);
}

void RenderScene::RequireNotCommitted() const {
    if (committed_) Fail("the scene is already committed");
}

void ValidateCamera(const CameraModel& c) {
    if (c.width <= 0 || c.height <= 0 || c.width > kMaxImageSide || c.height > kMaxImageSide ||
        int64_t(c.width) * c.height > kMaxImagePixels)
        Fail("camera resolution " + std::to_string(c.width) + " x " + std::to_string(c.height) +
             " is out of range (each side 1.." + std::to_string(kMaxImageSide) + ", at most 2^" +
             std::to_string(kMaxImagePixelsLog2) + " pixels)");
    for (const auto& row : c.to_world)
        for (float x : row)
            if (!std::isfinite(x)) Fail("camera matrix must be finite");
    const Vec3f cx = c.VectorToWorld({1, 0, 0}), cy = c.VectorToWorld({0, 1, 0}), cz = c.VectorToWorld({0, 0, 1});
    if (!(std::abs(Dot(Cross(cx, cy), cz)) > 1e-12f)) Fail("camera matrix is singular");
    if (!(c.half_width > 0 && c.half_height > 0 && std::isfinite(c.half_width) && std::isfinite(c.half_height)))
        Fail("camera image plane must have a positive, finite size (check lens, sensor and ortho_scale)");
    if (!std::isfinite(c.offset_x) || !std::isfinite(c.offset_y)) Fail("camera shift must be finite");
    if (!(c.aperture_radius >= 0) || !std::isfinite(c.aperture_radius)) Fail("aperture_radius must be >= 0");
    if (c.aperture_radius > 0 && !(c.focus_distance > 0 && std::isfinite(c.focus_distance)))
        Fail("focus_distance must be positive when aperture_radius > 0");
    if (!(c.clip_start >= 0) || !(c.clip_end > c.clip_start)) Fail("camera clipping needs 0 <= clip_start < clip_end");
}

void RenderScene::SetCamera(const CameraModel& c) {
    RequireNotCommitted();
    ValidateCamera(c);
    camera = c;
    camera_set_ = true;
}

void RenderScene::SetBackground(const Spectrum& radiance) {
    RequireNotCommitted();
    CheckColor("world background", radiance);
    background = radiance;
}

void RenderScene::SetMedium(const Spectrum& sigma_s, const Spectrum& sigma_a, float g) {
    RequireNotCommitted();
    CheckColor("medium sigma_s", sigma_s);
    CheckColor("medium sigma_a", sigma_a);
    if (!(g > -1 && g < 1)) Fail("medium anisotropy g must be in (-1, 1)");
    medium.sigma_s = sigma_s;
    medium.sigma_t = sigma_s + sigma_a;
    medium.g = g;
    medium.sigma_sampling = (medium.sigma_t.x + medium.sigma_t.y + medium.sigma_t.z) / 3;
    has_medium = medium.sigma_sampling > 0;
}

void RenderScene::SetFilmTransparent(bool transparent) {
    RequireNotCommitted();
    film_transparent = transparent;
}

int RenderScene::AddImage(const std::string& name, int width, int height, int channels, const uint8_t* bytes,
                          const float* floats, bool srgb) {
    return AddImage(MakeImage(name, width, height, channels, bytes, floats, srgb));
}

int RenderScene::AddImage(Image image) {
    RequireNotCommitted();
    images.push_back(std::move(image));
    return int(images.size()) - 1;
}

void RenderScene::SetLastMeshObjectLinear(const float linear[3][3], const float inverse[3][3]) {
    RequireNotCommitted();
    if (meshes.empty()) return;
    MeshData& m = meshes.back();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            if (!std::isfinite(linear[r][c]) || !std::isfinite(inverse[r][c])) Fail("object_linear must be finite");
            m.object_linear[r][c] = linear[r][c];
            m.object_linear_inverse[r][c] = inverse[r][c];
        }
    m.has_object_linear = true;
}

void RenderScene::AddMesh(const std::string& name, const float* vertices, size_t nv, const int32_t* triangles,
                          size_t nt, const float* normals, const int32_t* material_ids, const float* uvs,
                          const float* generated) {
    RequireNotCommitted();
    const std::string who = "mesh '" + name + "'";
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
    if (nt == 0) return;  // nothing to intersect (Embree refuses empty buffers)
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
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
    m.vertices = vb;
    m.triangles = ib;
    rtcCommitGeometry(geom);
    const unsigned id = rtcAttachGeometry(rtc_scene, geom);
    rtcReleaseGeometry(geom);
    if (id != meshes.size()) throw std::logic_error("unexpected Embree geometry id");
    meshes.push_back(std::move(m));
}

std::string RenderScene::AddRectLight(const Vec3f& corner, const Vec3f& ex, const Vec3f& ey, const Spectrum& radiance,
                                      bool two_sided, bool visible) {
    RequireNotCommitted();
    CheckColor("rectangle light radiance", radiance);
    const std::string problem = ValidateRectLight(RectLight<float>{corner, ex, ey, two_sided});
    if (!problem.empty()) Fail(problem);
    const std::string skipped = SkippedForArea("rectangle light", Length(Cross(ex, ey)));
    if (!skipped.empty()) return skipped;
    if (IsBlack(radiance)) return "rectangle light with zero radiance skipped";
    area_lights.push_back(MakeRectAreaLight(corner, ex, ey, radiance, two_sided, visible));
    return {};
}

std::string RenderScene::AddEllipseLight(const Vec3f& center, const Vec3f& ax, const Vec3f& ay,
                                         const Spectrum& radiance, bool two_sided, bool visible) {
    RequireNotCommitted();
    CheckColor("ellipse light radiance", radiance);
    CheckVector("ellipse light centre", center);
    CheckVector("ellipse light axes", ax);
    CheckVector("ellipse light axes", ay);
    const float la = Length(ax), lb = Length(ay);
    if (la > 0 && lb > 0 && std::abs(Dot(ax, ay)) > 1e-4f * la * lb)
        Fail("ellipse light axes axis_x and axis_y must be orthogonal");
    const std::string skipped = SkippedForArea("ellipse light", Length(Cross(ax, ay)));
    if (!skipped.empty()) return skipped;
    if (IsBlack(radiance)) return "ellipse light with zero radiance skipped";
    area_lights.push_back(MakeEllipseAreaLight(center, ax, ay, radiance, two_sided, visible));
    return {};
}

void RenderScene::AddPointLight(const Vec3f& position, const Spectrum& intensity) {
    RequireNotCommitted();
    CheckVector("point light position", position);
    CheckColor("point light intensity", intensity);
    DeltaLight l;
    l.kind = DeltaKind::Point;
    l.position = position;
    l.power = intensity;
    delta_lights.push_back(l);
}

void RenderScene::AddSpotLight(const Vec3f& position, const Vec3f& direction, const Spectrum& intensity,
                               float spot_size, float spot_blend) {
    RequireNotCommitted();
    CheckVector("spot light position", position);
    CheckColor("spot light intensity", intensity);
    if (!IsFinite(direction) || !(Length(direction) > 0)) Fail("spot light direction must be a non-zero vector");
    if (!(spot_size > 0 && spot_size <= 2 * kPi)) Fail("spot_size must be in (0, 2 pi]");
    if (!(spot_blend >= 0 && spot_blend <= 1)) Fail("spot_blend must be in [0, 1]");
    DeltaLight l;
    l.kind = DeltaKind::Spot;
    l.position = position;
    l.axis = Normalize(direction);
    l.power = intensity;
    l.cos_half_angle = std::cos(std::min(spot_size, kPi) / 2);
    l.spot_smooth = (1 - l.cos_half_angle) * spot_blend;
    delta_lights.push_back(l);
}

void RenderScene::AddSunLight(const Vec3f& direction, const Spectrum& irradiance) {
    RequireNotCommitted();
    CheckColor("sun irradiance", irradiance);
    if (!IsFinite(direction) || !(Length(direction) > 0)) Fail("sun direction must be a non-zero vector");
    DeltaLight l;
    l.kind = DeltaKind::Sun;
    l.axis = -Normalize(direction);  // towards the sun
    l.power = irradiance;
    delta_lights.push_back(l);
}

size_t RenderScene::NumTriangles() const {
    size_t n = 0;
    for (const auto& m : meshes) n += m.num_triangles;
    return n;
}

void RenderScene::Commit() {
    RequireNotCommitted();
    if (!camera_set_) Fail("the scene has no camera");
    if (NumTriangles() == 0 && area_lights.empty() && delta_lights.empty())
        Fail("empty scene: no triangles and no lights");
    if (bsdfs.empty()) AddMaterial(Material{});
    for (const auto& m : meshes)
        for (size_t i = 0; i < m.material_ids.size(); ++i)
            if (size_t(m.material_ids[i]) >= bsdfs.size())
                Fail("mesh '" + m.name + "': triangle " + std::to_string(i) + " uses material " +
                     std::to_string(m.material_ids[i]) + " but the scene has " + std::to_string(bsdfs.size()) +
                     " materials");
    LetRaysThroughTransparentMeshes();
    rtcCommitScene(rtc_scene);
    AddMeshLights();
    analytic_light_finder.Build(device_, area_lights, num_analytic_lights);
    std::vector<double> powers;
    for (const AreaLight& l : area_lights) {
        powers.push_back(AreaLightPower(l));
        medium_centres.push_back(l.center);
    }
    light_selector.Build(powers);
    for (const DeltaLight& d : delta_lights) {
        if (d.kind == DeltaKind::Sun) continue;
        powers.push_back(4.0 * double(Luminance(d.power)));  // flux 4 pi I, over pi like AreaLightPower
        medium_centres.push_back(d.position);
    }
    medium_centre_selector.Build(powers);
    sun_lights.clear();
    for (size_t i = 0; i < delta_lights.size(); ++i)
        if (delta_lights[i].kind == DeltaKind::Sun) sun_lights.push_back(uint32_t(i));
    features_ = {};
    film_alpha = film_transparent;
    // A glossy material only matters when some triangle uses it.
    std::vector<bool> used(bsdfs.size(), false);
    for (const auto& m : meshes) {
        if (m.num_triangles == 0) continue;
        if (m.material_ids.empty()) used[0] = true;
        for (int32_t id : m.material_ids) used[id] = true;
    }
    for (size_t i = 0; i < bsdfs.size(); ++i) {
        features_.glossy |= used[i] && bsdfs[i].glossy;
        features_.textures |= used[i] && bsdfs[i].textured;
        features_.normal_maps |= used[i] && bsdfs[i].normal_mapped;
        // Textures, normal maps (their bump shadowing) and back faces of dielectrics: the glossy kernel's (BsdfAtHit).
        features_.glossy |= used[i] && (bsdfs[i].textured || bsdfs[i].normal_mapped);
        film_alpha |= used[i] && bsdfs[i].holdout > 0;
    }
    CheckTextureCoordinates();
    features_.medium = has_medium;
    features_.dof = camera.aperture_radius > 0 && !camera.orthographic;
    features_.orthographic = camera.orthographic;
    for (const auto& l : area_lights) features_.ellipse_lights |= l.shape == AreaShape::Ellipse;
    features_.delta_lights = !delta_lights.empty();
    features_.background = !IsBlack(background);
    features_.emissive_meshes = has_mesh_lights;
    features_.transparency = has_transparency;
    if (has_transparency && has_medium)
        warnings.push_back(
            "transparent surfaces in a medium: a camera ray that goes through one weights its "
            "single scattering in front of the surface by the surface's transparency too (approximate)");
    committed_ = true;
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

void RenderScene::CheckTextureCoordinates() {
    for (const MeshData& m : meshes) {
        std::vector<bool> seen(bsdfs.size(), false);
        auto check = [&](int32_t id) {
            if (seen[size_t(id)]) return;
            seen[size_t(id)] = true;
            const Material& r = materials[size_t(id)];
            const NormalMap& nm = normal_maps[size_t(id)];
            // A normal map's tangents come from the UVs, whichever coordinates its image reads.
            const bool wants_uv = r.ReadsCoordinates(false) || nm.lookup.bound();
            if (wants_uv && m.uvs.empty())
                warnings.push_back("mesh '" + m.name + "': material " + std::to_string(id) +
                                   " reads UV coordinates the mesh does not have (0, 0 used, as Cycles does)");
            if (bsdfs[size_t(id)].anisotropic && m.generated.empty())
                warnings.push_back("mesh '" + m.name + "': material " + std::to_string(id) +
                                   " is anisotropic but the mesh has no generated coordinates for its radial tangent "
                                   "(an arbitrary tangent used)");
            if ((r.ReadsCoordinates(true) || (nm.lookup.bound() && nm.lookup.generated)) && m.generated.empty())
                warnings.push_back("mesh '" + m.name + "': material " + std::to_string(id) +
                                   " reads generated coordinates the mesh does not have (0 used)");
        };
        if (m.material_ids.empty()) check(0);
        for (int32_t id : m.material_ids) check(id);
    }
}

void RenderScene::BuildLightTree() const {
    if (!committed_) Fail("the light tree needs a committed scene");
    std::call_once(light_tree_once_, [this] {
        TreeEmitters emitters = CollectTreeEmitters(area_lights, delta_lights);
        light_tree_.Build(emitters.bounds);
        light_tree_refs_ = std::move(emitters.refs);
    });
}

// Every triangle whose material emits becomes an area light (on_mesh), except that two
// consecutive triangles of one material forming an exact rectangle (RectangleOfPair: how
// Blender triangulates a quad) become one rectangle light, sampled by the rectangle
// techniques.  Zero-area triangles are skipped and counted in one warning.
void RenderScene::AddMeshLights() {
    num_analytic_lights = area_lights.size();
    size_t emissive = 0;  // at most one light each: reserved once (a million lights are ~300 MB)
    for (const MeshData& m : meshes)
        for (size_t i = 0; i < m.num_triangles; ++i)
            emissive += !IsBlack(bsdfs[m.material_ids.empty() ? 0 : m.material_ids[i]].emission);
    area_lights.reserve(area_lights.size() + emissive);
    size_t skipped = 0;
    for (MeshData& m : meshes) {
        auto material_of = [&](size_t i) { return m.material_ids.empty() ? 0 : m.material_ids[i]; };
        bool emits = false;
        for (size_t i = 0; i < m.num_triangles && !emits; ++i) emits = !IsBlack(bsdfs[material_of(i)].emission);
        if (!emits) continue;
        auto triangle = [&](size_t i) {
            Triangle t;
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = m.triangles[3 * i + k];
                t.v[k] = Vec3f(m.vertices[3 * v], m.vertices[3 * v + 1], m.vertices[3 * v + 2]);
            }
            return t;
        };
        m.triangle_light.assign(m.num_triangles, -1);
        for (size_t i = 0; i < m.num_triangles; ++i) {
            const Spectrum& le = bsdfs[material_of(i)].emission;
            if (IsBlack(le)) continue;
            const Triangle t = triangle(i);
            const int index = int(area_lights.size());
            if (i + 1 < m.num_triangles && material_of(i + 1) == material_of(i)) {
                if (const auto rect = RectangleOfPair(t, triangle(i + 1))) {
                    area_lights.push_back(MakeRectAreaLight(rect->corner, rect->ex, rect->ey, le, true, true));
                    area_lights.back().on_mesh = true;
                    m.triangle_light[i] = m.triangle_light[i + 1] = index;
                    ++i;
                    continue;
                }
            }
            const AreaLight l = MakeTriangleAreaLight(t.v[0], t.v[1], t.v[2], le);
            if (!(l.area > 0) || !std::isfinite(l.area) || !IsFinite(l.n)) {
                ++skipped;
                continue;
            }
            area_lights.push_back(l);
            m.triangle_light[i] = index;
        }
    }
    has_mesh_lights = area_lights.size() > num_analytic_lights;
    if (skipped)
        warnings.push_back(std::to_string(skipped) + " emissive triangle" + (skipped > 1 ? "s" : "") +
                           " with zero area (degenerate) skipped");
    const size_t coinciding = CountCoincidingMeshLights(area_lights, num_analytic_lights);
    if (coinciding)
        warnings.push_back(std::to_string(coinciding) + " emissive triangle" + (coinciding > 1 ? "s" : "") +
                           " coincide with another (duplicated surfaces): camera and BSDF rays see only one of "
                           "each stack, so with MIS their light is underestimated -- remove the duplicates");
}

}  // namespace sphrect::render
