// Emissive meshes into area lights (Cycles: scene/light.cpp's mesh lights): each emitting triangle, or the rectangle
// two of them form.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>

#include "scene.h"
#include "scene_checks.h"

namespace sphrect::render {

namespace {

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
        // Cycles 3.4 makes no light of a mesh that no BSDF ray sees (object_usable_as_light).
        if (!emits || !(m.visibility & kRayBsdfClasses)) continue;
        const size_t first_light = area_lights.size();
        auto triangle = [&](size_t i) {
            Triangle t;
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = m.triangles[3 * i + k];
                t.v[k] = Vec3f(m.vertices[3 * v], m.vertices[3 * v + 1], m.vertices[3 * v + 2]);
            }
            return t;
        };
        m.triangle_light.assign(m.num_triangles, -1);
        auto textured = [&](size_t i) { return materials[material_of(i)].EmissionVaries(); };
        const uint32_t mesh_index = uint32_t(&m - meshes.data());
        for (size_t i = 0; i < m.num_triangles; ++i) {
            const Spectrum& le = bsdfs[material_of(i)].emission;
            if (IsBlack(le)) continue;
            const Triangle t = triangle(i);
            const int index = int(area_lights.size());
            if (i + 1 < m.num_triangles && material_of(i + 1) == material_of(i)) {
                if (const auto rect = RectangleOfPair(t, triangle(i + 1))) {
                    area_lights.push_back(MakeRectAreaLight(rect->corner, rect->ex, rect->ey, le, true, true));
                    area_lights.back().on_mesh = true;
                    if (textured(i)) AddMeshTexturedEmitter(material_of(i), mesh_index, uint32_t(i), 2);
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
            if (textured(i)) AddMeshTexturedEmitter(material_of(i), mesh_index, uint32_t(i), 1);
            m.triangle_light[i] = index;
        }
        // It lights the closures its object is visible to (light.cpp's mesh_light.shader_flag).
        for (size_t i = first_light; i < area_lights.size(); ++i)
            area_lights[i].vis = LightVisibility(m.visibility, true, true);
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
