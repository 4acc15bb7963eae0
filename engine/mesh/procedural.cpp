#include "mesh/procedural.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/assert.h"
#include "mesh/repair.h"
#include "mesh/subdivide.h"

namespace pbdsplat::mesh {

TriangleMesh icosphere(uint32_t level, float radius) {
    PBDSPLAT_ASSERT(level <= 8, "icosphere: level above 8 makes over 2.6 million triangles; lower it");
    TriangleMesh m;
    const float t = (1.0f + std::sqrt(5.0f)) * 0.5f;
    const float base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                               {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (const auto& p : base) m.positions.push_back(Vec3f(p[0], p[1], p[2]).normalized());
    m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                   {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                   {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};

    for (uint32_t l = 0; l < level; ++l) subdivide(m, [](const Vec3f& a, const Vec3f& b) { return Vec3f((a + b).normalized()); });
    for (Vec3f& p : m.positions) p *= radius;
    return m;
}

namespace {

// Welds shared seams and fixes orientation; procedural input never fails repair.
TriangleMesh finish(TriangleMesh m) {
    RepairOptions o;
    o.weld_tolerance = 1e-6f;
    auto r = repair(std::move(m), o, "procedural mesh");
    PBDSPLAT_ASSERT(r.ok(), "procedural meshes must survive repair");
    return std::move(r).value().mesh;
}

// Surface of revolution about y through profile points (radius, height) from top to bottom;
// a point with radius 0 is a pole (one vertex).
TriangleMesh lathe(const std::vector<Vec2f>& profile, uint32_t segments) {
    TriangleMesh m;
    std::vector<std::vector<uint32_t>> ring_ids;
    for (const Vec2f& p : profile) {
        std::vector<uint32_t> ids;
        if (p.x() <= 0.0f) {
            ids.assign(segments, uint32_t(m.positions.size()));
            m.positions.push_back(Vec3f(0.0f, p.y(), 0.0f));
        } else {
            for (uint32_t s = 0; s < segments; ++s) {
                const float a = 2.0f * k_pi * float(s) / float(segments);
                ids.push_back(uint32_t(m.positions.size()));
                m.positions.push_back(Vec3f(p.x() * std::cos(a), p.y(), -p.x() * std::sin(a)));
            }
        }
        ring_ids.push_back(std::move(ids));
    }
    for (size_t r = 0; r + 1 < ring_ids.size(); ++r)
        for (uint32_t s = 0; s < segments; ++s) {
            const uint32_t s1 = (s + 1) % segments;
            const uint32_t a = ring_ids[r][s], b = ring_ids[r][s1], c = ring_ids[r + 1][s], d = ring_ids[r + 1][s1];
            if (a != b) m.triangles.push_back({a, c, b});
            if (c != d) m.triangles.push_back({b, c, d});
        }
    return finish(std::move(m));
}

} // namespace

TriangleMesh uv_sphere(uint32_t rings, uint32_t segments, float radius) {
    PBDSPLAT_ASSERT(rings >= 2 && segments >= 3, "uv_sphere: need at least 2 rings and 3 segments");
    std::vector<Vec2f> profile;
    for (uint32_t i = 0; i <= rings; ++i) {
        const float t = k_pi * float(i) / float(rings);
        profile.push_back(Vec2f(i == 0 || i == rings ? 0.0f : radius * std::sin(t), radius * std::cos(t)));
    }
    return lathe(profile, segments);
}

TriangleMesh capsule(float radius, float length, uint32_t rings, uint32_t segments) {
    PBDSPLAT_ASSERT(radius > 0.0f && length >= 0.0f && rings >= 2 && segments >= 3,
                    "capsule: need radius > 0, length >= 0, rings >= 2, segments >= 3");
    std::vector<Vec2f> profile;
    const float half = 0.5f * length;
    for (uint32_t i = 0; i <= rings; ++i) {  // top hemisphere, pole to equator
        const float t = 0.5f * k_pi * float(i) / float(rings);
        profile.push_back(Vec2f(i == 0 ? 0.0f : radius * std::sin(t), half + radius * std::cos(t)));
    }
    for (uint32_t i = 0; i <= rings; ++i) {  // bottom hemisphere, equator to pole
        const float t = 0.5f * k_pi + 0.5f * k_pi * float(i) / float(rings);
        profile.push_back(Vec2f(i == rings ? 0.0f : radius * std::sin(t), -half + radius * std::cos(t)));
    }
    return lathe(profile, segments);
}

TriangleMesh torus(uint32_t segments, uint32_t sides, float major, float minor) {
    PBDSPLAT_ASSERT(segments >= 3 && sides >= 3 && major > minor && minor > 0.0f,
                    "torus: need 3+ segments and sides, and major > minor > 0");
    TriangleMesh m;
    for (uint32_t i = 0; i < segments; ++i)
        for (uint32_t j = 0; j < sides; ++j) {
            const float u = 2.0f * k_pi * float(i) / float(segments), v = 2.0f * k_pi * float(j) / float(sides);
            const float r = major + minor * std::cos(v);
            m.positions.push_back(Vec3f(r * std::cos(u), minor * std::sin(v), r * std::sin(u)));
        }
    auto id = [&](uint32_t i, uint32_t j) { return (i % segments) * sides + (j % sides); };
    for (uint32_t i = 0; i < segments; ++i)
        for (uint32_t j = 0; j < sides; ++j) {
            m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return finish(std::move(m));
}

namespace {
// An axis-aligned box from `lo` to `hi`, each face split into cells, `n[a]` along axis a.
TriangleMesh cuboid(const Vec3f& lo, const Vec3f& hi, const std::array<int, 3>& n) {
    TriangleMesh m;
    const Vec3f size = hi - lo;
    for (int axis = 0; axis < 3; ++axis)
        for (float side : {0.0f, 1.0f}) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            const uint32_t base = uint32_t(m.positions.size());
            for (int i = 0; i <= n[u]; ++i)
                for (int j = 0; j <= n[v]; ++j) {
                    Vec3f p;
                    p[axis] = lo[axis] + side * size[axis];
                    p[u] = lo[u] + size[u] * float(i) / float(n[u]);
                    p[v] = lo[v] + size[v] * float(j) / float(n[v]);
                    m.positions.push_back(p);
                }
            for (int i = 0; i < n[u]; ++i)
                for (int j = 0; j < n[v]; ++j) {
                    const uint32_t a = base + uint32_t(i * (n[v] + 1) + j), b = a + uint32_t(n[v] + 1);
                    m.triangles.push_back({a, b, b + 1});
                    m.triangles.push_back({a, b + 1, a + 1});
                }
        }
    return finish(std::move(m));  // welds the shared edges; orients all faces outward
}

// The same with cells of about `cell` on each axis (at least one): a long thin box gets square
// quads, not slivers.
TriangleMesh cuboid(const Vec3f& lo, const Vec3f& hi, float cell) {
    std::array<int, 3> n;
    for (int a = 0; a < 3; ++a) n[a] = std::max(1, int(std::lround((hi[a] - lo[a]) / cell)));
    return cuboid(lo, hi, n);
}
} // namespace

TriangleMesh box(const Vec3f& size, uint32_t divisions) {
    PBDSPLAT_ASSERT(divisions >= 1 && (size.array() > 0.0f).all(), "box: need positive size and divisions >= 1");
    const int d = int(divisions);
    return cuboid(-0.5f * size, 0.5f * size, {d, d, d});
}

TriangleMesh quadruped(uint32_t d) {
    PBDSPLAT_ASSERT(d >= 1 && d <= 64, "quadruped: divisions in [1, 64]");
    // In units of d cells: legs 1 x 4 x 1 at the corners of a body 6 long (x), 2 thick (y), 3 wide
    // (z); a head 2 x 2 x 3 sticks out in front of the body's top, so the front legs carry more.
    const int nx = int(8 * d), ny = int(7 * d), nz = int(3 * d), unit = int(d);
    auto solid = [&](int x, int y, int z) {
        if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) return false;
        if (x >= 6 * unit) return y >= 5 * unit;                      // head
        if (y >= 4 * unit) return y < 6 * unit;                        // body
        const bool leg_x = x < unit || (x >= 5 * unit && x < 6 * unit);  // legs
        return leg_x && (z < unit || z >= nz - unit);
    };
    TriangleMesh m;
    const float cell = 1.0f / float(ny);
    auto corner = [&](int x, int y, int z) {
        return uint32_t((x * (ny + 1) + y) * (nz + 1) + z);
    };
    for (int x = 0; x <= nx; ++x)
        for (int y = 0; y <= ny; ++y)
            for (int z = 0; z <= nz; ++z)
                m.positions.push_back(Vec3f(float(x) - 0.5f * float(nx), float(y) - 0.5f * float(ny), float(z) - 0.5f * float(nz)) * cell);
    // A face wherever a solid cell meets an empty one; the corners of a face in x, y, z order
    // around its axis, reversed on the negative side so that every face points out of the solid.
    for (int x = 0; x < nx; ++x)
        for (int y = 0; y < ny; ++y)
            for (int z = 0; z < nz; ++z) {
                if (!solid(x, y, z)) continue;
                for (int axis = 0; axis < 3; ++axis)
                    for (int side : {0, 1}) {
                        int n[3] = {x, y, z};
                        n[axis] += side ? 1 : -1;
                        if (solid(n[0], n[1], n[2])) continue;
                        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                        int c[4][3];
                        for (int k = 0; k < 4; ++k) {
                            c[k][0] = x, c[k][1] = y, c[k][2] = z;
                            c[k][axis] += side;
                            c[k][u] += (k == 1 || k == 2) ? 1 : 0;
                            c[k][v] += (k >= 2) ? 1 : 0;
                        }
                        uint32_t q[4];
                        for (int k = 0; k < 4; ++k) q[k] = corner(c[k][0], c[k][1], c[k][2]);
                        if (side) {
                            m.triangles.push_back({q[0], q[1], q[2]});
                            m.triangles.push_back({q[0], q[2], q[3]});
                        } else {
                            m.triangles.push_back({q[0], q[2], q[1]});
                            m.triangles.push_back({q[0], q[3], q[2]});
                        }
                    }
            }
    return finish(std::move(m));  // drops the interior grid points; checks orientation
}

TriangleMesh table(uint32_t d) {
    PBDSPLAT_ASSERT(d >= 1 && d <= 64, "table: divisions in [1, 64]");
    const float cell = 0.05f / float(d), top = 0.375f, thick = 0.05f, leg = 0.05f, inset = 0.05f;
    TriangleMesh m = cuboid(Vec3f(-0.6f, top - thick, -0.4f), Vec3f(0.6f, top, 0.4f), cell);
    // The legs stop a fiftieth of a cell under the top: touching, but sharing no vertex with it.
    const float leg_top = top - thick - 0.02f * cell;
    for (float sx : {-1.0f, 1.0f})
        for (float sz : {-1.0f, 1.0f}) {
            const Vec3f outer(sx * (0.6f - inset), -top, sz * (0.4f - inset));
            const Vec3f inner(sx * (0.6f - inset - leg), leg_top, sz * (0.4f - inset - leg));
            append(m, cuboid(outer.cwiseMin(inner), outer.cwiseMax(inner), cell));
        }
    return m;
}

TriangleMesh grid_sheet(uint32_t n, float size) {
    PBDSPLAT_ASSERT(n >= 1 && size > 0.0f, "grid_sheet: need n >= 1 and size > 0");
    TriangleMesh m;
    for (uint32_t i = 0; i <= n; ++i)
        for (uint32_t j = 0; j <= n; ++j)
            m.positions.push_back(Vec3f(-0.5f * size + size * float(j) / float(n), 0.0f, -0.5f * size + size * float(i) / float(n)));
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n; ++j) {
            const uint32_t a = i * (n + 1) + j, b = a + n + 1;
            m.triangles.push_back({a, b, a + 1});  // normal +y
            m.triangles.push_back({a + 1, b, b + 1});
        }
    return m;
}

std::vector<Vec3f> fibonacci_sphere(uint32_t count, float radius) {
    std::vector<Vec3f> p(count);
    const double golden = k_pi * (3.0 - std::sqrt(5.0));
    for (uint32_t i = 0; i < count; ++i) {
        const double y = 1.0 - 2.0 * (double(i) + 0.5) / double(count);
        const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
        const double t = golden * double(i);
        p[i] = Vec3f(float(r * std::cos(t)), float(y), float(r * std::sin(t))) * radius;
    }
    return p;
}

} // namespace pbdsplat::mesh
