// Nodes reading the hit's mesh and object (Cycles 3.4's kernel/svm/attribute.h, vertex_color.h, geometry.h,
// tex_coord.h): Attribute and Color Attribute over the mesh's attributes interpolated at the hit, the radial tangent.
#pragma once

#include "program.h"

namespace sphrect::render::svm {

struct AttributeOutput {
    Vec3f color;  // Color / Vector
    float fac = 0, alpha = 0;
};

// Attribute `a` of a mesh at barycentrics b (the weights of its vertices v), as the Attribute node (`node`
// kAttribute) or the Color Attribute node gives it; a missing one (null or empty) as Cycles reads it: colour 0, fac 0,
// and alpha 1 from the Attribute node (svm_node_attr's not-found type), 0 from Color Attribute.
inline AttributeOutput InterpolateAttribute(const MeshAttribute* a, AttributeNode node, const uint32_t (&v)[3],
                                            const float (&b)[3]) {
    AttributeOutput o;
    if (a == nullptr || a->values.empty()) {
        o.alpha = node == AttributeNode::kAttribute ? 1.0f : 0.0f;
        return o;
    }
    float x[4] = {0, 0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        const float* f = a->values.data() + 4 * size_t(v[k]);
        for (int c = 0; c < 4; ++c) x[c] += b[k] * f[c];
    }
    o.color = Vec3f(x[0], x[1], x[2]);
    o.fac = a->fac_is_x ? x[0] : (x[0] + x[1] + x[2]) * (1.0f / 3.0f);
    o.alpha = x[3];
    return o;
}

// The Tangent node's radial tangent about axis 0 X, 1 Y, 2 Z (and Geometry's Tangent: Z, Cycles' primitive_tangent) of
// Generated coordinates g: the direction circling the axis through the texture space's centre, taken to the world as
// a normal (normal_to_world, row-major) and made orthogonal to the shading normal n; zero on the axis.  Axis 3: g is
// the object-space tangent itself (a UV map's, svm_node_tangent's UV Map direction).
inline Vec3f RadialTangent(int axis, const Vec3f& g, const Vec3f& n, const float (&normal_to_world)[3][3]) {
    const Vec3f local = axis == 0   ? Vec3f(0, -(g.z - 0.5f), g.y - 0.5f)
                        : axis == 1 ? Vec3f(-(g.z - 0.5f), 0, g.x - 0.5f)
                        : axis == 2 ? Vec3f(-(g.y - 0.5f), g.x - 0.5f, 0)
                                    : g;
    const float(&m)[3][3] = normal_to_world;
    const Vec3f t(m[0][0] * local.x + m[0][1] * local.y + m[0][2] * local.z,
                  m[1][0] * local.x + m[1][1] * local.y + m[1][2] * local.z,
                  m[2][0] * local.x + m[2][1] * local.y + m[2][2] * local.z);
    const Vec3f across = Cross(t, n);
    const float len = Length(across);
    return len > 0 ? Cross(n, across / len) : Vec3f();
}

}  // namespace sphrect::render::svm
