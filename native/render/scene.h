// The renderer's scene: Embree triangle geometry, materials, lights, camera and world.
// Built once through the Add*/Set* calls (which validate their input and throw
// std::invalid_argument with a readable message), then Commit() builds the BVH.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "area_light_finder.h"
#include "bsdf.h"
#include "camera.h"
#include "environment_light.h"
#include "light_tree.h"
#include "lights.h"
#include "medium.h"
#include "object_volumes.h"
#include "ray_visibility.h"
#include "texture.h"
#include "material.h"
#include "textured_emitter.h"

namespace sphrect::render {

// Transparent surfaces a camera or shadow ray goes through before it counts as blocked (black), as Cycles'
// transparent_max_bounces does at its default (integrator/transparency.h).
constexpr int kMaxTransparentHits = 8;

// Limits of a scene's camera: each image side, and the pixel count (the bindings export the side).
constexpr int kMaxImageSide = 1 << 15;
constexpr int kMaxImagePixelsLog2 = 27;
constexpr int64_t kMaxImagePixels = int64_t(1) << kMaxImagePixelsLog2;

struct MeshData {
    std::string name;
    const float* vertices = nullptr;      // Embree-owned, [3 * num_vertices]
    const uint32_t* triangles = nullptr;  // Embree-owned, [3 * num_triangles]
    size_t num_vertices = 0, num_triangles = 0;
    std::vector<Vec3f> normals;         // per vertex, or empty (flat shading)
    std::vector<int32_t> material_ids;  // per triangle, or empty (material 0)
    // Emissive meshes: per triangle the index of its area light (a triangle, or the rectangle it
    // forms with its neighbour), -1 if it emits nothing; empty when no triangle emits.
    std::vector<int32_t> triangle_light;
    // Texture coordinates, per vertex, or empty: 'uv' (Mesh.uvs) and 'generated' (Mesh.generated).
    std::vector<Point2<float>> uvs;
    std::vector<Vec3f> generated;
    // The linear part L of its object's matrix and L^-1 (row-major), for normal maps applied in object space.
    bool has_object_linear = false;
    // Blender's Shadow Terminator Geometry Offset (0: none): near the terminator a light sample's shadow ray leaves
    // from the smooth surface the mesh's normals describe, as Cycles 3.4's shadow_ray_offset (integrator/terminator.h).
    float shadow_terminator_offset = 0;
    float object_linear[3][3], object_linear_inverse[3][3];
    Vec3f object_translation;      // its object's location (with object_linear: node programs' Object coordinates)
    uint8_t visibility = kRayAll;  // the ray kinds that see it (ray_visibility.h): its Embree geometry mask
    // What node programs read of it (svm/attribute_nodes.h): its attributes by the scene's attribute slot (an
    // Attribute node's; empty: it lacks that one), and its object (Object Info, the radial tangent's transform).
    std::vector<svm::MeshAttribute> attributes;
    svm::ObjectInfo object_info;
};

// What a scene asks of the integrator; each flag selects a specialised kernel or a feature name.
struct SceneFeatures {
    bool glossy = false, medium = false, dof = false;
    bool volumes = false;  // object volumes (object_volumes.h); medium is set too: they run the medium kernel
    bool ellipse_lights = false, delta_lights = false, orthographic = false, background = false;
    bool emissive_meshes = false, soft_lights = false, area_spread = false;
    bool textures = false, normal_maps = false, transparency = false;
    bool environment = false;  // an image world (environment_light.h)
    std::vector<std::string> Names() const;
};

// A soft point, spot or sun light (delta_light.h): delta_lights[delta], tree emitter tree_emitter of the light
// tree (-1: a sun, evaluated once).
struct SoftLightRef {
    uint32_t delta;
    int tree_emitter;
};

// std::invalid_argument unless the camera can render: resolution within the limits, a finite, non-singular
// matrix, a positive image plane, a valid lens and clipping range.
void ValidateCamera(const CameraModel& camera);

class RenderScene {
  public:
    RenderScene();
    ~RenderScene();
    RenderScene(const RenderScene&) = delete;
    RenderScene& operator=(const RenderScene&) = delete;

