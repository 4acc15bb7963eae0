#pragma once
// Tearing: an edge stretched past a threshold opens a short slit across itself through the
// same machinery as a line cut. One call tears one edge. A tear runs: the rim it made is its
// crack front, where the material is weakened (the stress a crack's tip concentrates, which a
// mesh this coarse does not resolve), so while the strain there stays high the rip grows frame
// after frame along the most strained direction, with a cap on splits per frame so it never
// shatters the body in one step.
#include <optional>
#include <span>
#include <vector>

#include "core/result.h"
#include "sim/soft_body.h"
#include "topology/cut.h"

namespace pbdsplat::topology {

struct TearOptions {
    float threshold = 1.5f;      // current / rest length beyond which an edge tears (> 1)
    uint32_t max_per_frame = 4;  // tears per frame
    float reach = 1.0f;          // the slit reaches at least this many torn-edge lengths (and the vertex's ring)
    // A tear that would cut off a piece of fewer triangles is not made (the edge waits, and the
    // next one is tried): a fleck of a few triangles flying off reads as a speck, not a rip.
    uint32_t min_fragment_triangles = 8;
    // An edge with an end on a crack front (the rim a tear made: CrackFront) tears beyond this stretch
    // instead (1 < tip_threshold <= threshold); 0: halfway between 1 and `threshold`.
    float tip_threshold = 0.0f;
    // The shortest length a stretch is measured over (metres; 0: each edge's own rest length). An
    // edge shorter than this counts its lengthening over the gauge: a sliver of a decimated mesh,
    // a few millimetres long, reads 1.6x when its ends move a millimetre or two apart while the
    // surface around it barely stretches (teapot_balloon's spout tore there 3 frames into its
    // pull). The body's mean rest edge (tear_gauge) makes the threshold a property of the material
    // rather than of the mesh's smallest triangles.
    float gauge = 0.0f;
    float front_threshold() const { return tip_threshold > 0.0f ? tip_threshold : 1.0f + 0.5f * (threshold - 1.0f); }
};
core::Status validate(const TearOptions& options);

struct StrainedEdge {
    uint32_t i = 0, j = 0;
    float ratio = 1.0f;   // current / rest length
    float excess = 1.0f;  // ratio over the threshold it passed (the front's or the body's)
};
// The distance constraints stretched beyond `threshold`, most strained first (ties: lower i,
// then lower j), at most `limit`; stretches measured over at least `gauge` (TearOptions::gauge).
std::vector<StrainedEdge> strained_edges(const sim::SoftBody& body, float threshold, size_t limit, float gauge = 0.0f);
// The gauge a tear measures stretches over by default: the body's mean rest edge.
float tear_gauge(const sim::SoftBody& body);

// The rims tears made, where the rips run on: the particles a tear made and those its slit ended
// at (the tip, an old vertex now on the opening). Particles are only ever appended, so a flag per
// particle index stays valid through later changes.
class CrackFront {
public:
    bool on(uint32_t particle) const { return particle < flags_.size() && flags_[particle] != 0; }
    // Every particle `change` made, and every corner of a triangle it touched that now lies on an
    // opening, joins the front (`body` as the change left it). Returns the particles older than the
    // change that joined.
    std::vector<uint32_t> grow(const sim::SoftBody& body, const TopologyChange& change);

private:
    std::vector<uint8_t> flags_;
};

// The strained edges of one frame's tearing: every constraint read once, then kept through the
// frame's tears. A tear moves no particle, so an edge it left constrained keeps its ratio, and
// every constraint it adds has a new particle at one end (a split-off copy or a point on a
// crossed edge): the frame's second and third tear cost what the first one touched, not another
// pass over the body (0.6M instructions on each of the teapot balloon's tear frames).
class StrainedSet {
public:
    StrainedSet(const sim::SoftBody& body, float threshold, float gauge = 0.0f);
    // With a crack front: edges with an end on it pass at `front_threshold` instead, and the
    // particles each tear makes join it (the front outlives the set: a rip runs over frames).
    StrainedSet(const sim::SoftBody& body, float threshold, float front_threshold, CrackFront& front, float gauge = 0.0f);
    // After `change` to `body`: drops the edges no longer constrained as they were, adds the
    // strained constraints of the new particles. The same set as a new StrainedSet would hold.
    void update(const sim::SoftBody& body, const TopologyChange& change);
    // The most strained first, by excess over their thresholds, at most `limit`.
    std::span<const StrainedEdge> most_strained(size_t limit) const { return std::span(edges_).first(std::min(limit, edges_.size())); }
    size_t size() const { return edges_.size(); }

private:
    void sort();
    float threshold_, front_threshold_, gauge_;
    CrackFront* front_ = nullptr;
    std::vector<StrainedEdge> edges_;  // sorted
};

// Tears at the most strained edge that can open: one of its end vertices is split by the plane
// through it normal to the edge (a pinned end never is), unless that cuts off a piece smaller
// than TearOptions::min_fragment_triangles. Nothing when no edge passes. With
// `strained`, the edges come from (and the tear is recorded in) the frame's set.
core::Result<std::optional<TopologyChange>> tear_once(sim::SoftBody& body, const TearOptions& tear, const CutOptions& cut);
core::Result<std::optional<TopologyChange>> tear_once(sim::SoftBody& body, const TearOptions& tear, const CutOptions& cut,
                                                      StrainedSet& strained);

} // namespace pbdsplat::topology
