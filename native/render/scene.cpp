// The scene as a whole (Cycles: scene/scene.cpp): its Embree device, world and medium, and Commit(), which builds
// the BVH and the lights' structures and says what the scene calls for (SceneFeatures).  Its parts are added by
// scene_camera.cpp, scene_materials.cpp, scene_images.cpp, scene_geometry.cpp, scene_lights.cpp and
// scene_mesh_lights.cpp.
#include "scene.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <stdexcept>

#include "scene_checks.h"

namespace sphrect::render {

std::vector<std::string> SceneFeatures::Names() const {
    std::vector<std::string> n;
    if (glossy) n.push_back("glossy");
    if (medium) n.push_back("medium");
    if (volumes) n.push_back("volumes");
    if (dof) n.push_back("dof");
    if (ellipse_lights) n.push_back("ellipse_lights");
    if (delta_lights) n.push_back("delta_lights");
    if (orthographic) n.push_back("orthographic");
    if (background) n.push_back("background");
    if (emissive_meshes) n.push_back("emissive_meshes");
    if (soft_lights) n.push_back("soft_lights");
    if (area_spread) n.push_back("area_spread");
    if (textures) n.push_back("textures");
    if (normal_maps) n.push_back("normal_maps");
    if (transparency) n.push_back("transparency");
    if (environment) n.push_back("environment");
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

void RenderScene::SetBackground(const Spectrum& radiance) {
    RequireNotCommitted();
    CheckColor("world background", radiance);
    background = radiance;
}

void RenderScene::SetWorldVisibility(const LightVisibility& vis) {
    RequireNotCommitted();
    world_visibility = vis;
}

// An EnvironmentLight of image `image` (added before), without its distribution; `what` names it in errors.
EnvironmentLight RenderScene::CheckedEnvironment(const std::string& what, int image, const Spectrum& strength,
                                                 const float to_world[3][3], TextureInterpolation interpolation) const {
    if (image < 0 || size_t(image) >= images.size())
        Fail(what + ": texture " + std::to_string(image) + " is not one of the scene's " +
             std::to_string(images.size()) + " images");
    CheckColor(what + " strength", strength);
    // A rotation: orthonormal rows and determinant +1 (float input: within 1e-4).
    const float(*m)[3] = to_world;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const float dot = m[i][0] * m[j][0] + m[i][1] * m[j][1] + m[i][2] * m[j][2];
            if (!(std::abs(dot - (i == j ? 1.0f : 0.0f)) <= 1e-4f))
                Fail(what + " to_world must be a rotation (orthonormal, determinant +1)");
        }
    const float det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                      m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                      m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if (!(det > 0)) Fail(what + " to_world must be a rotation (orthonormal, determinant +1)");
    EnvironmentLight e;
    e.image = image;
    e.strength = strength;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) e.to_world[i][j] = m[i][j];
    e.interpolation = interpolation;
    return e;
}

void RenderScene::SetEnvironment(int image, const Spectrum& strength, const float to_world[3][3],
                                 TextureInterpolation interpolation) {
    RequireNotCommitted();
    EnvironmentLight checked = CheckedEnvironment("world environment", image, strength, to_world, interpolation);
    // Its sampling distribution counts against the images' memory (replacing an earlier one's).
    const Image& im = images[size_t(image)];
    const uint64_t bytes = EnvironmentDistributionBytes(im.width, im.height);
    image_memory_bytes_ -= environment_memory_bytes_;
    environment_memory_bytes_ = 0;
    CheckImageMemory("the world environment's sampling distribution", bytes);
    image_memory_bytes_ += bytes;
    environment_memory_bytes_ = bytes;
    has_environment = true;
    environment = std::move(checked);
}

