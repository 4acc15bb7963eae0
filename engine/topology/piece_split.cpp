#include "topology/piece_split.h"

#include <algorithm>
#include <optional>

#include "topology/particle_scratch.h"

namespace pbdsplat::topology {

namespace {
Vec3d at(const sim::SoftBody& b, uint32_t i) { return b.particles.x[i].head<3>().cast<double>(); }

// Calls f(a, e1, e2) (first corner and the two edges from it) for the triangles whose first
// corner is v: over a part's particles, each of its triangles once.
template <class F>
void for_triangles_at(const sim::SoftBody& b, uint32_t v, F&& f) {
    for (uint32_t i : b.rings.triangles.of(v)) {
        const mesh::Triangle& t = b.triangles[i];
        if (t[0] != v) continue;
        const Vec3d a = at(b, t[0]);
        f(a, Vec3d(at(b, t[1]) - a), Vec3d(at(b, t[2]) - a));
    }
}

// The part's sums over those triangles.
void add_triangles_at(const sim::SoftBody& b, uint32_t v, Part& part) {
    for_triangles_at(b, v, [&](const Vec3d& a, const Vec3d& e1, const Vec3d& e2) {
        part.six_v += a.dot((a + e1).cross(a + e2));
        part.area_bound += 0.25 * (e1.squaredNorm() + e2.squaredNorm());
        ++part.triangles;
    });
}

// Grows a part from `seed` along the rings, marking its particles in `seen` and summing its
// triangles (each at its first corner, so once).
Part grow_part(const sim::SoftBody& b, uint32_t seed, std::vector<uint8_t>& seen) {
    Part part;
    part.particles.push_back(seed);
    seen[seed] = 1;
    std::vector<uint32_t>& queue = part.particles;
    for (size_t q = 0; q < queue.size(); ++q) {
        // The search hops across the body's memory: fetch ahead what the next particles read
        // (their lists first, then what the lists point at). Halves the search at 164k particles.
        if (q + 16 < queue.size()) {
            __builtin_prefetch(b.rings.ring.of(queue[q + 16]).data());
            __builtin_prefetch(b.rings.triangles.of(queue[q + 16]).data());
        }
        if (q + 8 < queue.size()) {
            for (const auto& pair : b.rings.ring.of(queue[q + 8])) __builtin_prefetch(&b.particles.x[pair[0]]), __builtin_prefetch(&seen[pair[0]]);
            for (uint32_t f : b.rings.triangles.of(queue[q + 8])) __builtin_prefetch(&b.triangles[f]);
        }
        const uint32_t v = queue[q];
        for (const auto& pair : b.rings.ring.of(v))
            for (uint32_t w : pair)
                if (!seen[w]) seen[w] = 1, queue.push_back(w);
        add_triangles_at(b, v, part);
    }
    return part;
}

// The searches of one piece from its seeds at once (see split_pieces). Returns nothing past the
// budget.
std::optional<std::vector<Part>> search_locally(const sim::SoftBody& b, std::span<const uint32_t> seeds, size_t budget,
                                                std::vector<uint32_t>& owner, size_t& searched, std::vector<uint32_t>& written) {
    constexpr uint32_t unseen = UINT32_MAX;
    std::vector<uint32_t> parent, queued, visited;
    size_t roots = 0, open = 0;
    auto find = [&](uint32_t s) {
        while (parent[s] != s) s = parent[s] = parent[parent[s]];
        return s;
    };
    for (uint32_t v : seeds) {
        if (owner[v] != unseen) continue;
        owner[v] = uint32_t(parent.size());
        parent.push_back(owner[v]);
        queued.push_back(1);
        visited.push_back(v);
        ++roots, ++open;
    }
    size_t head = 0;
    while (roots > 1 && open > 1) {
        if (visited.size() > budget) {
            for (uint32_t v : visited) owner[v] = unseen;  // the whole search runs on a clean slate
            searched += visited.size();
            return std::nullopt;
        }
        const uint32_t v = visited[head++];
        uint32_t r = find(owner[v]);
        if (--queued[r] == 0) --open;
        for (const auto& pair : b.rings.ring.of(v))
            for (uint32_t w : pair) {
                if (owner[w] == unseen) {
                    owner[w] = r;
                    if (queued[r]++ == 0) ++open;
                    visited.push_back(w);
                } else if (const uint32_t o = find(owner[w]); o != r) {
                    // Two searches met: one group, open if either was.
                    open -= (queued[r] > 0) + (queued[o] > 0);
                    parent[o] = r;
                    queued[r] += queued[o];
                    open += queued[r] > 0;
                    --roots;
                }
            }
    }
    searched += visited.size();
    written.insert(written.end(), visited.begin(), visited.end());
    // The closed groups are whole parts; the open one (at most one is left) is the rest of the
    // piece, unexplored. One group left and open: the piece did not fall apart.
    uint32_t open_root = UINT32_MAX;
    for (uint32_t g = 0; g < parent.size(); ++g)
        if (find(g) == g && queued[g] > 0) open_root = g;
    std::vector<Part> parts;
    std::vector<uint32_t> part_of_root(parent.size(), UINT32_MAX);
    for (uint32_t v : visited) {
        const uint32_t g = find(owner[v]);
        if (g == open_root) continue;
        if (part_of_root[g] == UINT32_MAX) part_of_root[g] = uint32_t(parts.size()), parts.emplace_back();
        Part& part = parts[part_of_root[g]];
        part.particles.push_back(v);
        add_triangles_at(b, v, part);
    }
    std::stable_sort(parts.begin(), parts.end(), [](const Part& x, const Part& y) { return x.particles.size() > y.particles.size(); });
    if (open_root != UINT32_MAX) {
        parts.insert(parts.begin(), Part{});
        parts.front().complete = false;
    }
    return parts;
}
} // namespace

double part_area(const sim::SoftBody& b, const Part& part) {
    double area = 0.0;
    for (uint32_t v : part.particles)
        for_triangles_at(b, v, [&](const Vec3d&, const Vec3d& e1, const Vec3d& e2) { area += 0.5 * e1.cross(e2).norm(); });
    return area;
}

SplitSearch split_pieces(sim::SoftBody& b, std::span<const uint32_t> reached, std::span<const uint32_t> seeds, size_t budget) {
    SplitSearch out;
    thread_local ParticleScratch<uint32_t> owners(UINT32_MAX);
    std::vector<uint32_t>& owner = owners.take(b.particle_count());
    std::vector<uint32_t> written;  // by the local searches that settled their piece
    std::vector<uint8_t> seen;  // for the whole search, made when first needed
    out.parts_of.resize(reached.size());
    std::vector<uint32_t> mine;
    for (size_t r = 0; r < reached.size(); ++r) {
        mine.clear();
        for (uint32_t v : seeds)
            if (b.piece_of_particle[v] == reached[r]) mine.push_back(v);
        std::vector<Part>& parts = out.parts_of[r];
        if (auto local = search_locally(b, mine, budget, owner, out.searched, written)) {
            parts = std::move(*local);
        } else {
            ++out.searched_whole;
            if (seen.empty()) seen.assign(b.particle_count(), 0);
            for (uint32_t v : mine)
                if (!seen[v]) parts.push_back(grow_part(b, v, seen));
            std::stable_sort(parts.begin(), parts.end(), [](const Part& x, const Part& y) { return x.particles.size() > y.particles.size(); });
            for (const Part& part : parts) out.searched += part.particles.size();
        }
        for (size_t k = 0; k < parts.size(); ++k) {
            parts[k].label = k == 0 ? reached[r] : uint32_t(b.pieces++);
            if (k > 0)
                for (uint32_t v : parts[k].particles) b.piece_of_particle[v] = parts[k].label;
        }
    }
    owners.give_back(written);
    return out;
}

} // namespace pbdsplat::topology
