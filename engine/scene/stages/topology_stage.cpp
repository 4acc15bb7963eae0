#include "scene/stages/topology_stage.h"

#include "topology/invariants.h"
#include "topology/tear.h"

namespace pbdsplat::scene {

TopologyStage::TopologyStage(bool check_invariants) : check_invariants_(check_invariants) {}

void TopologyStage::run(EventQueue& queue, sim::SoftBody& body, float t, float dt, const render::Camera& camera,
                        const topology::CutOptions& options, FrameChanges& changes, std::string& note) {
    changes.clear();
    for (const QueuedEvent& q : queue.take_due(t + dt, is_topology_event)) {
        if (!status_.ok()) break;
        const Event& e = q.event;
        if (const auto* c = std::get_if<CutEvent>(&e.data); c && q.from_user) {
            const size_t particles = body.particle_count();
            const core::Status s = apply_cut(body, *c, camera, options, changes);
            if (!s.ok()) note = "cut failed: " + s.error().to_string();
            else if (body.particle_count() == particles) note = "the stroke cut nothing";
            else note = "cut: " + std::to_string(body.particle_count() - particles) + " particles split off";
            if (s.ok()) ++cuts_;
        } else if (c) {
            status_ = apply_cut(body, *c, camera, options, changes);
            ++cuts_;
        } else {
            tearing_ = std::get<TearEvent>(e.data);
            gauge_ = topology::tear_gauge(body);
            tearing_until_ = tearing_->duration > 0.0f ? e.time + tearing_->duration : 1e30f;
        }
    }
    if (tearing_ && t >= tearing_until_) tearing_.reset();
    if (tearing_ && status_.ok()) status_ = apply_tears(body, options, changes);
}

core::Status TopologyStage::apply_cut(sim::SoftBody& body, const CutEvent& cut, const render::Camera& camera,
                                      const topology::CutOptions& options, FrameChanges& changes) {
    core::Result<topology::CutSurface> surface = core::make_error("cut: no surface");
    if (cut.plane) {
        surface = topology::plane_cut(cut.plane->first, cut.plane->second);
    } else {
        const Mat4f view_proj = math::perspective(math::radians(camera.fov_y_degrees), cut.screen.x() / cut.screen.y(), camera.z_near,
                                                  camera.z_far) *
                                math::look_at(camera.eye, camera.target, camera.up);
        surface = topology::screen_cut(view_proj, camera.eye, cut.screen, (*cut.segment)[0], (*cut.segment)[1]);
    }
    if (!surface.ok()) return surface.error();
    auto change = topology::cut(body, surface.value(), options);
    if (!change.ok()) return change.error();
    return after(body, change.value(), &surface.value(), changes);
}

core::Status TopologyStage::apply_tears(sim::SoftBody& body, const topology::CutOptions& cut_options, FrameChanges& changes) {
    topology::TearOptions options;
    options.threshold = tearing_->threshold;
    options.max_per_frame = tearing_->max_per_frame;
    options.tip_threshold = tearing_->tip_threshold;
    options.gauge = gauge_;
    PBDSPLAT_TRY(topology::validate(options));
    // One pass a frame, kept through its tears; the front is kept through the run.
    topology::StrainedSet strained(body, options.threshold, options.front_threshold(), front_, options.gauge);
    for (uint32_t k = 0; k < options.max_per_frame; ++k) {
        auto change = topology::tear_once(body, options, cut_options, strained);
        if (!change.ok()) return change.error();
        if (!change.value()) break;  // nothing strained enough
        ++tears_;
        PBDSPLAT_TRY(after(body, *change.value(), nullptr, changes));
    }
    return core::Status::success();
}

core::Status TopologyStage::after(sim::SoftBody& body, const topology::TopologyChange& change, const topology::CutSurface* cut,
                                  FrameChanges& changes) {
    last_change_ = change;
    if (!change.changed()) return core::Status::success();
    // Handed on broken too: the passes that follow this one in the frame (the density control's
    // per-triangle state) then match the body while the error travels to the caller, who stops
    // there.
    const core::Status broken = check_invariants_ ? topology::check_invariants(body) : core::Status::success();
    // A cut is counted after its change, a tear before it: the seeds of the samples laid
    // since the first scenes were recorded.
    if (changes.empty()) changes.seed_offset = cuts_ + tears_ + 1;
    changes.changes.push_back({change, cut ? std::optional<topology::CutSurface>(*cut) : std::nullopt});
    changes.refill.insert(changes.refill.end(), change.touched_triangles.begin(), change.touched_triangles.end());
    return broken;
}

} // namespace pbdsplat::scene
