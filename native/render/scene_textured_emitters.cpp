// Area lights whose emission an image drives (textured_emitter.h): emissive meshes' and rectangle or ellipse lights'
// own; their mean radiance, which light selection uses, and for rectangles the power of their blocks, by which light
// samples choose where to go (core/rectangle_blocks.h).
#include <algorithm>
#include <cmath>

#include "core/patterns.h"
#include "integrator/textured_emission.h"
#include "scene.h"
#include "sampling_util.h"
#include "scene_checks.h"

namespace sphrect::render {

namespace {

// Share of the mean block radiance every block gets on top of its own: a block whose lookups all read black may still
// emit between them (a thin bright line, bilinear filtering), and must keep a pdf > 0 for the estimate to stay
// unbiased; a black block then takes ~1% of the samples a mean block of its solid angle takes.
constexpr double kBlockPowerFloor = 0.01;
// Lookups per light side at most, when measuring its emission (texel density above this is averaged over).
constexpr int kMaxLookupsPerSide = 1024;
// A node program's emitter has no texels to count: measured as if it spanned this many per side -- a rectangle 16
// (32 x 32 evaluations, 16 x 16 blocks: with 8 x 8 the lava cracks of tests/blender/test_node_programs.py were twice
// as noisy), a triangle or an ellipse 2 (16 evaluations: their mean only chooses among lights).  A program costs ~150
// ns for 20 nodes (bench_node_program): 10^4 emissive quads take ~1.5 s to measure.
constexpr double kProgramTexelsPerRectangleSide = 16;
constexpr double kProgramTexelsPerSide = 2;

// How many texels of the emitter's image lie between points a and b of light l (its lookup's mapped coordinates).
double TexelsBetween(const RenderScene& scene, const TexturedEmitter& e, const AreaLight& l, const Vec3f& a,
                     const Vec3f& b) {
    if (e.programmed) return l.shape == AreaShape::Rectangle ? kProgramTexelsPerRectangleSide : kProgramTexelsPerSide;
    const TextureLookup& t = e.lookup;
    const Image& im = scene.images[size_t(t.image)];
    auto mapped = [&](const Vec3f& p) {
        const Vec3f c = EmitterLookupCoordinates(scene, e, l, p);
        const float(&m)[3][4] = t.transform;
        return Point2<float>{m[0][0] * c.x + m[0][1] * c.y + m[0][2] * c.z + m[0][3],
                             m[1][0] * c.x + m[1][1] * c.y + m[1][2] * c.z + m[1][3]};
    };
    const Point2<float> pa = mapped(a), pb = mapped(b);
    const double texels = std::max(std::abs(double(pb.u) - pa.u) * im.width, std::abs(double(pb.v) - pa.v) * im.height);
    return std::isfinite(texels) ? texels : 1.0;
}

// Two lookups per texel: at texel centres alone, a black block beside a bright texel would read black where bilinear
// filtering brings the bright one in over half a texel -- light its block's floor would sample rarely (high variance).
int LookupsAlong(double texels) { return std::clamp(int(std::ceil(2 * texels)), 1, kMaxLookupsPerSide); }

// Direction k of the views a program's emitter is measured from (unit, away from the surface): cosine-weighted over the
// side of `normal` for even k, the other side for odd k (a mesh emits from both), from consecutive points of a (0, 2)
// sequence through Malley's polar map (u -> cos^2 theta = 1 - u: strata of u are strata of the cosine), so that any
// run of lookups covers the angles from the normal evenly.
Vec3f ProgramViewDirection(const Vec3f& normal, uint32_t k) {
    const Point2<float> u = SobolPoint(k / 2, 0x5eed);
    const float r = std::sqrt(u.u), phi = 2 * kPi * u.v;
    const Vec3f d = Frame::FromZ(normal).FromLocal({r * std::cos(phi), r * std::sin(phi), std::sqrt(1 - u.u)});
    return k % 2 == 0 ? d : -d;
}

}  // namespace

// The light's mean radiance and, for a rectangle without spread, its blocks' powers: from lookups at cell centres about
// one per texel the light covers (at most kMaxLookupsPerSide per side).  Light selection only changes the variance,
// so the mean needs no more precision than this; the block floor keeps the block sampler unbiased whatever the
// lookups miss.
void RenderScene::AddTexturedEmitter(TexturedEmitter e) {
    AreaLight& l = area_lights.back();
    const Spectrum scale = e.multiplier;
    double sum[3] = {0, 0, 0};
    auto add = [&](const Spectrum& c) { sum[0] += c.x, sum[1] += c.y, sum[2] += c.z; };
    // Lookup k at point p.  A program's emission may depend on the direction it is seen from (a Layer Weight's
    // facing), so lookup k sees it from direction k of a cosine-weighted set over both sides (ProgramViewDirection):
    // the mean is then the emitter's power per unit area over pi, as light selection wants, not its radiance seen
    // face-on (near 0 for a glow that shows at grazing angles: a pmf that small made fireflies where it does show).
    auto radiance = [&](const Vec3f& p, uint32_t k) {
        if (e.programmed) {
            const EmitterTrianglePoint q = EmitterTrianglePointAt(*this, e, p);
            const Vec3f toward = ProgramViewDirection(TriangleNormal(meshes[e.mesh], q.prim), k);
            return ProgramEmitterRadianceAt(*this, e, q.prim, q.b1, q.b2, p, toward, 0);
        }
        return EmitterRadianceAt(*this, e, EmitterLookupCoordinates(*this, e, l, p));
    };
    size_t n = 0;
    if (l.shape == AreaShape::Rectangle) {
        const RectLight<float>& r = l.frame.light;
        const double tx = TexelsBetween(*this, e, l, r.corner, r.corner + r.ex);
        const double ty = TexelsBetween(*this, e, l, r.corner, r.corner + r.ey);
        const int nx = std::clamp(int(std::ceil(tx)), 1, kMaxRectangleBlocksPerSide);
        const int ny = std::clamp(int(std::ceil(ty)), 1, kMaxRectangleBlocksPerSide);
        const int sx = (LookupsAlong(tx) + nx - 1) / nx, sy = (LookupsAlong(ty) + ny - 1) / ny;
        std::vector<double> power(size_t(nx * ny), 0.0);
        for (int j = 0; j < ny * sy; ++j)
            for (int i = 0; i < nx * sx; ++i) {
                const float s = (i + 0.5f) / float(nx * sx), t = (j + 0.5f) / float(ny * sy);
                const Spectrum c = radiance(r.corner + r.ex * s + r.ey * t, uint32_t(j * nx * sx + i));
                add(c);
                power[size_t((j / sy) * nx + i / sx)] += std::max(double(Luminance(c)), 0.0);
            }
        n = size_t(nx * sx) * size_t(ny * sy);
        // With spread the light is sampled on the part a point receives from (SpreadClippedFrame): no blocks.
        if (!l.HasSpread()) {
            e.nx = nx, e.ny = ny;
            double total = 0;
            for (double p : power) total += p;
            const double floor = total > 0 ? kBlockPowerFloor * total / double(power.size()) : 1.0;
            // Relative to the largest (only ratios matter): any emission's magnitude stays within float.
            const double largest = *std::max_element(power.begin(), power.end()) + floor;
            for (double p : power) e.block_radiance.push_back(float((p + floor) / largest));
        }
    } else if (l.shape == AreaShape::Ellipse) {
        // Cell centres of an s x s grid over its bounding rectangle, those on the ellipse.
        const int s = std::min(LookupsAlong(std::max(TexelsBetween(*this, e, l, l.center - l.ax, l.center + l.ax),
                                                     TexelsBetween(*this, e, l, l.center - l.ay, l.center + l.ay))),
                               kMaxLookupsPerSide);
        for (int j = 0; j < s; ++j)
            for (int i = 0; i < s; ++i) {
                const float x = 2 * (i + 0.5f) / float(s) - 1, y = 2 * (j + 0.5f) / float(s) - 1;
                if (x * x + y * y > 1) continue;
                add(radiance(l.center + l.ax * x + l.ay * y, uint32_t(n)));
                ++n;
            }
    } else {
        // Cell centres of an s x s grid through the square-to-triangle map that is uniform by area
        // (SampleTriangleArea).
        const int s = std::min(LookupsAlong(std::max(TexelsBetween(*this, e, l, l.v0, l.v0 + l.e1),
                                                     TexelsBetween(*this, e, l, l.v0, l.v0 + l.e2))),
                               64);
        for (int j = 0; j < s; ++j)
            for (int i = 0; i < s; ++i) {
                const float su = std::sqrt((i + 0.5f) / s), v = (j + 0.5f) / s;
                add(radiance(l.v0 + l.e1 * (su * (1 - v)) + l.e2 * (su * v), uint32_t(j * s + i)));
            }
        n = size_t(s) * size_t(s);
    }
    n = std::max(n, size_t(1));
    Spectrum mean(float(sum[0] / double(n)), float(sum[1] / double(n)), float(sum[2] / double(n)));
    // A light whose lookups all read black may still emit between them: a small power keeps it selectable.
    if (!(Luminance(mean) > 0)) mean = scale * 1e-6f;
    l.radiance = mean;
    l.texture = int(textured_emitters.size());
    textured_emitters.push_back(std::move(e));
}

void RenderScene::AddMeshTexturedEmitter(int material, uint32_t mesh, uint32_t first, int count) {
    TexturedEmitter e;
    e.lookup = materials[size_t(material)].textures[int(TexturedInput::kEmission)];
    e.programmed = !materials[size_t(material)].programs[int(TexturedInput::kEmission)].empty();
    e.multiplier = area_lights.back().radiance;  // the material's emission: the image's multiplier
    e.material = material;
    e.mesh = mesh;
    e.num_triangles = count;
    for (int k = 0; k < count; ++k) e.triangles[k] = first + uint32_t(k);
    AddTexturedEmitter(std::move(e));
}

void RenderScene::SetLastLightTexture(const TextureLookup& lookup) {
    RequireNotCommitted();
    if (area_lights.empty() || area_lights.back().on_mesh || area_lights.back().texture >= 0)
        Fail("a light texture must follow the rectangle or ellipse light it belongs to");
    CheckLookup(lookup);
    if (lookup.generated)
        Fail("a light's texture reads the light's own coordinates: its lookup's coordinates must be 'uv'");
    TexturedEmitter e;
    e.lookup = lookup;
    e.multiplier = area_lights.back().radiance;
    e.on_light_plane = true;
    AddTexturedEmitter(std::move(e));
}

}  // namespace sphrect::render
