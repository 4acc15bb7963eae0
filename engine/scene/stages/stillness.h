#pragma once
// Frames on which the body has not moved: every piece asleep (sim/sleep.h), or the scene paused.
// The surface passes made their samples, records and occluder mesh from the very same positions
// on an earlier frame, so on such a frame they let them stand and only the drawing is left (a
// landed bunny_cut: its surface update 6 ms a frame before, about 0.1 ms now; docs/BENCHMARKS.md).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "graph/blackboard.h"
#include "graph/frame_graph.h"
#include "sim/soft_body.h"

namespace pbdsplat::scene {

class Stillness {
public:
    // Whether the particles (positions and inverse masses) and the triangles are bit for bit as
    // the last moving frame left them. A frame on which they are not becomes the new reference:
    // this frame's surface passes make their outputs from it.
    void observe(const sim::BodyStructure& structure, const sim::BodyState& state);
    bool still() const { return still_; }
    // On a frame that moved with the same triangles as the last: per triangle, whether a
    // particle of its piece moved (a piece is a closed set: nothing outside it bends its
    // normals). Empty when every triangle counts as moved (the first frame, a topology change).
    // What a pass made on an unmoved piece's triangles last frame stands: a static table, the
    // sleeping pieces of a pile. On a still frame the marks are the last moving frame's (what
    // they call unmoved has still not moved).
    std::span<const uint8_t> moved_triangles() const { return moved_triangles_; }

private:
    std::vector<Vec4f> seen_;
    std::vector<mesh::Triangle> triangles_;
    std::vector<uint8_t> moved_piece_, moved_triangles_;
    bool still_ = false;
    void judge_pieces(const sim::BodyStructure& structure, const sim::BodyState& state);
};

namespace keys {
inline constexpr graph::Key<Stillness> stillness{"stillness"};
}

// "stillness": observes the body after the simulation; the surface, map and occluder passes
// read it. Reads the body and keys::stillness from `board` and puts back the latter.
void add_stillness_pass(graph::FrameGraph& g, graph::Blackboard& board, uint32_t tag);

} // namespace pbdsplat::scene
