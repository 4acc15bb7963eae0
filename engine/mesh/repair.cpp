#include "mesh/repair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <tuple>
#include <unordered_map>

#include "mesh/topology.h"

namespace pbdsplat::mesh {
namespace {

uint64_t edge_key(uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); }

// Keeps the per-vertex attributes in step with a vertex remapping.
template <class T>
void remap_attribute(std::vector<T>& attr, const std::vector<uint32_t>& source_of_new) {
    if (attr.empty()) return;
    std::vector<T> out(source_of_new.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = attr[source_of_new[i]];
    attr = std::move(out);
}
void remap_vertices(TriangleMesh& m, const std::vector<uint32_t>& source_of_new) {
    remap_attribute(m.positions, source_of_new);
    remap_attribute(m.normals, source_of_new);
    remap_attribute(m.uvs, source_of_new);
    remap_attribute(m.colors, source_of_new);
}

// The representatives welding has kept, by grid cell: an open-addressed table of cells, each
// chaining its representatives in the order they were kept. A hash map of vectors allocated a
// vector per cell, and a scan's million vertices spent a third of the weld in the allocator.
class WeldCells {
public:
    static constexpr uint32_t k_none = UINT32_MAX;
    explicit WeldCells(size_t expected) {
        size_t cap = 16;
        while (cap < 2 * expected) cap <<= 1;
        cells_.assign(cap, Cell{});
        mask_ = cap - 1;
        next_.reserve(expected);
    }
    // The first representative of `cell` (k_none if none) and the one after `r`.
    uint32_t first(const Eigen::Vector3i& cell) const {
        const Cell& c = cells_[slot(cell)];
        return c.used ? c.head : k_none;
    }
    uint32_t next(uint32_t r) const { return next_[r]; }
    // Representative `r` (numbered in the order kept) joins the end of its cell's chain.
    void add(const Eigen::Vector3i& cell, uint32_t r) {
        Cell& c = cells_[slot(cell)];
        next_.push_back(k_none);
        if (!c.used) c = Cell{cell, r, r, true};
        else next_[c.tail] = r, c.tail = r;
    }

private:
    struct Cell {
        Eigen::Vector3i key = Eigen::Vector3i::Zero();
        uint32_t head = k_none, tail = k_none;
        bool used = false;
    };
    // The slot holding `cell`, or the empty one where it would go. Never full: one cell at most
    // per vertex, and the table holds twice as many slots.
    size_t slot(const Eigen::Vector3i& cell) const {
        size_t h = (size_t(uint32_t(cell.x())) * 73856093u ^ size_t(uint32_t(cell.y())) * 19349663u ^ size_t(uint32_t(cell.z())) * 83492791u);
        h = (h * 0x9E3779B97F4A7C15ull) >> 20;
        for (size_t s = h & mask_;; s = (s + 1) & mask_)
            if (!cells_[s].used || cells_[s].key == cell) return s;
    }
    std::vector<Cell> cells_;
    std::vector<uint32_t> next_;
    size_t mask_ = 0;
};

// Welds vertices within `tol` of one another, keeping the first of each cluster.
size_t weld(TriangleMesh& m, float tol) {
    if (tol <= 0.0f) return 0;
    WeldCells grid(m.positions.size());
    std::vector<uint32_t> rep(m.positions.size());
    std::vector<uint32_t> kept;  // representatives, in order
    const float tol2 = tol * tol;
    for (uint32_t i = 0; i < m.positions.size(); ++i) {
        const Vec3f& p = m.positions[i];
        const Eigen::Vector3i cell = (p / tol).array().floor().cast<int>();
        uint32_t found = UINT32_MAX;
        for (int dz = -1; dz <= 1 && found == UINT32_MAX; ++dz)
            for (int dy = -1; dy <= 1 && found == UINT32_MAX; ++dy)
                for (int dx = -1; dx <= 1 && found == UINT32_MAX; ++dx)
                    for (uint32_t r = grid.first(cell + Eigen::Vector3i(dx, dy, dz)); r != WeldCells::k_none; r = grid.next(r))
                        if ((m.positions[kept[r]] - p).squaredNorm() <= tol2) {
                            found = r;
                            break;
                        }
        if (found == UINT32_MAX) {
            found = uint32_t(kept.size());
            kept.push_back(i);
            grid.add(cell, found);
        }
        rep[i] = found;
    }
    for (Triangle& t : m.triangles)
        for (uint32_t& v : t) v = rep[v];
    const size_t merged = m.positions.size() - kept.size();
    remap_vertices(m, kept);
    return merged;
}

// Drops unreferenced vertices, keeping the order of the rest.
size_t drop_unreferenced(TriangleMesh& m) {
    std::vector<uint32_t> new_index(m.positions.size(), UINT32_MAX), source;
    for (const Triangle& t : m.triangles)
        for (uint32_t v : t) new_index[v] = 0;
    for (uint32_t i = 0; i < new_index.size(); ++i)
        if (new_index[i] == 0) new_index[i] = uint32_t(source.size()), source.push_back(i);
    for (Triangle& t : m.triangles)
        for (uint32_t& v : t) v = new_index[v];
    const size_t dropped = m.positions.size() - source.size();
    remap_vertices(m, source);
    return dropped;
}

double signed_volume_of(const TriangleMesh& m, const std::vector<uint32_t>& faces, bool with_caps) {
    double v = 0.0;
    auto tri = [&](const Vec3d& a, const Vec3d& b, const Vec3d& c) { v += a.dot((b - a).cross(c - a)); };
    for (uint32_t f : faces) {
        const Triangle& t = m.triangles[f];
        tri(m.positions[t[0]].cast<double>(), m.positions[t[1]].cast<double>(), m.positions[t[2]].cast<double>());
    }
    if (with_caps) {
        TriangleMesh part;
        part.positions = m.positions;
        for (uint32_t f : faces) part.triangles.push_back(m.triangles[f]);
        for (const auto& loop : boundary_loops(part)) {
            Vec3d c = Vec3d::Zero();
            for (uint32_t q : loop) c += m.positions[q].cast<double>();
            c /= double(loop.size());
            for (size_t i = 0; i < loop.size(); ++i)
                tri(m.positions[loop[i]].cast<double>(), m.positions[loop[(i + 1) % loop.size()]].cast<double>(), c);
        }
    }
    return v / 6.0;
}

// Whether two triangles over the same corners run the same way round.
bool same_turn(const Triangle& a, const Triangle& b) {
    for (int k = 0; k < 3; ++k)
        if (a[0] == b[size_t(k)]) return a[1] == b[size_t((k + 1) % 3)];
    return false;
}

// Degenerate (repeated corners, zero area) and duplicate triangles out. A triangle repeated the
// same way round is one triangle written twice: one copy stays. A triangle repeated the other
// way round is a fin, a two-sided flap of no volume (suzanne has one at its ear): both copies go,
// since the one left would be a third face on the edge it hangs from and pair there with a face
// of the surface, breaking the sheet it belongs to.
void drop_bad_triangles(TriangleMesh& m, float diag, RepairReport& r) {
    const double min_area2 = double(diag) * diag * 1e-14;  // (twice the area)^2 below this is zero
    // The triangles with corners and area, each with its corners sorted: copies of one triangle
    // sort next to each other, the first written first.
    struct Entry {
        std::array<uint32_t, 3> sorted;
        uint32_t index;
        bool operator<(const Entry& o) const { return std::tie(sorted, index) < std::tie(o.sorted, o.index); }
    };
    std::vector<Entry> entries;
    entries.reserve(m.triangles.size());
    for (uint32_t i = 0; i < m.triangles.size(); ++i) {
        const Triangle& t = m.triangles[i];
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) { ++r.degenerate_triangles; continue; }
        const Vec3d a = m.positions[t[0]].cast<double>();
        const double area2 = (m.positions[t[1]].cast<double>() - a).cross(m.positions[t[2]].cast<double>() - a).squaredNorm();
        if (area2 <= min_area2) { ++r.degenerate_triangles; continue; }
        std::array<uint32_t, 3> sorted = t;
        std::sort(sorted.begin(), sorted.end());
        entries.push_back({sorted, i});
    }
    std::sort(entries.begin(), entries.end());
    std::vector<uint8_t> keep(m.triangles.size(), 0);
    for (size_t a = 0; a < entries.size();) {
        size_t b = a + 1;
        bool fin = false;
        for (; b < entries.size() && entries[b].sorted == entries[a].sorted; ++b) {
            ++r.duplicate_triangles;
            fin = fin || !same_turn(m.triangles[entries[a].index], m.triangles[entries[b].index]);
        }
        if (fin) ++r.duplicate_triangles;
        else keep[entries[a].index] = 1;
        a = b;
    }
    std::vector<Triangle> kept;
    kept.reserve(entries.size());
    for (uint32_t i = 0; i < m.triangles.size(); ++i)
        if (keep[i]) kept.push_back(m.triangles[i]);
    m.triangles = std::move(kept);
}

using Adjacency = std::unordered_map<uint64_t, std::array<uint32_t, 2>>;  // edge -> the two faces it joins

// Face adjacency: an edge joins at most two triangles; a third and beyond are cut loose. The
// edges are sorted once (each with its face, in face order) rather than gathered in a hash map of
// vectors, which spent most of its time allocating on a scan of half a million triangles.
Adjacency face_adjacency(const TriangleMesh& m, RepairReport& r) {
    std::vector<std::pair<uint64_t, uint32_t>> edges;
    edges.reserve(m.triangles.size() * 3);
    for (uint32_t f = 0; f < m.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) edges.emplace_back(edge_key(m.triangles[f][size_t(k)], m.triangles[f][size_t((k + 1) % 3)]), f);
    std::sort(edges.begin(), edges.end());
    Adjacency adjacent;
    adjacent.reserve(edges.size() / 2);
    for (size_t a = 0; a < edges.size();) {
        size_t b = a + 1;
        while (b < edges.size() && edges[b].first == edges[a].first) ++b;
        if (b - a > 2) ++r.nonmanifold_edges;
        if (b - a >= 2) adjacent[edges[a].first] = {edges[a].second, edges[a + 1].second};
        a = b;
    }
    return adjacent;
}

// Consistent orientation by breadth-first search over adjacent faces. Where a neighbour
// cannot be made consistent (a non-orientable strip), the join is cut instead.
void orient_consistently(TriangleMesh& m, Adjacency& adjacent, RepairReport& r) {
    const uint32_t nf = uint32_t(m.triangles.size());
    auto has_directed = [&](uint32_t f, uint32_t a, uint32_t b) {
        const Triangle& t = m.triangles[f];
        for (int k = 0; k < 3; ++k)
            if (t[size_t(k)] == a && t[size_t((k + 1) % 3)] == b) return true;
        return false;
    };
    std::vector<int8_t> flip(nf, -1);
    std::vector<std::vector<std::pair<uint32_t, uint64_t>>> neighbours(nf);
    for (const auto& [key, pair] : adjacent) {
        neighbours[pair[0]].push_back({pair[1], key});
        neighbours[pair[1]].push_back({pair[0], key});
    }
    for (auto& n : neighbours) std::sort(n.begin(), n.end());  // deterministic walk
    std::vector<uint32_t> queue;
    for (uint32_t seed = 0; seed < nf; ++seed) {
        if (flip[seed] != -1) continue;
        flip[seed] = 0;
        queue.assign(1, seed);
        for (size_t q = 0; q < queue.size(); ++q) {
            const uint32_t f = queue[q];
            for (const auto& [g, key] : neighbours[f]) {
                const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
                // f (as oriented) runs a->b or b->a; g must run the other way.
                const bool f_ab = has_directed(f, a, b) != bool(flip[f]);
                const bool g_ab_raw = has_directed(g, a, b);
                const int8_t want = int8_t(g_ab_raw == f_ab ? 1 : 0);
                if (flip[g] == -1) {
                    flip[g] = want;
                    queue.push_back(g);
                } else if (flip[g] != want) {
                    adjacent.erase(key);  // non-orientable: cut here
                }
            }
        }
    }
    for (uint32_t f = 0; f < nf; ++f)
        if (flip[f] == 1) std::swap(m.triangles[f][1], m.triangles[f][2]), ++r.flipped_triangles;
}

// Split vertices whose triangles form several fans (bow-ties, and the ends of cut edges).
// Decided on the unsplit triangles first, applied after, so every lookup sees original ids.
void split_fans(TriangleMesh& m, const Adjacency& adjacent, RepairReport& r) {
    std::vector<std::vector<uint32_t>> faces_at(m.positions.size());
    for (uint32_t f = 0; f < m.triangles.size(); ++f)
        for (uint32_t v : m.triangles[f]) faces_at[v].push_back(f);
    std::vector<uint32_t> source(m.positions.size());
    std::iota(source.begin(), source.end(), 0u);
    std::vector<Triangle> split = m.triangles;
    // Per vertex, over the positions of its fan (a handful of faces): a union-find, and the copy
    // of v each group's root takes. Small arrays searched in place: hash maps cleared per vertex
    // spent more on allocation than on the work.
    std::vector<uint32_t> parent, copy_of;
    for (uint32_t v = 0; v < faces_at.size(); ++v) {
        const auto& fan = faces_at[v];
        if (fan.size() <= 1) continue;
        const auto position = [&](uint32_t f) { return uint32_t(std::find(fan.begin(), fan.end(), f) - fan.begin()); };
        // Union the faces around v that are joined through an edge incident to v.
        parent.resize(fan.size());
        std::iota(parent.begin(), parent.end(), 0u);
        auto find = [&](uint32_t x) {
            while (parent[x] != x) x = parent[x] = parent[parent[x]];
            return x;
        };
        for (uint32_t f : fan)
            for (uint32_t w : m.triangles[f]) {
                if (w == v) continue;
                auto it = adjacent.find(edge_key(v, w));
                if (it == adjacent.end()) continue;
                const uint32_t p0 = position(it->second[0]), p1 = position(it->second[1]);
                if (p0 < fan.size() && p1 < fan.size()) parent[find(p0)] = find(p1);
            }
        copy_of.assign(fan.size(), UINT32_MAX);
        bool first = true;
        for (uint32_t q = 0; q < fan.size(); ++q) {  // the group of the first face keeps v
            uint32_t& copy = copy_of[find(q)];
            if (copy == UINT32_MAX) {
                copy = first ? v : uint32_t(source.size());
                if (!first) source.push_back(v), ++r.split_vertices;
                first = false;
            }
            const uint32_t f = fan[q];
            for (int k = 0; k < 3; ++k)
                if (m.triangles[f][size_t(k)] == v) split[f][size_t(k)] = copy;
        }
    }
    m.triangles = std::move(split);
    remap_vertices(m, source);
}

// Outward orientation per component: positive (capped) volume. Returns the component count.
uint32_t orient_outward(TriangleMesh& m, RepairReport& r) {
    std::vector<uint32_t> comp;
    const uint32_t nc = triangle_components(m, comp);
    std::vector<std::vector<uint32_t>> faces_of(nc);
    for (uint32_t f = 0; f < m.triangles.size(); ++f) faces_of[comp[f]].push_back(f);
    for (const auto& faces : faces_of)
        if (signed_volume_of(m, faces, true) < 0.0) {
            for (uint32_t f : faces) std::swap(m.triangles[f][1], m.triangles[f][2]);
            r.flipped_triangles += faces.size();
        }
    return nc;
}

// A fan in the loop's own order has the mesh's orientation (the capped volume in
// signed_volume_of is summed the same way).
void cap_holes(TriangleMesh& m, RepairReport& r) {
    for (const auto& loop : boundary_loops(m)) {
        if (loop.size() < 3) continue;
        Vec3f c = Vec3f::Zero();
        for (uint32_t q : loop) c += m.positions[q];
        c /= float(loop.size());
        uint32_t centre = uint32_t(m.positions.size());
        m.positions.push_back(c);
        if (!m.normals.empty()) m.normals.push_back(Vec3f::UnitZ());
        if (!m.colors.empty()) m.colors.push_back(m.colors[loop[0]]);
        if (!m.uvs.empty()) m.uvs.push_back(m.uvs[loop[0]]);
        for (size_t i = 0; i < loop.size(); ++i) m.triangles.push_back({loop[i], loop[(i + 1) % loop.size()], centre});
        ++r.capped_holes;
    }
}

// What is left: components, closedness, boundary.
void count_what_is_left(const TriangleMesh& m, RepairReport& r) {
    std::vector<uint32_t> comp;
    r.components = triangle_components(m, comp);
    std::vector<size_t> boundary_in(r.components, 0);
    std::unordered_map<uint64_t, uint32_t> uses;
    for (const Triangle& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++uses[edge_key(t[size_t(k)], t[size_t((k + 1) % 3)])];
    for (uint32_t f = 0; f < m.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k)
            if (uses[edge_key(m.triangles[f][size_t(k)], m.triangles[f][size_t((k + 1) % 3)])] == 1) ++boundary_in[comp[f]], ++r.boundary_edges;
    r.closed_components = size_t(std::count(boundary_in.begin(), boundary_in.end(), size_t(0)));
    r.boundary_loops = boundary_loops(m).size();
    r.output_vertices = m.positions.size();
    r.output_triangles = m.triangles.size();
}

core::Status check_input(const TriangleMesh& m, const std::string& name) {
    if (m.triangles.empty()) return core::make_error(name, 0, "the mesh has no triangles");
    for (size_t i = 0; i < m.positions.size(); ++i)
        if (!m.positions[i].allFinite()) return core::make_error(name, 0, "vertex " + std::to_string(i + 1) + " has a non-finite coordinate");
    for (const Triangle& t : m.triangles)
        for (uint32_t v : t)
            if (v >= m.positions.size())
                return core::make_error(name, 0, "a triangle refers to vertex " + std::to_string(v + 1) + " of " + std::to_string(m.positions.size()));
    return core::Status::success();
}

std::string largest_coordinate(const TriangleMesh& m) {
    float largest = 0.0f;
    for (const Vec3f& p : m.positions) largest = std::max(largest, p.cwiseAbs().maxCoeff());
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", double(largest));
    return text;
}

} // namespace

std::string RepairReport::summary() const {
    return std::to_string(input_vertices) + " vertices / " + std::to_string(input_triangles) + " triangles in, " +
           std::to_string(output_vertices) + " / " + std::to_string(output_triangles) + " out; welded " +
           std::to_string(welded_vertices) + ", unreferenced " + std::to_string(unreferenced_vertices) +
           ", degenerate " + std::to_string(degenerate_triangles) + ", duplicate " + std::to_string(duplicate_triangles) +
           ", non-manifold edges " + std::to_string(nonmanifold_edges) + ", split vertices " +
           std::to_string(split_vertices) + ", flipped " + std::to_string(flipped_triangles) + "; " +
           std::to_string(components) + " component(s), " + std::to_string(closed_components) + " closed, " +
           std::to_string(boundary_loops) + " boundary loop(s), " + std::to_string(boundary_edges) + " boundary edges" +
           (capped_holes ? "; " + std::to_string(capped_holes) + " hole(s) capped" : std::string());
}

core::Result<RepairedMesh> repair(TriangleMesh m, const RepairOptions& options, const std::string& name) {
    RepairReport r;
    r.input_vertices = m.positions.size();
    r.input_triangles = m.triangles.size();
    PBDSPLAT_TRY(check_input(m, name));

    // Only vertices that triangles use define the scale (the bunny has stray ones).
    r.unreferenced_vertices = drop_unreferenced(m);
    const float diag = bounds(m).diagonal();
    if (std::isinf(diag))  // each coordinate is finite (check_input) but the extent is not a float
        return core::make_error(name, 0, "the mesh's extent overflows single precision (coordinates near " + largest_coordinate(m) +
                                             "): scale the model down before loading it");
    if (!(diag > 0.0f)) return core::make_error(name, 0, "all vertices coincide: the mesh has no extent");
    r.welded_vertices = weld(m, options.weld_tolerance * diag);
    drop_bad_triangles(m, diag, r);
    r.unreferenced_vertices += drop_unreferenced(m);  // a fin's tip belongs to nothing now
    if (m.triangles.empty())
        return core::make_error(name, 0, "all " + std::to_string(r.input_triangles) + " triangles are degenerate (repeated corners or zero area)");

    Adjacency adjacent = face_adjacency(m, r);
    orient_consistently(m, adjacent, r);
    split_fans(m, adjacent, r);
    orient_outward(m, r);

    // Centre and scale.
    const Bounds b = bounds(m);
    const Vec3f shift = options.center ? Vec3f(-b.center()) : Vec3f::Zero();
    float s = options.scale;
    if (options.fit_diagonal > 0.0f) s *= options.fit_diagonal / b.diagonal();
    if (!(s > 0.0f) || !std::isfinite(s)) return core::make_error(name, 0, "the scale must be a positive number");
    for (Vec3f& p : m.positions) p = (p + shift) * s;

    if (options.close_holes) cap_holes(m, r);
    count_what_is_left(m, r);
    return RepairedMesh{std::move(m), r, shift, s};
}

} // namespace pbdsplat::mesh
