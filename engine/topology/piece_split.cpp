#include "topology/piece_split.h"

#include <algorithm>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "sim/vec4_ops.h"
#include "topology/particle_scratch.h"

namespace pbdsplat::topology {

namespace {
// Adds triangle (a, b, c) to a part's sums: each triangle's terms in float (as the solver's
// volume pass takes them), the sums in double. Written out: a search sums a part cut off from a
// large body, hundreds of thousands of triangles.
inline void add_triangle(Part& part, const Vec4f& a, const Vec4f& b, const Vec4f& c) {
#if defined(__SSE__)
    // Four lanes, the same products and the same order of additions as the scalar code below
    // (the same bits): rows (a . cross terms, |p|^2 terms, |q|^2 terms) transposed so one pair of
    // adds sums all three.
    const Vec4f pv = b - a, qv = c - a;
    const __m128 p = _mm_load_ps(pv.data()), q = _mm_load_ps(qv.data());
    __m128 terms = _mm_mul_ps(_mm_load_ps(a.data()), _mm_load_ps(sim::cross3<float>(pv, qv).data()));  // (ax cx, ay cy, az cz)
    __m128 pp = _mm_mul_ps(p, p), qq = _mm_mul_ps(q, q), zero = _mm_setzero_ps();
    _MM_TRANSPOSE4_PS(terms, pp, qq, zero);  // now terms = x lanes, pp = y lanes, qq = z lanes
    float sums[4];
    _mm_storeu_ps(sums, _mm_add_ps(_mm_add_ps(terms, pp), qq));
    part.six_v += double(sums[0]);
    part.area_bound += 0.25 * double(sums[1] + sums[2]);
    ++part.triangles;
#else
    const float px = b.x() - a.x(), py = b.y() - a.y(), pz = b.z() - a.z();
    const float qx = c.x() - a.x(), qy = c.y() - a.y(), qz = c.z() - a.z();
    const float cx = py * qz - pz * qy, cy = pz * qx - px * qz, cz = px * qy - py * qx;
    part.six_v += double(a.x() * cx + a.y() * cy + a.z() * cz);
    part.area_bound += 0.25 * double(px * px + py * py + pz * pz + (qx * qx + qy * qy + qz * qz));
    ++part.triangles;
#endif
}

// Adds v's share of a part's triangles to its sums: those whose lowest-numbered corner is v.
// The ring holds each triangle's other two corners in winding order, so the search, which reads
// the ring anyway, reads no triangle list.
void add_triangles_at(const sim::SoftBody& b, uint32_t v, Part& part) {
    for (const auto& [j, k] : b.rings.ring.of(v))
        if (j > v && k > v) add_triangle(part, b.particles.x[v], b.particles.x[j], b.particles.x[k]);
}

// sweep_parts' union-find over a piece's particles, in `up`: a root holds k_sweep_root and its
// part's size; once the particle pass has met it, k_sweep_part and the part's index instead.
constexpr uint32_t k_sweep_root = 0x80000000u, k_sweep_part = 0x40000000u, k_sweep_value = k_sweep_part - 1;

uint32_t sweep_root(std::vector<uint32_t>& up, uint32_t s) {
    while (!(up[s] & k_sweep_root)) {
        const uint32_t parent = up[s];
        if (up[parent] & k_sweep_root) return parent;
        s = up[s] = up[parent];  // halving: point at the grandparent and go there
    }
    return s;
}

// Every particle of the piece joined with its triangles' corners. Union by size keeps the trees
// shallow.
void sweep_union(const sim::SoftBody& b, uint32_t piece, std::vector<uint32_t>& up) {
    const std::vector<uint32_t>& label = b.piece_of_particle;
    up.resize(b.particle_count());
    std::fill(up.begin(), up.end(), k_sweep_root | 1u);
    auto link = [&](uint32_t a, uint32_t c) {
        if (a == c) return a;
        if ((up[a] & k_sweep_value) < (up[c] & k_sweep_value)) std::swap(a, c);
        up[a] += up[c] & k_sweep_value;
        up[c] = a;
        return a;
    };
    // Triangles come sorted by their first corner, so consecutive ones mostly share it: its root
    // is the last link's result (still a root: only these links change roots).
    uint32_t last = UINT32_MAX, last_root = 0;
    for (const mesh::Triangle& t : b.triangles) {
        if (label[t[0]] != piece) continue;
        const uint32_t r0 = t[0] == last ? last_root : sweep_root(up, t[0]);
        const uint32_t r01 = link(r0, sweep_root(up, t[1]));  // before the next find: link takes roots
        last = t[0], last_root = link(r01, sweep_root(up, t[2]));
    }
}

// A piece's parts by one union-find pass over its triangles in memory order, for an edit whose
// searches outgrew their budget (two large parts, as a cut through the middle makes). A search
// hops across memory and waits on a cache miss per particle; this pass streams the triangle
// list and keeps its work in a per-particle array that stays in cache, so it reads the whole
// piece several times faster than a search reads half of it. The largest part is the rest:
// it keeps the label and, like a search's unexplored rest, stays unsummed (`complete` false)
// unless `sum_rest` (the piece has no solver measure to take its volume from).
std::vector<Part> sweep_parts(const sim::SoftBody& b, uint32_t piece, bool sum_rest, std::vector<uint32_t>& up, size_t& searched) {
    const std::vector<uint32_t>& label = b.piece_of_particle;
    const uint32_t n = uint32_t(b.particle_count());
    PBDSPLAT_ASSERT(n <= k_sweep_value, "a body of more than 2^30 particles: sweep_parts packs flags into the particle index");
    sweep_union(b, piece, up);
    auto find = [&](uint32_t s) { return sweep_root(up, s); };
    // Parts numbered in the order of their lowest particle; every particle pointed at its root.
    std::vector<size_t> counts;
    for (uint32_t v = 0; v < n; ++v) {
        if (label[v] != piece) continue;
        const uint32_t r = find(v);
        if (r != v) up[v] = r;
        if (!(up[r] & k_sweep_part)) counts.push_back(up[r] & k_sweep_value), up[r] = k_sweep_root | k_sweep_part | uint32_t(counts.size() - 1);
        ++searched;
    }
    auto part_of = [&](uint32_t v) { return size_t(up[up[v] & k_sweep_root ? v : up[v]] & k_sweep_value); };
    std::vector<Part> parts(counts.size());
    if (parts.size() < 2) {  // the searches all met, beyond the region they saw
        parts.front().complete = false;
        return parts;
    }
    const size_t rest = size_t(std::max_element(counts.begin(), counts.end()) - counts.begin());
    const size_t skipped = sum_rest ? parts.size() : rest;
    if (!sum_rest) parts[rest].complete = false;
    for (size_t k = 0; k < parts.size(); ++k)
        if (k != skipped) parts[k].particles.reserve(counts[k]);
    for (uint32_t v = 0; v < n; ++v)
        if (label[v] == piece)
            if (const size_t k = part_of(v); k != skipped) parts[k].particles.push_back(v);
    const size_t triangles = b.triangles.size();
    for (size_t f = 0; f < triangles; ++f) {
        if (f + 16 < triangles) {
            const mesh::Triangle& ahead = b.triangles[f + 16];
            __builtin_prefetch(&b.particles.x[ahead[1]]), __builtin_prefetch(&b.particles.x[ahead[2]]);
        }
        const mesh::Triangle& t = b.triangles[f];
        if (label[t[0]] != piece) continue;
        const size_t k = part_of(t[0]);
        if (k == skipped) continue;
        add_triangle(parts[k], b.particles.x[t[0]], b.particles.x[t[1]], b.particles.x[t[2]]);
    }
    // The rest first, then the parts cut off, largest first.
    std::swap(parts[0], parts[rest]);
    std::stable_sort(parts.begin() + 1, parts.end(), [](const Part& x, const Part& y) { return x.particles.size() > y.particles.size(); });
    return parts;
}

// The searches of one piece from its seeds at once (see split_pieces): breadth first over all
// of them while the search is small, then a sweep of the whole piece.
class PieceSearch {
public:
    PieceSearch(const sim::SoftBody& b, std::vector<uint32_t>& owner, std::vector<uint32_t>& sweep) : b_(b), owner_(owner), sweep_(sweep) {}