void RenderScene::SetCameraEnvironment(int image, const Spectrum& strength, const float to_world[3][3],
                                       TextureInterpolation interpolation) {
    RequireNotCommitted();
    camera_environment = CheckedEnvironment("world camera environment", image, strength, to_world, interpolation);
    has_camera_environment = true;
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

void RenderScene::AddVolume(const std::string& name, const float* vertices, size_t num_vertices,
                            const int32_t* triangles, size_t num_triangles, const Spectrum& sigma_s,
                            const Spectrum& sigma_a, float g) {
    RequireNotCommitted();
    volumes.Add(device_, name, vertices, num_vertices, triangles, num_triangles, sigma_s, sigma_a, g);
    has_volumes = true;
}

void RenderScene::SetFilmTransparent(bool transparent) {
    RequireNotCommitted();
    film_transparent = transparent;
}

size_t RenderScene::NumTriangles() const {
    size_t n = 0;
    for (const auto& m : meshes) n += m.num_triangles;
    return n;
}

void RenderScene::Commit() {
    RequireNotCommitted();
    if (!camera_set_) Fail("the scene has no camera");
    if (NumTriangles() == 0 && area_lights.empty() && delta_lights.empty() && !has_environment)
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
    volumes.Commit(device_);
    AddMeshLights();
    ray_visibility = false;
    for (const MeshData& m : meshes) ray_visibility |= m.visibility != kRayAll;
    for (const AreaLight& l : area_lights) ray_visibility |= !l.vis.IsDefault();
    for (const DeltaLight& d : delta_lights) ray_visibility |= !d.vis.IsDefault();
    ray_visibility |= !world_visibility.IsDefault() || light_path_programs;
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
    BuildWeighedMediumCentres(powers);
    delta_lights_beside_tree.clear();
    soft_lights.clear();
    const std::vector<int> tree_emitters =
        DeltaTreeEmitters(area_lights.size(), delta_lights, DeltaLightsInTree(delta_lights));
    for (size_t i = 0; i < delta_lights.size(); ++i) {
        if (tree_emitters[i] < 0) delta_lights_beside_tree.push_back(uint32_t(i));
        if (IsSoft(delta_lights[i])) soft_lights.push_back({uint32_t(i), tree_emitters[i]});
    }
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
    features_.volumes = has_volumes;
    features_.medium = has_medium || has_volumes;
    features_.dof = camera.aperture_radius > 0 && !camera.orthographic;
    features_.orthographic = camera.orthographic;
    for (const auto& l : area_lights) {
        features_.ellipse_lights |= l.shape == AreaShape::Ellipse;
        features_.area_spread |= l.HasSpread();
    }
    features_.delta_lights = !delta_lights.empty();
    if (has_environment) {  // it replaces the background
        background = {};
        BuildEnvironmentDistribution(environment, images[size_t(environment.image)]);
        features_.environment = true;
    }
    features_.background = !IsBlack(background);
    features_.emissive_meshes = has_mesh_lights;
    features_.soft_lights = !soft_lights.empty();
    features_.transparency = has_transparency;
    committed_ = true;
}

void RenderScene::BuildWeighedMediumCentres(std::vector<double> powers) {
    std::vector<uint32_t> order(powers.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = uint32_t(i);
    const size_t top = std::min(order.size(), kMaxCentresWeighedPerRay);
    std::partial_sort(order.begin(), order.begin() + std::ptrdiff_t(top), order.end(),
                      [&](uint32_t a, uint32_t b) { return powers[a] > powers[b]; });
    medium_centres_weighed.assign(order.begin(), order.begin() + std::ptrdiff_t(top));
    medium_centre_rest_share = 1;
    for (uint32_t i : medium_centres_weighed) {
        medium_centre_rest_share -= medium_centre_selector.pmf[i];
        powers[i] = 0;
    }
    medium_centre_rest_share = std::max(medium_centre_rest_share, 0.0f);
    medium_centre_rest_selector = {};
    if (order.size() > top) medium_centre_rest_selector.Build(powers);
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
        TreeEmitters emitters = CollectTreeEmitters(area_lights, delta_lights, DeltaLightsInTree(delta_lights));
        light_tree_.Build(emitters.bounds);
        light_tree_refs_ = std::move(emitters.refs);
    });
}

}  // namespace sphrect::render
