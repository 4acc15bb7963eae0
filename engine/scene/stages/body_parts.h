#pragma once
// The body on the frame graph as the three parts sim::SoftBody is made of (sim/soft_body.h), each
// a resource of its own: its structure (written by the topology pass and, for the volumes'
// pressure, the timeline and the solver's forces stage), its state (written by the solver's
// stages every step) and its caches (the normals, written by the solver's last stage; rebuilt by
// the topology pass). A pass's declaration then says which part it changes, and the check of
// undeclared writes (RuntimeOptions::check_writes) sees a pass that changed another.
#include "graph/blackboard.h"
#include "graph/frame_graph.h"
#include "sim/soft_body.h"

namespace pbdsplat::scene {

// Which parts a pass changes; it reads the others.
struct BodyWrites {
    bool structure = false, state = false, caches = false;
};

struct BodyParts {
    graph::Handle<sim::BodyStructure> structure;
    graph::Handle<sim::BodyState> state;
    graph::Handle<sim::BodyCaches> caches;

    static BodyParts from(const graph::Blackboard& board);
    void put(graph::Blackboard& board) const;
    // Declares the pass's access to all three parts: a write of those `w` names, a read of the rest.
    void declare(graph::PassBuilder& b, BodyWrites w = {});
    // The whole body, through the parts as the pass declared them (the graph checks each). Each
    // part is a base of the one body the runtime imported, so the whole is reached from any of
    // them; the write check's fingerprints of each part hold the pass to what it declared.
    const sim::SoftBody& body(const graph::PassResources& r) const;
    // A pass that changes the body (`w.state` and what else it declared).
    sim::SoftBody& body(const graph::PassResources& r, BodyWrites w) const;
};

} // namespace pbdsplat::scene