    void SetCamera(const CameraModel& camera);
    void SetBackground(const Spectrum& radiance);
    // Blender's Film > Transparent: camera rays that escape see nothing and give alpha 0 (the background still
    // lights the scene).
    void SetFilmTransparent(bool transparent);
    // The world's Ray Visibility (Blender's World > Ray Visibility: camera, diffuse, glossy, transmission, volume
    // scatter), for the background and the image world alike, as a light's (ray_visibility.h): the kinds of
    // `vis.rays()` see and are lit by it.
    void SetWorldVisibility(const LightVisibility& vis);
    // An image world (environment_light.h) on image `image` (added before), replacing the background: strength
    // finite and non-negative, to_world a rotation (row-major).  Commit() builds its sampling distribution, whose
    // memory counts against SetImageMemoryLimit (std::invalid_argument here where it would pass it).
    void SetEnvironment(int image, const Spectrum& strength, const float to_world[3][3],
                        TextureInterpolation interpolation);
    // What escaping camera rays see instead of the background or the image world, where the world shows the camera
    // something else than the light it gives (a Light Path node's Is Camera Ray): an image as SetEnvironment's,
    // never sampled as a light.
    void SetCameraEnvironment(int image, const Spectrum& strength, const float to_world[3][3],
                              TextureInterpolation interpolation);
    void SetMedium(const Spectrum& sigma_s, const Spectrum& sigma_a, float g);
    // A homogeneous medium bounded by a closed mesh (ObjectVolumes::Add), beside the world's and any other volumes
    // (their coefficients add where they overlap).
    void AddVolume(const std::string& name, const float* vertices, size_t num_vertices, const int32_t* triangles,
                   size_t num_triangles, const Spectrum& sigma_s, const Spectrum& sigma_a, float g);
    // Checks the material (std::invalid_argument naming it and the field) and adds it with its Bsdf; returns its
    // index.  Emissive triangles of its meshes become area lights at Commit().
    int AddMaterial(const Material& material);
    // Images, which materials' lookups name by index.  AddImage copies width x height x channels bytes or floats (rows
    // bottom to top), or takes an Image made by MakeImage / ShareImage (texture.h); LoadImage reads a file with
    // OpenImageIO, shares the pixels of a file another scene holds (unchanged since), or on failure makes Cycles'
    // magenta missing image and a warning.  Each counts against SetImageMemoryLimit before it is copied or decoded.
    int AddImage(const std::string& name, int width, int height, int channels, const uint8_t* bytes,
                 const float* floats, bool srgb);
    int AddImage(Image image);
    int LoadImage(const std::string& name, const std::string& path, bool srgb);
    // The most bytes the scene's images may take together (0: no limit): what a Renderer's memory limit leaves
    // beside its film.  std::invalid_argument from the Add/Load call whose image would pass it.
    void SetImageMemoryLimit(uint64_t bytes);
    // std::invalid_argument naming `image` (its name, and path if any) if `bytes` more would pass the limit.
    void CheckImageMemory(const std::string& image, uint64_t bytes) const;
    uint64_t ImageMemoryBytes() const { return image_memory_bytes_; }  // shared pixels counted too
    // The mesh added last: its object's linear map and inverse (meshes without triangles are not kept: ignored).
    void SetLastMeshObjectLinear(const float linear[3][3], const float inverse[3][3], const Vec3f& translation = {});
    // The mesh added last: its attribute in slot `slot` (4 floats per vertex: svm::MeshAttribute), and its object's
    // Object Info (colour, alpha, pass index, random number; its location is object_linear's translation), whether its
    // triangles list Blender's corners reversed (svm::ObjectInfo).
    void SetLastMeshAttribute(size_t slot, std::vector<float> values, bool fac_is_x);
    void SetLastMeshObjectInfo(const Vec3f& color, float alpha, float index, float random, bool reversed = false);
    // The mesh added last: Blender's Shadow Terminator Geometry Offset, in [0, 1] (MeshData::shadow_terminator_offset).
    void SetLastMeshShadowTerminatorOffset(float offset);
    // Copies the arrays (one memcpy each into Embree's buffers).  normals / material_ids / uvs / generated may be
    // null.  A mesh without triangles is validated and then ignored.
    void AddMesh(const std::string& name, const float* vertices, size_t num_vertices, const int32_t* triangles,
                 size_t num_triangles, const float* normals, const int32_t* material_ids, const float* uvs = nullptr,
                 const float* generated = nullptr, uint8_t visibility = kRayAll);
    // Area lights return "" when added, or why the light was skipped (zero area, black).  spread: Blender's
    // Spread, radians in [0, pi] (pi: none; area_light.h, SetAreaSpread).  vis: what every light lights and how
    // (ray_visibility.h); its camera visibility is `visible`.
    std::string AddRectLight(const Vec3f& corner, const Vec3f& ex, const Vec3f& ey, const Spectrum& radiance,
                             bool two_sided, bool visible, float spread = kPi, const LightVisibility& vis = {});
    std::string AddEllipseLight(const Vec3f& center, const Vec3f& ax, const Vec3f& ay, const Spectrum& radiance,
                                bool two_sided, bool visible, float spread = kPi, const LightVisibility& vis = {});
    // The light just added (AddRectLight or AddEllipseLight returned ""), its radiance then varying over it as the
    // lookup's colour x that radiance: the lookup reads (a, b, 0), the point's fractions along the light's edges (an
    // ellipse's bounding rectangle's) from its corner, through its transform (a Blender light's node tree).
    void SetLastLightTexture(const TextureLookup& lookup);
    // radius (point, spot) and angle (the sun's angular diameter, in [0, pi]): soft lights as Cycles 3.4's
    // (delta_light.h); 0: delta lights.  visible: a soft light is seen by camera rays.
    void AddPointLight(const Vec3f& position, const Spectrum& intensity, float radius = 0, bool visible = true,
                       const LightVisibility& vis = {});
    void AddSpotLight(const Vec3f& position, const Vec3f& direction, const Spectrum& intensity, float spot_size,
                      float spot_blend, float radius = 0, bool visible = true, const LightVisibility& vis = {});
    void AddSunLight(const Vec3f& direction, const Spectrum& irradiance, float angle = 0, bool visible = true,
                     const LightVisibility& vis = {});
    void Commit();