    std::vector<Part> run(uint32_t piece, bool sum_rest, std::span<const uint32_t> seeds, std::span<const int8_t> side, size_t budget, bool& went_deep,
                          size_t& searched, std::vector<uint32_t>& written) {
        for (uint32_t v : seeds) {
            if (owner_[v] != k_unseen) continue;
            owner_[v] = uint32_t(parent_.size());
            parent_.push_back(owner_[v]);
            queued_.push_back(1);
            members_.push_back(1);
            visited_.push_back(v);
            ++roots_, ++open_;
        }
        // Breadth first: searches that meet merge, and a small part cut off closes early. With
        // sides, past the first rings around the edit, one part at a time is flooded instead.
        const size_t rings = std::min(budget, k_first_rings + 2 * seeds.size());
        bool flood_failed = false;
        while (roots_ > 1 && open_ > 1) {
            if (!side.empty() && visited_.size() >= rings) {
                if (!flood_one(piece, side)) {
                    flood_failed = true;
                    break;
                }
            } else if (visited_.size() <= budget) {
                visit(head_++);
            } else {
                break;
            }
        }
        searched += visited_.size();
        written.insert(written.end(), visited_.begin(), visited_.end());
        // Past the budget (two large parts, as a cut through the middle makes) the piece is
        // swept whole: see sweep_parts.
        went_deep = flood_failed || (roots_ > 1 && open_ > 1);
        if (went_deep) return sweep_parts(b_, piece, sum_rest, sweep_, searched);
        return parts();
    }

private:
    static constexpr uint32_t k_unseen = UINT32_MAX;
    static constexpr size_t k_first_rings = 256;
    // The open search to flood: on the side with fewer of the piece's particles, the smallest
    // there. `votes`: each search's sum of its particles' sides (its side is the sign).
    std::pair<uint32_t, int> pick_flood(uint32_t piece, std::span<const int8_t> side, std::vector<int32_t>& votes) {
        if (side_count_[0] < 0) {
            side_count_[0] = side_count_[1] = 0;
            for (uint32_t v = 0; v < side.size(); ++v)
                if (side[v] != 0 && b_.piece_of_particle[v] == piece) ++side_count_[side[v] > 0];
        }
        const int smaller = side_count_[1] < side_count_[0] ? 1 : -1;
        votes.assign(parent_.size(), 0);
        for (uint32_t v : visited_)
            if (v < side.size()) votes[find(owner_[v])] += side[v];
        uint32_t g = UINT32_MAX;
        int g_side = 0;
        for (uint32_t r = 0; r < parent_.size(); ++r) {
            if (find(r) != r || queued_[r] == 0) continue;
            const int s = (votes[r] > 0) - (votes[r] < 0);
            const bool better = g == UINT32_MAX || (s == smaller && g_side != smaller) || (s == g_side && members_[r] < members_[g]);
            if (better) g = r, g_side = s;
        }
        return {g, g_side};
    }

