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
    still_ = !seen_.empty() && same_bytes(seen_, state.particles.x) && same_bytes(triangles_, structure.triangles);
    if (still_) return;
    seen_ = state.particles.x;
    triangles_ = structure.triangles;
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
