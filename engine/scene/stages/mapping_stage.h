#pragma once
// From the body to the Gaussians: the paper's one-to-one mapping (eqs. 11-13) of the particles
// and the boundary particles, their deformed shapes where the scene asks, the fade-in of
// splats a cut added, the far-to-near CPU sort, and the hand-over to the GPU passes with the
// byte ranges that changed since the last frame.
#include <optional>
#include <span>
#include <vector>

#include "graph/blackboard.h"
#include "graph/frame_graph.h"
#include "render/frame_inputs.h"
#include "passes/gpu_passes.h"
#include "sim/colliders.h"
#include "sim/soft_body.h"
#include "splat/cut_faces.h"
#include "splat/deformed_shape.h"
#include "splat/fade_in.h"
#include "splat/mapping.h"
#include "splat/normal_field.h"
#include "splat/sort.h"
#include "splat/texcoords.h"
#include "surface/boundary_particles.h"
#include "topology/topology_change.h"

namespace pbdsplat::scene {

class MappingStage {
public:
    // `deformed`: each boundary particle a disc carried by its triangle (render.splat_shape).
    // `varying_normals`: each splat carries how the normal turns across it (render.splat_normals).
    // `pool`: threads the per-sample work splits over (the records are the same), or null.
    MappingStage(const sim::SoftBody& body, uint32_t fade_frames, bool deformed, bool varying_normals, core::ThreadPool* pool = nullptr);

    struct Sources {
        const sim::SoftBody* body = nullptr;
        bool particles = true;  // the particles are splats (not under an embedded surface)
        const surface::BoundaryParticles* samples = nullptr;  // shown boundary particles, or null
        const splat::StretchScale* stretch = nullptr;         // stretch-scaled splats, or null
        const splat::CutFaces* cut_faces = nullptr;           // the faces cuts made, drawn after the rest, or null
    };
    // What a frame knows of what stood still since the last map(): the records of the samples on
    // an unmoved triangle (Stillness::moved_triangles) are kept when no sample was added or
    // removed since (`samples_same`) and they do not fade. Empty: every record is made.
    struct Unmoved {
        std::span<const uint8_t> moved_triangles;
        bool samples_same = false;
    };
    void map(const Sources& s, const splat::Appearance& look, const Unmoved& unmoved);
    void map(const Sources& s, const splat::Appearance& look);
    // Samples whose records the last map() kept as they were.
    size_t kept() const { return kept_count_; }
    // Whether the records the last map() made stand for this frame as they are: the body has not
    // moved since (`body_still`), nor have the samples (`samples_still`: nothing added, removed or
    // fading), no particle or cut face fades in, and the same splats are drawn with the same look.
    bool stands(const Sources& s, const splat::Appearance& look, bool body_still, bool samples_still) const;
    void sort(const render::Camera& camera);
    // Hands the records (and shapes) to the GPU passes with what changed. `moved`: the body was
    // simulated this frame, so every record changed: all of them go, without comparing them with
    // the last frame's (a copy and a compare of every record per frame). A frame that did not
    // move the body (paused) compares, and uploads only what a sort or a setting changed.
    void publish(passes::SplatStream& input, bool moved);
    // Hands the records over as they stand: nothing of them changed (stands()).
    void publish_unchanged(passes::SplatStream& input) const;
    // New particles fade in; the deformed shapes follow the new triangles.
    void topology_changed(const sim::SoftBody& body, const topology::TopologyChange& change, bool particles);

    const std::vector<splat::GaussianRecord>& records() const { return records_; }
    const std::vector<splat::GaussianShape>& shapes() const { return shapes_; }
    // Where a textured model's texture lies on each splat, parallel to records(); empty unless
    // the samples carry texture coordinates (scene/stages/paint.h).
    const std::vector<splat::GaussianTexcoord>& texcoords() const { return texcoords_; }
    splat::SortScratch& sort_scratch() { return sort_scratch_; }

private:
    // What the last map() made the records from, besides the body and the samples.
    struct Made {
        bool valid = false;
        bool particles = false, samples = false, stretch = false, cut_faces = false;
        splat::Appearance look;
        size_t particle_count = 0, sample_count = 0;
    };
    Made made_;
    // Per sample: its record stands from the last map() (see Unmoved).
    std::vector<uint8_t> kept_;
    size_t kept_count_ = 0;
    bool made_like(const Sources& s, const splat::Appearance& look) const;  // the same splats, the same look
    bool keeps(const Sources& s, const splat::Appearance& look, const Unmoved& unmoved) const;
    std::vector<splat::GaussianRecord> records_;
    std::vector<splat::GaussianRecord> previous_;  // what the GPU holds, when previous_valid_: for the changed ranges
    bool previous_valid_ = false;
    std::vector<splat::GaussianShape> shapes_;     // parallel to records_ with deformed shapes
    std::vector<splat::GaussianTexcoord> texcoords_;  // parallel to records_ for textured models
    splat::TexcoordScratch texcoord_scratch_;
    splat::DeformedShapes deformed_;
    splat::NormalField normal_field_;
    bool varying_normals_ = false;
    core::ThreadPool* pool_ = nullptr;
    splat::FadeIn fade_;
    splat::SortScratch sort_scratch_;
};

// What the map pass reads of the runtime besides the body and the samples: settings that change
// between frames (the user hides the boundary splats, a cut opens the body).
struct MapSettings {
    bool particles = true;      // the particles are splats (not under an embedded surface)
    bool show_boundary = true;  // the boundary particles' splats are drawn
    bool closed = false;        // the body has no open boundary now: its far side may be culled
    bool cull_back = true;      // the scene allows that
    bool draw_ground = true;
    std::optional<sim::GroundPlane> ground;
};

namespace keys {
inline constexpr graph::Key<MapSettings> map_settings{"map settings"};
inline constexpr graph::Key<MappingStage> mapping{"mapping"};
} // namespace keys
struct MapPassOptions {
    bool boundary = false, stretch = false, sorted = false;
    bool keep_records = false;  // the caller reads the records every frame: the passes always run
    bool moved = true;          // the frame simulates the body (not paused)
    uint32_t tag = 0;
    bool cut_faces = false;     // cuts can come: the faces they make are followed and drawn
    bool stillness = false;     // keys::stillness is on the board: a still frame keeps the records
};
// "map" (body -> records, the cut faces follow the body's cap loops, the view follows the body,
// the records handed over unless sorted) and
// "sort" (far to near on the CPU, then handed over). They read the body, samples, stretch,
// sort scratch, appearance, frame view, keys::map_settings and keys::mapping from `board` (the
// samples, stretch and sort may be absent: the options say which are there) and put back the
// frame view, the splat stream and the cut faces they wrote.
void add_mapping_passes(graph::FrameGraph& g, graph::Blackboard& board, const MapPassOptions& o);

} // namespace pbdsplat::scene