    bool committed() const { return committed_; }
    const SceneFeatures& features() const { return features_; }
    size_t NumTriangles() const;

    // Read by the integrator after Commit().
    RTCScene rtc_scene = nullptr;
    CameraModel camera;
    Spectrum background;  // black where the scene has an environment (it replaces the background)
    // The image world, if has_environment: a light of its own, sampled once per light sample (its distribution
    // empty, and it lights nothing, for an all-black image).
    bool has_environment = false;
    EnvironmentLight environment;
    bool has_camera_environment = false;  // SetCameraEnvironment: camera_environment (no distribution) replaces them
    EnvironmentLight camera_environment;  // for camera rays
    bool film_transparent = false;
    LightVisibility world_visibility;  // SetWorldVisibility; the default: seen by every ray
    bool film_alpha = false;  // Commit(): the film's alpha can differ from 1 (transparent film, or a holdout used)
    bool has_medium = false;  // a world medium (SetMedium); zero coefficients without one
    HomogeneousMedium medium;
    bool has_volumes = false;  // object volumes (AddVolume): their transmittance and scattering are added to medium's
    ObjectVolumes volumes;
    std::vector<Bsdf> bsdfs;
    // Per material: what it is made of, which a hit on a textured one (Bsdf::textured) evaluates; bsdfs holds its
    // lobes.
    std::vector<Material> materials;
    std::vector<NormalMap> normal_maps;  // per material; lookup unbound: none
    std::vector<Image> images;
    std::vector<MeshData> meshes;  // index = Embree geometry id (meshes without triangles are not kept)
    // The scene's lights [0, num_analytic_lights), intersected analytically by camera and BSDF rays,
    // then the emissive meshes' (on_mesh), which those rays find through Embree.
    std::vector<AreaLight> area_lights;
    size_t num_analytic_lights = 0;
    AreaLightFinder analytic_light_finder;           // of lights [0, num_analytic_lights): which a ray crosses
    LightSelector light_selector;                    // over area_lights, by power
    bool has_mesh_lights = false;                    // some area light is on_mesh
    std::vector<TexturedEmitter> textured_emitters;  // the area lights' of texture >= 0 (textured_emission.h)
    bool has_transparency = false;                   // Commit(): some triangle's material may let rays through
    // Commit(): some mesh hides from some ray kind, or some light's visibility is not the default (ray_visibility.h):
    // BSDF rays then need their lobe's kind.
    bool ray_visibility = false;
    // AddMaterial(): some material's program reads the Light Path node's ray kinds or depths (svm::RayContext): BSDF
    // rays then need their lobe's kind too (ray_visibility is set), and diffuse hits keep their BSDF samples, whose
    // emitters may differ from their light samples' (integrator/shade_context.h).
    bool light_path_programs = false;
    // Whether triangle `prim` of `mesh` has a material that may let rays through (integrator/transparency.h).
    bool MayBeTransparent(const MeshData& mesh, uint32_t prim) const {
        const int32_t material = mesh.material_ids.empty() ? 0 : mesh.material_ids[prim];
        return bsdfs[size_t(material)].has_transparency;
    }
    std::vector<std::string> warnings;  // Commit()'s, e.g. skipped degenerate emissive triangles
    // Centres for equi-angular sampling in the medium: area lights' centres and point/spot
    // lights' positions, picked by power (sun excluded: it is infinitely far).
    std::vector<Vec3f> medium_centres;
    LightSelector medium_centre_selector;
    // The most powerful of them (up to kMaxCentresWeighedPerRay, by decreasing power), which a camera ray through
    // object volumes weighs by how close it passes (integrator/shade_volume.h, EquiAngularAboutANearLight), and the
    // others, chosen by power among themselves (their selector; their share of the power, rest_share).
    static constexpr size_t kMaxCentresWeighedPerRay = 16;
    std::vector<uint32_t> medium_centres_weighed;
    LightSelector medium_centre_rest_selector;
    float medium_centre_rest_share = 0;
    std::vector<DeltaLight> delta_lights;
    // The soft ones among delta_lights (a radius or an angle), which BSDF, phase and camera rays reach.
    std::vector<SoftLightRef> soft_lights;
    // The delta_lights (indices) that are not tree emitters: what "tree" still evaluates once per sample -- the suns,
    // and the point and spot lights while there are few (DeltaLightsInTree) -- in a list of their own so that the
    // tree's point and spot lights cost nothing in that loop.
    std::vector<uint32_t> delta_lights_beside_tree;
    // Every area light and (when there are many, DeltaLightsInTree) point/spot light in one light tree
    // (light_selection "tree"): tree emitter i < area_lights.size() is area light i, then the point and spot lights
    // (light_tree_refs() maps each to its light); suns stay outside.  Built by the first
    // Renderer that selects by tree (BuildLightTree, thread-safe), so that "power" renders of a
    // million emitters do not pay its ~1.4 s and ~100 MB; empty until then.
    void BuildLightTree() const;
    const LightTree& light_tree() const { return light_tree_; }
    const std::vector<TreeEmitterRef>& light_tree_refs() const { return light_tree_refs_; }