    // Floods the open search on the side with fewer of the piece's particles until it closes
    // (true: a part cut off, all its particles expanded) or meets a search from the other side
    // (false: the cut did not separate them; the caller sweeps). Searches from its own side that
    // it meets join it.
    // Breadth first, so the particles to expand next are known and their rings are fetched
    // a few steps ahead: a flood through half a large body otherwise waits on a cache miss
    // at every step (without it the flood at icosphere:7 took 1.6x as long; fetching the
    // neighbours' labels and positions too gained nothing: those arrays stay in cache).
    // Each particle's triangles at their lowest corner are summed as it is expanded (its
    // ring is in cache then); parts() sums only those the first rings expanded.
    // Both lists sized for every particle of the body up front and written by index: a
    // push_back that the compiler leaves out of line costs more than the rest of a step.
    bool flood_one(uint32_t piece, std::span<const int8_t> side) {
        std::vector<int32_t> votes;
        const std::pair<uint32_t, int> picked = pick_flood(piece, side, votes);
        const uint32_t g = picked.first;
        const int g_side = picked.second;
        auto side_of = [&](uint32_t root) { return (votes[root] > 0) - (votes[root] < 0); };
        std::vector<uint32_t>& queue = flood_queue_;
        const size_t n = b_.particle_count();
        queue.resize(n);
        size_t queued = 0, seen = visited_.size();
        visited_.resize(seen + n);
        auto take_queued = [&](uint32_t root) {
            for (size_t at = head_; at < seen; ++at)
                if (find(owner_[visited_[at]]) == root) queue[queued++] = visited_[at];
        };
        take_queued(g);
        Part sums;
        const sim::SlackLists<std::array<uint32_t, 2>>& rings = b_.rings.ring;
        const auto& x = b_.particles.x;
        constexpr size_t k_place_ahead = 16, k_items_ahead = 8;
        for (size_t c = 0; c < queued; ++c) {
            if (c + k_place_ahead < queued) rings.prefetch_place(queue[c + k_place_ahead]);
            if (c + k_items_ahead < queued) rings.prefetch_items(queue[c + k_items_ahead]);
            const uint32_t v = queue[c];
            for (const auto& [w, k] : rings.of(v)) {  // the first of each pair: see visit
                if (w > v && k > v) add_triangle(sums, x[v], x[w], x[k]);
                const uint32_t ow = owner_[w];
                if (ow == g) continue;
                if (ow == k_unseen) {
                    owner_[w] = g;
                    ++members_[g];
                    visited_[seen++] = w;
                    queue[queued++] = w;
                    continue;
                }
                const uint32_t o = find(ow);
                if (o == g) continue;
                if (g_side != 0 && side_of(o) == -g_side) {
                    visited_.resize(seen);
                    return false;
                }
                take_queued(o);  // before the merge: only o's particles
                open_ -= queued_[o] > 0;
                queued_[g] += queued_[o], queued_[o] = 0;
                members_[g] += members_[o];
                parent_[o] = g;
                --roots_;
            }
        }
        visited_.resize(seen);
        open_ -= queued_[g] > 0;  // closed: its entries left in the queue are never expanded
        queued_[g] = 0;
        flood_sums_.push_back({g, std::move(sums)});
        return true;
    }
    uint32_t find(uint32_t s) {
        while (parent_[s] != s) s = parent_[s] = parent_[parent_[s]];
        return s;
    }
    // Expands the particle at position `at` of the search; new particles join its group.
    void visit(size_t at) {
        const uint32_t v = visited_[at];
        const uint32_t raw = owner_[v];
        const uint32_t r = find(raw);
        if (--queued_[r] == 0) --open_;
        // Each triangle (v, j, k) sits in v's ring as (j, k), in j's as (k, v), in k's as (v, j):
        // following the first of each pair walks every triangle's corners round, so a search
        // that expanded all its particles has reached every corner of their triangles.
        for (const auto& pair : b_.rings.ring.of(v)) {
            const uint32_t w = pair[0];
            const uint32_t ow = owner_[w];
            if (ow == raw || ow == r) continue;  // most neighbours: the same search, no find
            if (ow == k_unseen) {
                owner_[w] = r;
                if (queued_[r]++ == 0) ++open_;
                ++members_[r];
                visited_.push_back(w);
            } else if (const uint32_t o = find(ow); o != r) {
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
    // The closed groups are whole parts; the open one (at most one is left) is the rest of the
    // piece, unexplored. One group left and open: the piece did not fall apart.
    std::vector<Part> parts() {
        uint32_t open_root = UINT32_MAX;
        for (uint32_t g = 0; g < parent_.size(); ++g)
            if (find(g) == g && queued_[g] > 0) open_root = g;
        std::vector<Part> parts;
        std::vector<uint32_t> part_of_root(parent_.size(), UINT32_MAX);
        std::vector<size_t> filled;  // per part, its particles written so far (sized by its members, written by index)
        for (size_t p = 0; p < visited_.size(); ++p) {
            const uint32_t v = visited_[p];
            const uint32_t g = find(owner_[v]);
            if (g == open_root) continue;
            if (part_of_root[g] == UINT32_MAX) {
                part_of_root[g] = uint32_t(parts.size());
                parts.emplace_back().particles.resize(members_[g]);
                filled.push_back(0);
            }
            const uint32_t k = part_of_root[g];
            Part& part = parts[k];
            part.particles[filled[k]++] = v;
            // A closed group's particles were all expanded: those before the queue's head by
            // the first rings, the others by a flood, which summed them.
            if (p < head_) add_triangles_at(b_, v, part);
        }
        for (size_t k = 0; k < parts.size(); ++k) {
            PBDSPLAT_ASSERT(filled[k] == parts[k].particles.size(), "PieceSearch: a group's member count differs from its particles");
            parts[k].particles.resize(filled[k]);
        }
        for (const auto& [g, sums] : flood_sums_) {
            Part& part = parts[part_of_root[g]];
            part.six_v += sums.six_v, part.area_bound += sums.area_bound, part.triangles += sums.triangles;
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
    std::vector<uint32_t>& sweep_;  // sweep_parts' scratch, kept between edits
    size_t head_ = 0;
    uint32_t roots_ = 0, open_ = 0;
    int64_t side_count_[2] = {-1, -1};
    std::vector<uint32_t> flood_queue_;
    std::vector<std::pair<uint32_t, Part>> flood_sums_;  // per flood that closed: its group and its particles' triangles  // the piece's particles on the negative and positive side, counted at the first flood
};
} // namespace

double part_area(const sim::SoftBody& b, const Part& part) {
    double area = 0.0;
    for (uint32_t v : part.particles)
        for (const auto& [j, k] : b.rings.ring.of(v))  // each triangle at its lowest corner, as add_triangles_at
            if (j > v && k > v) {
                const Vec3d a = sim::xyz(b.particles.x[v]).cast<double>();
                area += 0.5 * (sim::xyz(b.particles.x[j]).cast<double>() - a).cross(sim::xyz(b.particles.x[k]).cast<double>() - a).norm();
            }
    return area;
}

SplitSearch split_pieces(sim::SoftBody& b, std::span<const uint32_t> reached, std::span<const uint8_t> unmeasured, std::span<const uint32_t> seeds,
                        size_t budget, std::span<const int8_t> side) {
    SplitSearch out;
    thread_local ParticleScratch<uint32_t> owners(UINT32_MAX);
    std::vector<uint32_t>& owner = owners.take(b.particle_count());
    thread_local std::vector<uint32_t> sweep;
    std::vector<uint32_t> written;  // particles the searches labelled, to reset afterwards
    out.parts_of.resize(reached.size());
    std::vector<uint32_t> mine;
    for (size_t r = 0; r < reached.size(); ++r) {
        mine.clear();
        for (uint32_t v : seeds)
            if (b.piece_of_particle[v] == reached[r]) mine.push_back(v);
        bool went_deep = false;
        std::vector<Part>& parts = out.parts_of[r];
        parts = PieceSearch(b, owner, sweep).run(reached[r], unmeasured[r] != 0, mine, side, budget, went_deep, out.searched, written);
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
