#include "topology/edit.h"

#include <algorithm>
#include <numeric>

#include "core/assert.h"
#include "core/key_table.h"
#include "core/radix_sort.h"
#include "core/small_sort.h"
#include "mesh/topology.h"
#include "sim/volume.h"
#include "topology/particle_scratch.h"

namespace pbdsplat::topology {

namespace {
float area_of(const std::vector<Vec3f>& p, const mesh::Triangle& t) {
    return 0.5f * (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).norm();
}
} // namespace

Edit::Edit(sim::SoftBody& body) : b_(body), n0_(body.particle_count()), t0_(body.triangles.size()) {
    change.particles_before = n0_;
    change.triangles_before = t0_;
}

uint32_t Edit::point_on(uint32_t i, uint32_t j) const {
    const auto it = point_of_edge_.find(edge_key(i, j));
    return it == point_of_edge_.end() ? UINT32_MAX : points_[it->second].vertex;
}

uint32_t Edit::new_particle(uint32_t from) {
    const uint32_t v = uint32_t(b_.particle_count());
    sim::Particles& p = b_.particles;
    p.x.push_back(p.x[from]);
    p.x_prev.push_back(p.x_prev[from]);
    p.v.push_back(p.v[from]);
    p.w.push_back(p.w[from]);
    b_.rest_positions.push_back(b_.rest_positions[from]);
    if (!b_.colors.empty()) b_.colors.push_back(b_.colors[from]);
    if (!b_.texcoords.empty()) b_.texcoords.push_back(b_.texcoords[from]);
    if (b_.model_of_particle.size() + 1 == p.x.size()) b_.model_of_particle.push_back(b_.model_of_particle[from]);
    if (b_.part_of_particle.size() + 1 == p.x.size()) b_.part_of_particle.push_back(b_.part_of_particle[from]);
    b_.normals.push_back(from < b_.normals.size() ? b_.normals[from] : Vec3f::UnitY());
    b_.piece_of_particle.push_back(b_.piece_of_particle[from]);  // until the volume policy finds the pieces
    origin_.push_back(origin(from));
    return v;
}

void Edit::add_edge_point(uint32_t i, uint32_t j, float t) {
    PBDSPLAT_ASSERT(i < j && i < n0_ && j < n0_, "edge points split original edges, given as (low, high)");
    const uint32_t v = new_particle(i);
    origin_.back() = v;  // an edge point is its own origin
    sim::Particles& p = b_.particles;
    auto lerp4 = [t](const Vec4f& a, const Vec4f& c) { return Vec4f(a + t * (c - a)); };
    p.x[v] = lerp4(p.x[i], p.x[j]);
    p.x_prev[v] = lerp4(p.x_prev[i], p.x_prev[j]);
    p.v[v] = lerp4(p.v[i], p.v[j]);
    p.w[v] = 1.0f;  // set by redistribute_mass
    b_.rest_positions[v] = b_.rest_positions[i] + t * (b_.rest_positions[j] - b_.rest_positions[i]);
    if (!b_.colors.empty()) b_.colors[v] = b_.colors[i] + t * (b_.colors[j] - b_.colors[i]);
    if (!b_.texcoords.empty()) b_.texcoords[v] = mesh::lerp(b_.texcoords[i], b_.texcoords[j], t);
    const Vec3f n = b_.normals[i] + t * (b_.normals[j] - b_.normals[i]);
    b_.normals[v] = n.norm() > 0.0f ? Vec3f(n.normalized()) : b_.normals[i];
    point_of_edge_.emplace(edge_key(i, j), uint32_t(points_.size()));
    points_.push_back({i, j, t, v});
}

int Edit::side(const mesh::Triangle& t) const {
    for (uint32_t v : t)
        if (v < n0_ && sign[v] != 0) return sign[v];
    return 1;
}

void Edit::add_child(uint32_t parent, bool first, const mesh::Triangle& corners, const std::array<Vec3f, 3>& bary) {
    uint32_t index = parent;
    if (first) {
        b_.triangles[parent] = corners;
    } else {
        index = uint32_t(b_.triangles.size());
        b_.triangles.push_back(corners);
    }
    change.splits.push_back({index, parent, bary});
}

void Edit::retriangulate(uint32_t t) {
    const mesh::Triangle tri = b_.triangles[t];
    parents_.emplace(t, tri);
    uint32_t point[3];
    float u[3];  // parameter of the point from corner k toward corner k + 1
    int crossed = 0;
    for (int k = 0; k < 3; ++k) {
        const uint32_t a = tri[size_t(k)], c = tri[size_t((k + 1) % 3)];
        const auto it = point_of_edge_.find(edge_key(a, c));
        point[k] = UINT32_MAX;
        if (it == point_of_edge_.end()) continue;
        const EdgePoint& ep = points_[it->second];
        point[k] = ep.vertex;
        u[k] = ep.i == a ? ep.t : 1.0f - ep.t;
        ++crossed;
    }
    const Vec3f e[3] = {Vec3f::UnitX(), Vec3f::UnitY(), Vec3f::UnitZ()};
    auto on_edge = [&](int k) { return Vec3f((1.0f - u[k]) * e[k] + u[k] * e[(k + 1) % 3]); };
    PBDSPLAT_ASSERT(crossed == 1 || crossed == 2, "a plane crosses one or two edges of a triangle; three means the vertex sides are inconsistent");
    if (crossed == 1) {
        const int k = point[0] != UINT32_MAX ? 0 : point[1] != UINT32_MAX ? 1 : 2;
        const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        const uint32_t p = point[k];
        const Vec3f bp = on_edge(k);
        add_child(t, true, {tri[size_t(k)], p, tri[size_t(k2)]}, {e[k], bp, e[k2]});
        add_child(t, false, {p, tri[size_t(k1)], tri[size_t(k2)]}, {bp, e[k1], e[k2]});
        return;
    }
    // The lone vertex a is where both crossed edges meet: edges k (a -> b) and k + 2 (c -> a).
    const int k = point[0] != UINT32_MAX && point[2] != UINT32_MAX ? 0 : point[0] != UINT32_MAX ? 1 : 2;
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    const uint32_t a = tri[size_t(k)], bb = tri[size_t(k1)], c = tri[size_t(k2)];
    const uint32_t p = point[k], q = point[k2];
    const Vec3f bp = on_edge(k), bq = on_edge(k2);
    add_child(t, true, {a, p, q}, {e[k], bp, bq});
    // The quad p, b, c, q: split along its shorter rest diagonal.
    const auto& r = b_.rest_positions;
    if ((r[p] - r[c]).squaredNorm() <= (r[bb] - r[q]).squaredNorm()) {
        add_child(t, false, {p, bb, c}, {bp, e[k1], e[k2]});
        add_child(t, false, {p, c, q}, {bp, e[k2], bq});
    } else {
        add_child(t, false, {p, bb, q}, {bp, e[k1], bq});
        add_child(t, false, {bb, c, q}, {e[k1], e[k2], bq});
    }
}

bool Edit::split_fan(uint32_t v, const std::vector<uint32_t>& fan, std::vector<uint32_t>& root) {
    const size_t m = fan.size();
    root.resize(m);
    std::iota(root.begin(), root.end(), 0u);
    auto find = [&](uint32_t x) {
        while (root[x] != x) x = root[x] = root[root[x]];
        return x;
    };
    for (size_t a = 0; a < m; ++a)
        for (size_t c = a + 1; c < m; ++c) {
            const mesh::Triangle& ta = b_.triangles[fan[a]];
            const mesh::Triangle& tc = b_.triangles[fan[c]];
            for (uint32_t w : ta) {
                if (w == v || std::find(tc.begin(), tc.end(), w) == tc.end()) continue;
                // They share edge (v, w): joined unless it is a cut edge.
                if (!(on_cut(w) && side(ta) != side(tc))) root[find(uint32_t(a))] = find(uint32_t(c));
            }
        }
    // Fans ordered by their lowest triangle; the first keeps v.
    std::vector<std::pair<uint32_t, uint32_t>> fan_of;  // (root, lowest triangle)
    for (size_t a = 0; a < m; ++a) {
        const uint32_t r = find(uint32_t(a));
        auto it = std::find_if(fan_of.begin(), fan_of.end(), [r](const auto& f) { return f.first == r; });
        if (it == fan_of.end()) fan_of.push_back({r, fan[a]});
        else it->second = std::min(it->second, fan[a]);
    }
    if (fan_of.size() < 2) return false;
    std::sort(fan_of.begin(), fan_of.end(), [](const auto& x, const auto& y) { return x.second < y.second; });
    for (size_t g = 1; g < fan_of.size(); ++g) {
        const uint32_t copy = new_particle(v);
        ++change.duplicated_vertices;
        for (size_t a = 0; a < m; ++a)
            if (find(uint32_t(a)) == fan_of[g].first)
                for (uint32_t& corner : b_.triangles[fan[a]])
                    if (corner == v) corner = copy;
    }
    return true;
}

void Edit::split_vertices_along_cut() {
    // Triangles around every vertex on the cut: an original vertex's from its ring (before the
    // edit; a re-used parent index may have lost it), and the children of the split triangles.
    std::vector<uint64_t> children;  // (corner on the cut) << 32 | child
    for (const mesh::TriangleSplit& s : change.splits)
        for (uint32_t v : b_.triangles[s.triangle])
            if (on_cut(v)) children.push_back(uint64_t(v) << 32 | s.triangle);
    core::radix_sort(std::span(children));
    std::vector<uint32_t> candidates = on_cut_vertices;
    for (uint64_t c : children) candidates.push_back(uint32_t(c >> 32));
    core::radix_sort_unique(candidates);  // deterministic copy numbering

    std::vector<uint32_t> root, fan;
    auto child = children.begin();  // both ascend: one walk along the children
    for (uint32_t v : candidates) {
        fan.clear();
        if (v < n0_)
            for (uint32_t t : b_.rings.triangles.of(v))
                if (std::ranges::find(b_.triangles[t], v) != b_.triangles[t].end()) fan.push_back(t);
        while (child != children.end() && uint32_t(*child >> 32) < v) ++child;
        for (; child != children.end() && uint32_t(*child >> 32) == v; ++child) fan.push_back(uint32_t(*child));
        core::insertion_sort(fan.begin(), fan.end());  // a fan is a handful of triangles
        fan.erase(std::unique(fan.begin(), fan.end()), fan.end());
        if (fan.empty()) continue;
        if (!split_fan(v, fan, root)) continue;
        local_triangles_.insert(local_triangles_.end(), fan.begin(), fan.end());
    }
    // The local triangles: the children and those around duplicated vertices.
    for (const mesh::TriangleSplit& s : change.splits) local_triangles_.push_back(s.triangle);
    core::radix_sort_unique(local_triangles_);
}

void Edit::update_rings() {
    // Every vertex whose triangles changed is a corner of a local triangle: a parent's corners
    // are corners of its children, a duplicated vertex keeps one fan.
    std::vector<uint32_t> region;
    for (uint32_t t : local_triangles_) region.insert(region.end(), b_.triangles[t].begin(), b_.triangles[t].end());
    core::radix_sort_unique(region);
    sim::update_vertex_rings(b_.rings, b_.triangles, b_.particle_count(), region, local_triangles_);
    if (!b_.rings.rest_area.empty()) sim::update_rest_ring_areas(b_.rings, b_.rest_positions, region);
    region_ = std::move(region);
    b_.normals.resize(b_.particle_count(), Vec3f(0.0f, 1.0f, 0.0f));
}

void Edit::redistribute_mass() {
    const std::vector<uint32_t>& region = region_;
    if (region.empty()) return;
    // Each model's share apart: a stroke through a pinned table and the teapot on it must not
    // hand the teapot's mass to the table's new particles (they came loose and jittered).
    const bool models = b_.model_of_particle.size() == b_.particle_count();
    const auto model = [&](uint32_t v) { return models ? b_.model_of_particle[v] : 0u; };
    std::vector<uint32_t> ids;
    for (uint32_t v : region) ids.push_back(model(v));
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    // A third of each triangle's rest area, summed in triangle order (as a pass over the whole
    // list would), from the rings made again for the region.
    std::vector<float> area(region.size(), 0.0f);
    for (size_t k = 0; k < region.size(); ++k)
        for (uint32_t t : b_.rings.triangles.of(region[k])) area[k] += area_of(b_.rest_positions, b_.triangles[t]) / 3.0f;
    for (uint32_t id : ids) {
        double mass = 0.0, total = 0.0;
        for (size_t k = 0; k < region.size(); ++k) {
            const uint32_t v = region[k];
            if (model(v) != id) continue;
            if (v < n0_ && b_.particles.w[v] > 0.0f) mass += 1.0 / double(b_.particles.w[v]);
            // Pinned particles (and their copies) stay pinned and take no share.
            if (b_.particles.w[v] > 0.0f) total += area[k];
        }
        for (size_t k = 0; k < region.size(); ++k) {
            const uint32_t v = region[k];
            if (model(v) != id || b_.particles.w[v] == 0.0f) continue;
            const double m = total > 0.0 ? mass * double(area[k]) / total : 0.0;
            b_.particles.w[v] = m > 0.0 ? float(1.0 / m) : 0.0f;
        }
    }
}

std::vector<Edit::Definition> Edit::constraints_to_remake() const {
    // Old edges whose constraints are re-made: the parents' edges, and every edge of a local
    // triangle in terms of the original vertices. Their ends' constraints are read once each
    // (a per-thread mark), and each is looked up among those edges in a table sized for them.
    thread_local ParticleScratch<uint8_t> marks(0);
    std::vector<uint8_t>& marked = marks.take(n0_);
    core::KeySet old_edges(3 * (parents_.size() + local_triangles_.size()));
    std::vector<uint32_t> touched;
    auto mark = [&](uint32_t a, uint32_t c) {
        if (a >= n0_ || c >= n0_) return;
        old_edges.insert(edge_key(a, c));
        for (uint32_t v : {a, c})
            if (!marked[v]) marked[v] = 1, touched.push_back(v);
    };
    for (const auto& [t, tri] : parents_)
        for (int k = 0; k < 3; ++k) mark(tri[size_t(k)], tri[size_t((k + 1) % 3)]);
    for (uint32_t t : local_triangles_)
        for (int k = 0; k < 3; ++k) mark(origin(b_.triangles[t][size_t(k)]), origin(b_.triangles[t][size_t((k + 1) % 3)]));
    marks.give_back(touched);
    // The order met does not matter: the caller keys them by edge, the later slot defining it.
    std::vector<Definition> removed;
    for (uint32_t a : touched)
        for (uint32_t slot : b_.distance_groups.of_particle.of(a)) {
            const sim::DistanceConstraint& c = b_.distance[slot];
            if (a != std::min(c.i, c.j)) continue;  // met from its lower end only
            const uint64_t k = edge_key(c.i, c.j);
            if (old_edges.contains(k)) removed.push_back({k, slot, c.rest, c.compliance});
        }
    return removed;
}

void Edit::update_distance_constraints() {
    const std::vector<uint32_t>& local = local_triangles_;
    std::vector<Definition> removed = constraints_to_remake();
    float default_compliance = 0.0f;  // the last removed in array order
    uint32_t last_slot = 0;
    for (const Definition& d : removed)
        if (d.slot >= last_slot) last_slot = d.slot, default_compliance = d.compliance;
    if (removed.empty())
        for (const sim::DistanceConstraint& c : b_.distance)
            if (c.alive()) {
                default_compliance = c.compliance;
                break;
            }
    // By key for lookups; of two constraints on one edge the later slot defines it. The map
    // holds 1 + the definition's index (0: a key just met).
    core::KeyMap<uint32_t> by_key(removed.size());
    for (uint32_t k = 0; k < removed.size(); ++k) {
        uint32_t& at = by_key[removed[k].key];
        if (at == 0 || removed[at - 1].slot < removed[k].slot) at = k + 1;
    }
    auto definition = [&](uint64_t key) -> const Definition* {
        const uint32_t* at = by_key.find(key);
        return at ? &removed[*at - 1] : nullptr;
    };
    std::vector<uint8_t> kept(removed.size(), 0);  // edges the edit left as they were keep their constraint where it is

    std::vector<sim::DistanceConstraint> added;
    std::vector<uint64_t> emitted;
    for (uint32_t t : local)
        for (int k = 0; k < 3; ++k) emitted.push_back(edge_key(b_.triangles[t][size_t(k)], b_.triangles[t][size_t((k + 1) % 3)]));
    core::radix_sort_unique(emitted);  // each new edge once, in key order (deterministic)
    for (const uint64_t key : emitted) {
        const uint32_t a = uint32_t(key >> 32), c = uint32_t(key);
        const uint32_t oa = origin(a), oc = origin(c);
        if (const Definition* d = definition(edge_key(oa, oc))) {
            // Both ends the particles they were (not split off, not new): the same constraint.
            if (a == oa && c == oc) kept[size_t(d - removed.data())] = 1;
            else added.push_back({a, c, d->rest, d->compliance});
            continue;
        }
        if (!is_edge_point(oa) && !is_edge_point(oc)) continue;  // an edge nobody constrained
        // A half of a split edge keeps the fraction t of the parent's rest length; a new edge
        // across a triangle takes its length in the rest state.
        const uint32_t pv = is_edge_point(oa) ? oa : oc, other = pv == oa ? oc : oa;
        const EdgePoint& ep = points_[pv - n0_];
        const Definition* parent = definition(edge_key(ep.i, ep.j));
        const float compliance = parent ? parent->compliance : default_compliance;
        float rest = (b_.rest_positions[a] - b_.rest_positions[c]).norm();
        if ((other == ep.i || other == ep.j) && parent) rest = parent->rest * (other == ep.i ? ep.t : 1.0f - ep.t);
        added.push_back({a, c, rest, compliance});
    }
    std::vector<uint32_t> removed_slots;
    for (size_t k = 0; k < removed.size(); ++k)
        if (!kept[k]) removed_slots.push_back(removed[k].slot);
    core::radix_sort(std::span(removed_slots));
    sim::replace_distance_constraints(b_.distance, b_.distance_groups, b_.distance_lambda, b_.particle_count(), removed_slots, added);
    change.constraints_removed = removed_slots.size();
    change.constraints_added = added.size();
}

void Edit::finish() {
    change.particles_after = b_.particle_count();
    change.triangles_after = b_.triangles.size();
    change.touched_triangles = local_triangles_;
}

} // namespace pbdsplat::topology
