// A material's shading normal from a node program (a Bump node's graph: RenderScene::normal_maps' program), as
// Cycles 3.4 feeds a shader's Normal input.  Out of line: only hits of such materials come here.
#include "shader_globals.h"
#include "surface_hit.h"

namespace sphrect::render {

Vec3f BumpedShadingNormal(const RenderScene& scene, const svm::NodeProgram& program, const SurfaceHit& s,
                          const Vec3f& ng, const Vec3f& ns) {
    // The program sees the hit as Cycles' ShaderData: both normals facing the incoming ray.
    SurfaceHit facing = s;
    const Vec3f incoming(s.incoming[0], s.incoming[1], s.incoming[2]);
    const float flip = Dot(ng, incoming) < 0 ? -1.0f : 1.0f;
    facing.ng = ng * flip;
    facing.ns = ns * flip;
    facing.mapped = false;  // ns is the normal before the program
    const Vec3f n = svm::EvalNodeProgram(program, scene.images, HitShaderGlobals(facing));
    const float len = Length(n);
    return len > 0 && std::isfinite(len) ? n * (flip / len) : ns;
}

}  // namespace sphrect::render
