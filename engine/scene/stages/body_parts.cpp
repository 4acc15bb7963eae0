#include "scene/stages/body_parts.h"

#include "scene/stages/frame_keys.h"

namespace pbdsplat::scene {

namespace {
template <class T>
void declare_part(graph::PassBuilder& b, graph::Handle<T>& h, bool write) {
    if (write) h = b.write(h);
    else b.read(h);
}

// Checks the part was declared as the pass says it uses it.
template <class T>
void reach_part(const graph::PassResources& r, graph::Handle<T> h, bool write) {
    if (write) r.write(h);
    else r.read(h);
}
} // namespace

BodyParts BodyParts::from(const graph::Blackboard& board) {
    return {board.get(keys::body_structure), board.get(keys::body_state), board.get(keys::body_caches)};
}

void BodyParts::put(graph::Blackboard& board) const {
    board.put(keys::body_structure, structure);
    board.put(keys::body_state, state);
    board.put(keys::body_caches, caches);
}

void BodyParts::declare(graph::PassBuilder& b, BodyWrites w) {
    declare_part(b, structure, w.structure);
    declare_part(b, state, w.state);
    declare_part(b, caches, w.caches);
}

const sim::SoftBody& BodyParts::body(const graph::PassResources& r) const {
    r.read(state);
    r.read(caches);
    return static_cast<const sim::SoftBody&>(r.read(structure));
}

sim::SoftBody& BodyParts::body(const graph::PassResources& r, BodyWrites w) const {
    reach_part(r, structure, w.structure);
    reach_part(r, caches, w.caches);
    // Every pass that changes the body moves its state (a solver stage, the timeline's spins, the
    // particles a cut adds): reached through it.
    return static_cast<sim::SoftBody&>(r.write(state));
}

} // namespace pbdsplat::scene