  private:
    Bsdf MakeMaterialBsdf(const Material& material) const;  // checks it; a mix's layers recursively
    void CheckLookup(const TextureLookup& lookup) const;
    void BuildWeighedMediumCentres(std::vector<double> powers);  // Commit(): medium_centres_weighed and the rest
    void CheckTextureCoordinates();  // Commit(): warns of meshes a textured material reads without their coordinates
    mutable std::once_flag light_tree_once_;
    mutable LightTree light_tree_;
    mutable std::vector<TreeEmitterRef> light_tree_refs_;
    void RequireNotCommitted() const;
    EnvironmentLight CheckedEnvironment(const std::string& what, int image, const Spectrum& strength,
                                        const float to_world[3][3], TextureInterpolation interpolation) const;
    void AddMeshLights();
    // AddMeshLights: area_lights.back(), of material `material`, made of `count` triangles of meshes[mesh] from
    // `first`, takes its emission from the material's image (scene_textured_emitters.cpp).
    void AddMeshTexturedEmitter(int material, uint32_t mesh, uint32_t first, int count);
    void AddTexturedEmitter(TexturedEmitter e);  // area_lights.back()'s: its mean radiance, its blocks
    void LetRaysThroughTransparentMeshes();      // Commit(): sets has_transparency and the meshes' occlusion filters
    RTCDevice device_ = nullptr;
    bool committed_ = false, camera_set_ = false;
    uint64_t image_memory_limit_ = 0, image_memory_bytes_ = 0;
    uint64_t environment_memory_bytes_ = 0;  // the image world's sampling distribution, in image_memory_bytes_
    SceneFeatures features_;
};

}  // namespace sphrect::render
