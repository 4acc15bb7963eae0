#include "scene/stages/stillness.h"

#include <cstring>

#include "scene/stages/body_parts.h"

namespace pbdsplat::scene {

namespace {
template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}
} // namespace

void Stillness::observe(const sim::BodyStructure& structure, const sim::BodyState& state) {
    // Bit for bit, not within a tolerance: a held piece's particles are not written at all, and
    // anything that moved them (a drag, a cut, a wake) moved them by more than nothing.
    const bool same_triangles = !seen_.empty() && seen_.size() == state.particles.x.size() && same_bytes(triangles_, structure.triangles);
    still_ = same_triangles && same_bytes(seen_, state.particles.x);
    if (still_) return;
    if (same_triangles) judge_pieces(structure, state);
    else moved_triangles_.clear();
    seen_ = state.particles.x;
    triangles_ = structure.triangles;
}

void Stillness::judge_pieces(const sim::BodyStructure& structure, const sim::BodyState& state) {
    const std::vector<Vec4f>& x = state.particles.x;
    moved_piece_.assign(structure.pieces, 0);
    bool any_unmoved = false;
    for (size_t i = 0; i < x.size(); ++i) {
        const uint32_t k = structure.piece_of_particle[i];
        if (k < structure.pieces && !moved_piece_[k] && std::memcmp(&x[i], &seen_[i], sizeof(Vec4f)) != 0) moved_piece_[k] = 1;
    }
    for (uint8_t m : moved_piece_) any_unmoved = any_unmoved || !m;
    if (!any_unmoved) {  // every piece moved: as good as no marks
        moved_triangles_.clear();
        return;
    }
    moved_triangles_.resize(structure.triangles.size());
    for (size_t t = 0; t < structure.triangles.size(); ++t) {
        const uint32_t k = structure.piece_of_particle[structure.triangles[t][0]];
        moved_triangles_[t] = k < structure.pieces ? moved_piece_[k] : 1;
    }
}

void add_stillness_pass(graph::FrameGraph& g, graph::Blackboard& board, uint32_t tag) {
    const BodyParts body = BodyParts::from(board);
    auto stillness = board.get(keys::stillness);
    g.add_pass("stillness", graph::PassKind::cpu, [&](graph::PassBuilder& b) {
        b.read(body.structure);
        b.read(body.state);
        stillness = b.write(stillness);
        return [body, stillness](const graph::PassResources& r, graph::ExecuteContext&) {
            r.write(stillness).observe(r.read(body.structure), r.read(body.state));
        };
    }, tag);
    board.put(keys::stillness, stillness);
}

} // namespace pbdsplat::scene
