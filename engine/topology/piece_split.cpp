#include "topology/piece_split.h"

#include <algorithm>

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

// A part's sums over its triangles (a Part, or sums kept apart and added to one later).
struct TriangleSums {
    double six_v = 0.0, area_bound = 0.0;
    size_t triangles = 0;
};
template <class Sums>
void add_triangles_at(const sim::SoftBody& b, uint32_t v, Sums& sums) {
    for_triangles_at(b, v, [&](const Vec3d& a, const Vec3d& e1, const Vec3d& e2) {
        sums.six_v += a.dot((a + e1).cross(a + e2));
        sums.area_bound += 0.25 * (e1.squaredNorm() + e2.squaredNorm());
        ++sums.triangles;
    });
}

// The searches of one piece from its seeds at once (see split_pieces): breadth first over all
// of them while the search is small, then one group at a time.
class PieceSearch {
public:
    PieceSearch(const sim::SoftBody& b, std::vector<uint32_t>& owner) : b_(b), owner_(owner) {}

    std::vector<Part> run(std::span<const uint32_t> seeds, size_t budget, bool& went_deep, size_t& searched, std::vector<uint32_t>& written) {
        for (uint32_t v : seeds) {
            if (owner_[v] != k_unseen) continue;
            owner_[v] = uint32_t(parent_.size());
            parent_.push_back(owner_[v]);
            queued_.push_back(1);
            members_.push_back(1);
            visited_.push_back(v);
            ++roots_, ++open_;
        }
        // Breadth first: searches that meet merge, and a small part cut off closes early.
        while (roots_ > 1 && open_ > 1 && visited_.size() <= budget) visit(head_++);
        // Past the budget (two large parts, as a cut through the middle makes): one open group
        // at a time, the smallest so far, to its end or until it meets another. When all but
        // one have closed, the last is the rest and stays unexplored: the cut pays for the parts
        // cut off, not for the piece (half a sphere cut in two, not all of it).
        went_deep = roots_ > 1 && open_ > 1;
        if (went_deep) deep();
        searched += visited_.size();
        written.insert(written.end(), visited_.begin(), visited_.end());
        return parts();
    }

private:
    static constexpr uint32_t k_unseen = UINT32_MAX;
    uint32_t find(uint32_t s) {
        while (parent_[s] != s) s = parent_[s] = parent_[parent_[s]];
        return s;
    }
    // Expands the particle at position `at` of the search; new particles join its group.
    // `joined` receives the positions of particles new to the search.
    template <class Joined>
    void expand(size_t at, Joined&& joined) {
        const uint32_t v = visited_[at];
        const uint32_t r = find(owner_[v]);
        if (--queued_[r] == 0) --open_;
        for (const auto& pair : b_.rings.ring.of(v))
            for (uint32_t w : pair) {
                if (owner_[w] == k_unseen) {
                    owner_[w] = r;
                    if (queued_[r]++ == 0) ++open_;
                    ++members_[r];
                    visited_.push_back(w);
                    joined(visited_.size() - 1);
                } else if (const uint32_t o = find(owner_[w]); o != r) {
                    // Two searches met: one group, open if either was.
                    open_ -= (queued_[r] > 0) + (queued_[o] > 0);
                    parent_[o] = r;
                    queued_[r] += queued_[o];
                    members_[r] += members_[o];
                    open_ += queued_[r] > 0;
                    --roots_;
                }
            }
    }
    void visit(size_t at) {
        expand(at, [](size_t) {});
    }
    void deep() {
        // Per position: 0 waiting in the breadth-first queue, 1 taken by the group being
        // searched, 2 expanded. Positions before head_ are expanded already.
        std::vector<uint8_t> state(visited_.size(), 0);
        std::fill(state.begin(), state.begin() + long(head_), uint8_t(2));
        std::vector<size_t> mine;
        // Each particle's triangles are summed as it is expanded, while what they read is at
        // hand (summing the part afterwards, in search order, read it all again from memory).
        deep_sums_.assign(parent_.size(), {});
        while (roots_ > 1 && open_ > 1) {
            uint32_t group = UINT32_MAX;
            for (uint32_t g = 0; g < parent_.size(); ++g)
                if (find(g) == g && queued_[g] > 0 && (group == UINT32_MAX || members_[g] < members_[group])) group = g;
            mine.clear();
            auto take_waiting = [&](uint32_t root) {
                for (size_t p = head_; p < visited_.size(); ++p)
                    if (state[p] == 0 && find(owner_[visited_[p]]) == root) state[p] = 1, mine.push_back(p);
            };
            take_waiting(group);
            const uint32_t roots_before = roots_;
            for (size_t q = 0; q < mine.size() && open_ > 1; ++q) {
                // The search hops across the body's memory: fetch ahead what the next particles
                // read (their lists first, then what the lists point at).
                if (q + 16 < mine.size()) {
                    __builtin_prefetch(b_.rings.ring.of(visited_[mine[q + 16]]).data());
                    __builtin_prefetch(b_.rings.triangles.of(visited_[mine[q + 16]]).data());
                }
                if (q + 8 < mine.size()) {
                    const uint32_t ahead = visited_[mine[q + 8]];
                    for (const auto& pair : b_.rings.ring.of(ahead))
                        __builtin_prefetch(&owner_[pair[0]]), __builtin_prefetch(&b_.particles.x[pair[0]]);
                    for (uint32_t f : b_.rings.triangles.of(ahead)) __builtin_prefetch(&b_.triangles[f]);
                }
                state[mine[q]] = 2;
                add_triangles_at(b_, visited_[mine[q]], deep_sums_[find(owner_[visited_[mine[q]]])]);
                expand(mine[q], [&](size_t p) {
                    state.push_back(1);
                    mine.push_back(p);
                });
                // Met another group: its waiting particles are this search's now.
                if (roots_ != roots_before && q + 1 == mine.size()) take_waiting(find(group));
            }
            // Either the group closed (everything it took was expanded) or it is the last open
            // one, the rest, and the search ends here.
        }
    }
    // The closed groups are whole parts; the open one (at most one is left) is the rest of the
    // piece, unexplored. One group left and open: the piece did not fall apart.
    std::vector<Part> parts() {
        uint32_t open_root = UINT32_MAX;
        for (uint32_t g = 0; g < parent_.size(); ++g)
            if (find(g) == g && queued_[g] > 0) open_root = g;
        std::vector<Part> parts;
        std::vector<uint32_t> part_of_root(parent_.size(), UINT32_MAX);
        for (size_t p = 0; p < visited_.size(); ++p) {
            const uint32_t v = visited_[p];
            const uint32_t g = find(owner_[v]);
            if (g == open_root) continue;
            if (part_of_root[g] == UINT32_MAX) part_of_root[g] = uint32_t(parts.size()), parts.emplace_back();
            Part& part = parts[part_of_root[g]];
            part.particles.push_back(v);
            if (p < head_) add_triangles_at(b_, v, part);  // expanded breadth first; the rest summed as expanded
        }
        for (uint32_t g = 0; g < deep_sums_.size(); ++g) {
            const uint32_t root = find(g);
            if (root == open_root || part_of_root[root] == UINT32_MAX) continue;
            Part& part = parts[part_of_root[root]];
            part.six_v += deep_sums_[g].six_v;
            part.area_bound += deep_sums_[g].area_bound;
            part.triangles += deep_sums_[g].triangles;
        }
        std::stable_sort(parts.begin(), parts.end(), [](const Part& x, const Part& y) { return x.particles.size() > y.particles.size(); });
        if (open_root != UINT32_MAX) {
            parts.insert(parts.begin(), Part{});
            parts.front().complete = false;
        }
        return parts;
    }

    const sim::SoftBody& b_;
    std::vector<uint32_t>& owner_;
    std::vector<uint32_t> parent_, queued_, members_, visited_;
    std::vector<TriangleSums> deep_sums_;  // per group at the time of expansion (deep search only)
    size_t head_ = 0;
    uint32_t roots_ = 0, open_ = 0;
};
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
    std::vector<uint32_t> written;  // particles the searches labelled, to reset afterwards
    out.parts_of.resize(reached.size());
    std::vector<uint32_t> mine;
    for (size_t r = 0; r < reached.size(); ++r) {
        mine.clear();
        for (uint32_t v : seeds)
            if (b.piece_of_particle[v] == reached[r]) mine.push_back(v);
        bool went_deep = false;
        std::vector<Part>& parts = out.parts_of[r];
        parts = PieceSearch(b, owner).run(mine, budget, went_deep, out.searched, written);
        out.searched_whole += went_deep;
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
