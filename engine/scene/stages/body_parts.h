#pragma once
// The body on the frame graph as the three parts sim::SoftBody is made of (sim/soft_body.h), each
// a resource of its own: its structure (written by the topology pass and, for the volumes'
// pressure, the timeline), its state (written by the solver's stages every step) and its caches
// (the normals, written by the solver's last stage; rebuilt by the topology pass). A pass's
// declaration then says which part it changes: a solver stage reads the structure and writes the
// state, and the check of undeclared writes (RuntimeOptions::check_writes) sees a stage that
// changed the structure.
#include "graph/blackboard.h"
#include "graph/frame_graph.h"
#include "sim/soft_body.h"

namespace pbdsplat::scene {

struct BodyParts {
    graph::Handle<sim::BodyStructure> structure;
    graph::Handle<sim::BodyState> state;
    graph::Handle<sim::BodyCaches> caches;

    static BodyParts from(const graph::Blackboard& board);
    void put(graph::Blackboard& board) const;
    // Declares reads of all three: the pass sees the whole body, const.
    void read(graph::PassBuilder& b) const;
    // Declares writes of all three (the topology pass: cuts change every part), or of the
    // structure and the state, reading the caches (the timeline: pressures, spins).
    void write(graph::PassBuilder& b, bool caches = true);
    // The whole body, const, for a pass that declared reads of all three.
    const sim::SoftBody& body(const graph::PassResources& r) const;
    // The whole body of a solver stage: the state written, the structure read (or written, with
    // `structure`). It reaches the other parts through the same object; the write check's
    // fingerprints of each part hold it to what it declared.
    sim::SoftBody& body_written_through_state(const graph::PassResources& r, bool structure = false) const;
    // The whole body of a pass that declared writes of all three (without `caches`: of the
    // structure and the state, the caches read).
    sim::SoftBody& body_written(const graph::PassResources& r, bool caches = true) const;
};

} // namespace pbdsplat::scene
