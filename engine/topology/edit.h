#pragma once
// Internal to the topology room: one topology edit in progress on a body. The cut decides
// where the body splits (vertex sides, crossed edges); the edit performs the steps every
// topology change shares, in order: new edge particles, re-triangulation, vertex duplication,
// masses, distance constraints. Kept apart from cut.cpp so tearing reuses the same steps.
#include <unordered_map>
#include <vector>

#include "sim/soft_body.h"
#include "topology/topology_change.h"

namespace pbdsplat::topology {

class Edit {
public:
    explicit Edit(sim::SoftBody& body);

    // Per original vertex: -1 / +1 for its side of the cut, 0 for "on the cut".
    std::span<const int8_t> sign;
    // The original vertices with sign 0 (the new edge points are on the cut too).
    std::vector<uint32_t> on_cut_vertices;
    TopologyChange change;

    // The new particle splitting edge (i, j), or UINT32_MAX.
    uint32_t point_on(uint32_t i, uint32_t j) const;
    // Eq. 26: a new particle at x_i + t (x_j - x_i), state and rest position interpolated.
    void add_edge_point(uint32_t i, uint32_t j, float t);
    size_t edge_points() const { return points_.size(); }
    // Eq. 27: replaces triangle t by children around the new particles on its edges.
    void retriangulate(uint32_t t);
    const mesh::Triangle& parent_triangle(uint32_t t) const { return parents_.at(t); }
    // Eq. 28: every vertex on the cut gets one copy per extra fan of triangles, the fans being
    // separated by cut edges (both ends on the cut, the two triangles on opposite sides).
    void split_vertices_along_cut();
    // The vertex rings (and triangle lists) of every vertex the edit touched made again.
    void update_rings();
    // Masses of the touched region spread again by rest area, keeping their sum.
    void redistribute_mass();
    // Constraints of touched edges re-made with the old definitions and the new indices.
    void update_distance_constraints();
    const std::vector<uint32_t>& local_triangles() const { return local_triangles_; }
    // Fills the counts and the touched-triangle list of `change`.
    void finish();

private:
    // v's triangles `fan` grouped by the edges they share that are not cut edges; each group but
    // the first (by its lowest triangle) gets a copy of v; false: one group, nothing split.
    // `root`: scratch.
    bool split_fan(uint32_t v, const std::vector<uint32_t>& fan, std::vector<uint32_t>& root);
    struct EdgePoint {
        uint32_t i, j;  // i < j
        float t;        // from i
        uint32_t vertex;
    };
    sim::SoftBody& b_;
    size_t n0_, t0_;
    std::vector<EdgePoint> points_;
    std::unordered_map<uint64_t, uint32_t> point_of_edge_;  // edge key -> index into points_
    std::unordered_map<uint32_t, mesh::Triangle> parents_;   // original corners of re-triangulated triangles
    std::vector<uint32_t> origin_;                           // for particle n0_ + k: what it came from
    std::vector<uint32_t> local_triangles_;                  // children and triangles around duplicated vertices
    std::vector<uint32_t> region_;                           // their corners

    // An old distance constraint about to be re-made: its slot and definition, by edge key.
    struct Definition {
        uint64_t key;
        uint32_t slot;
        float rest, compliance;
    };
    std::vector<Definition> constraints_to_remake() const;
    uint32_t new_particle(uint32_t copy_of);
    uint32_t origin(uint32_t v) const { return v < n0_ ? v : origin_[v - n0_]; }
    bool is_edge_point(uint32_t v) const { return v >= n0_ && v < n0_ + points_.size(); }
    bool on_cut(uint32_t v) const { return v >= n0_ || sign[v] == 0; }
    int side(const mesh::Triangle& t) const;
    void add_child(uint32_t parent, bool first, const mesh::Triangle& corners, const std::array<Vec3f, 3>& bary);
};

inline uint64_t edge_key(uint32_t a, uint32_t b) {
    return (uint64_t(a < b ? a : b) << 32) | (a < b ? b : a);
}

} // namespace pbdsplat::topology
