#include "standard_attributes.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <numeric>
#include <set>
#include <string>
#include <utility>

#include "procedural_textures.h"  // HashUint, HashUint2, UintToFloatIncl

namespace sphrect::render::svm {

namespace {

// Cycles' DisjointSet (util/disjoint_set.h): union by rank, path compression; the representative it picks decides
// the island's random number.
class DisjointSet {
  public:
    explicit DisjointSet(size_t n) : parent_(n), rank_(n, 0) { std::iota(parent_.begin(), parent_.end(), size_t(0)); }
    size_t Find(size_t x) {
        size_t root = x;
        while (parent_[root] != root) root = parent_[root];
        while (parent_[x] != root) {
            const size_t next = parent_[x];
            parent_[x] = root;
            x = next;
        }
        return root;
    }
    void Join(size_t x, size_t y) {
        size_t rx = Find(x), ry = Find(y);
        if (rx == ry) return;
        if (rank_[rx] < rank_[ry]) std::swap(rx, ry);
        parent_[ry] = rx;
        if (rank_[rx] == rank_[ry]) ++rank_[rx];
    }

  private:
    std::vector<size_t> parent_, rank_;
};

float SafeAcos(float a) { return a <= -1.0f ? 3.14159265f : a >= 1.0f ? 0.0f : std::acos(a); }

}  // namespace

std::vector<float> Pointiness(const std::vector<Vec3f>& p, const std::vector<Vec3f>& normals,
                              const std::vector<uint32_t>& edges) {
    const size_t n = p.size();
    std::vector<float> out(n, 0.0f);
    if (n == 0) return out;
    // 1: each vertex's first co-located one, found among the vertices sorted by coordinate sum (Cycles'
    // VertexAverageComparator, equal positions by descending index).
    std::vector<int> sorted(n);
    std::iota(sorted.begin(), sorted.end(), 0);
    auto sum = [&](int i) { return p[i].x + p[i].y + p[i].z; };
    std::sort(sorted.begin(), sorted.end(), [&](int a, int b) {
        if (p[a].x == p[b].x && p[a].y == p[b].y && p[a].z == p[b].z) return a > b;
        return sum(a) < sum(b);
    });
    std::vector<int> orig(n);
    for (size_t s = 0; s < n; ++s) {
        const int v = sorted[s];
        orig[v] = v;
        for (size_t o = s + 1; o < n; ++o) {
            const int w = sorted[o];
            if (sum(w) - sum(v) > 3 * FLT_EPSILON) break;
            const Vec3f d = p[w] - p[v];
            if (Dot(d, d) < FLT_EPSILON) {
                orig[v] = w;
                break;
            }
        }
    }
    for (size_t v = 0; v < n; ++v) {
        int o = orig[v];
        while (o != orig[o]) o = orig[o];
        orig[v] = o;
    }
    // 2: the merged vertices' normals summed, normalised.
    std::vector<Vec3f> normal(n, Vec3f());
    for (size_t v = 0; v < n; ++v) normal[orig[v]] = normal[orig[v]] + normals[v];
    for (size_t v = 0; v < n; ++v) normal[v] = normal[orig[v]] / Length(normal[orig[v]]);
    // 3: the angle to the mean edge direction over each merged edge once.
    std::vector<int> count(n, 0);
    std::vector<float> raw(n, 0.0f);
    std::vector<Vec3f> accum(n, Vec3f());
    std::set<std::pair<int, int>> visited;
    auto first_visit = [&](int a, int b) { return visited.insert({std::min(a, b), std::max(a, b)}).second; };
    for (size_t e = 0; 2 * e + 1 < edges.size(); ++e) {
        const int v0 = orig[edges[2 * e]], v1 = orig[edges[2 * e + 1]];
        if (!first_visit(v0, v1)) continue;
        const Vec3f d = p[v1] - p[v0];
        const float len = Length(d);
        const Vec3f dir = len > 0 ? d / len : Vec3f();
        accum[v0] = accum[v0] + dir;
        accum[v1] = accum[v1] - dir;
        ++count[v0], ++count[v1];
    }
    for (size_t v = 0; v < n; ++v)
        if (int(v) == orig[v] && count[v] > 0)
            raw[v] = SafeAcos(Dot(normal[v], accum[v] / float(count[v]))) * float(1.0 / 3.14159265358979323846);
    // 4: blurred with the neighbours (a two-ring neighbourhood), then copied to the merged vertices.
    out = raw;
    std::fill(count.begin(), count.end(), 0);
    visited.clear();
    for (size_t e = 0; 2 * e + 1 < edges.size(); ++e) {
        const int v0 = orig[edges[2 * e]], v1 = orig[edges[2 * e + 1]];
        if (!first_visit(v0, v1)) continue;
        out[v0] += raw[v1];
        out[v1] += raw[v0];
        ++count[v0], ++count[v1];
    }
    for (size_t v = 0; v < n; ++v) out[v] /= float(count[v] + 1);
    for (size_t v = 0; v < n; ++v) out[v] = out[orig[v]];
    return out;
}

std::vector<float> RandomPerIsland(size_t num_vertices, const std::vector<uint32_t>& edges) {
    DisjointSet islands(num_vertices);
    for (size_t e = 0; 2 * e + 1 < edges.size(); ++e) islands.Join(edges[2 * e], edges[2 * e + 1]);
    std::vector<float> out(num_vertices);
    for (size_t v = 0; v < num_vertices; ++v) out[v] = UintToFloatIncl(HashUint(uint32_t(islands.Find(v))));
    return out;
}

float ObjectNameRandom(const std::string& name) {
    uint32_t h = 0;  // Cycles' hash_string, over (signed) chars as x86 compilers read them
    for (char c : name) h = h * 37 + uint32_t(int32_t(static_cast<signed char>(c)));
    return ObjectIdRandom(HashUint2(h, 0));
}

float ObjectIdRandom(uint32_t random_id) { return UintToFloatIncl(random_id); }

}  // namespace sphrect::render::svm
