#include "scene/stages/body_parts.h"

#include "scene/stages/frame_keys.h"

namespace pbdsplat::scene {

BodyParts BodyParts::from(const graph::Blackboard& board) {
    return {board.get(keys::body_structure), board.get(keys::body_state), board.get(keys::body_caches)};
}

void BodyParts::put(graph::Blackboard& board) const {
    board.put(keys::body_structure, structure);
    board.put(keys::body_state, state);
    board.put(keys::body_caches, caches);
}

void BodyParts::read(graph::PassBuilder& b) const {
    b.read(structure);
    b.read(state);
    b.read(caches);
}

void BodyParts::write(graph::PassBuilder& b, bool with_caches) {
    structure = b.write(structure);
    state = b.write(state);
    if (with_caches) caches = b.write(caches);
    else b.read(caches);
}

// Each part is a base of the one sim::SoftBody the runtime imported, so the whole is reached from
// any of them; the graph has checked the pass declared the part it is reached through.
const sim::SoftBody& BodyParts::body(const graph::PassResources& r) const {
    r.read(state);
    r.read(caches);
    return static_cast<const sim::SoftBody&>(r.read(structure));
}

sim::SoftBody& BodyParts::body_written_through_state(const graph::PassResources& r, bool with_structure) const {
    if (with_structure) r.write(structure);
    else r.read(structure);
    return static_cast<sim::SoftBody&>(r.write(state));
}

sim::SoftBody& BodyParts::body_written(const graph::PassResources& r, bool with_caches) const {
    if (with_caches) r.write(caches);
    else r.read(caches);
    r.write(state);
    return static_cast<sim::SoftBody&>(r.write(structure));
}

} // namespace pbdsplat::scene
