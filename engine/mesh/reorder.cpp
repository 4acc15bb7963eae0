#include "mesh/reorder.h"

#include <algorithm>
#include <numeric>

namespace pbdsplat::mesh {
namespace {
// Spreads the low 21 bits of x so two zero bits separate each.
uint64_t spread3(uint64_t x) {
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
}
} // namespace

std::vector<uint32_t> reorder_for_locality(TriangleMesh& m) {
    const size_t n = m.positions.size();
    const Bounds b = bounds(m);
    const Vec3f extent = (b.max - b.min).cwiseMax(Vec3f::Constant(1e-30f));
    std::vector<uint64_t> code(n);
    for (size_t i = 0; i < n; ++i) {
        const Vec3f q = ((m.positions[i] - b.min).cwiseQuotient(extent) * 2097151.0f).cwiseMax(0.0f);
        code[i] = spread3(uint64_t(q.x())) | spread3(uint64_t(q.y())) << 1 | spread3(uint64_t(q.z())) << 2;
    }
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t c) { return code[a] < code[c]; });
    std::vector<uint32_t> new_index(n);
    for (uint32_t i = 0; i < n; ++i) new_index[order[i]] = i;

    auto permute = [&](auto& attr) {
        if (attr.empty()) return;
        auto out = attr;
        for (size_t i = 0; i < n; ++i) out[i] = attr[order[i]];
        attr = std::move(out);
    };
    permute(m.positions);
    permute(m.normals);
    permute(m.uvs);
    permute(m.colors);
    for (Triangle& t : m.triangles) {
        for (uint32_t& v : t) v = new_index[v];
        // Rotate so the smallest index leads (same orientation), then sort by it.
        while (t[0] > t[1] || t[0] > t[2]) std::rotate(t.begin(), t.begin() + 1, t.end());
    }
    std::stable_sort(m.triangles.begin(), m.triangles.end(),
                     [](const Triangle& x, const Triangle& y) { return x[0] != y[0] ? x[0] < y[0] : x[1] < y[1]; });
    return new_index;
}

} // namespace pbdsplat::mesh
