#pragma once
// The names under which a frame's shared resources sit on the graph's blackboard
// (graph/blackboard.h): the runtime puts each import there, and every stage module takes what
// its passes read and puts back what they wrote. A module's own resources have their keys in
// its header.
#include <string>
#include <vector>

#include "graph/blackboard.h"
#include "passes/gpu_passes.h"
#include "scene/event_queue.h"
#include "scene/timeline.h"
#include "sim/colliders.h"
#include "sim/constraints.h"
#include "sim/shape.h"
#include "sim/soft_body.h"
#include "splat/cut_faces.h"
#include "splat/gaussian_record.h"
#include "splat/mapping.h"
#include "splat/sort.h"
#include "surface/boundary_particles.h"
#include "surface/density.h"

namespace pbdsplat::scene::keys {

// The body in its three parts (scene/stages/body_parts.h).
inline constexpr graph::Key<sim::BodyStructure> body_structure{"body structure"};
inline constexpr graph::Key<sim::BodyState> body_state{"body state"};
inline constexpr graph::Key<sim::BodyCaches> body_caches{"body caches"};
inline constexpr graph::Key<Timeline> timeline{"timeline"};  // absent without timed events
inline constexpr graph::Key<std::vector<sim::VolumeConstraint>> volumes{"volume constraints"};
inline constexpr graph::Key<std::vector<sim::ShapeCluster>> shapes{"shape clusters"};
inline constexpr graph::Key<sim::Colliders> colliders{"colliders"};
inline constexpr graph::Key<sim::DragConstraint> drag{"drag"};
// What the GPU passes read (passes::GpuFrameInput), in three parts by writer.
inline constexpr graph::Key<render::FrameInputs> view{"frame view"};
inline constexpr graph::Key<passes::SplatStream> splats{"splat stream"};
inline constexpr graph::Key<passes::OccluderInput> occluder_input{"occluder input"};
inline constexpr graph::Key<surface::BoundaryParticles> samples{"boundary particles"};
inline constexpr graph::Key<surface::DensityControl> density{"density control"};
inline constexpr graph::Key<splat::SortScratch> sort{"sort"};
inline constexpr graph::Key<splat::StretchScale> stretch{"stretch"};
inline constexpr graph::Key<passes::ImageSink> sink{"image"};
inline constexpr graph::Key<EventQueue> queue{"event queue"};
// The queue again, as a marker read by the topology pass: absent when no cut or tear can come.
inline constexpr graph::Key<EventQueue> cuts{"topology events"};
inline constexpr graph::Key<splat::Appearance> appearance{"appearance"};
inline constexpr graph::Key<std::string> note{"note"};
inline constexpr graph::Key<splat::CutFaces> cut_faces{"cut faces"};

} // namespace pbdsplat::scene::keys
