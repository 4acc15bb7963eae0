#include "render/splat_renderer.h"

#include <cstring>

#include "core/assert.h"
#include "core/timer.h"
#include "render/frame_uniforms.h"

namespace pbdsplat::render {

Use uses::records_read(SplatPath path) {
    switch (path) {
    case SplatPath::geometry: return {{VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT}};
    case SplatPath::mesh: return {{VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT}};
    case SplatPath::vertex: return {{VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT}};
    }
    return {};
}

Use uses::streams_read(SplatPath path) {
    switch (path) {
    case SplatPath::geometry: return {{VK_PIPELINE_STAGE_2_GEOMETRY_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT}};
    case SplatPath::mesh: return {{VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT}};
    case SplatPath::vertex: return {{VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT}};
    }
    return {};
}

namespace {
// One host-visible storage buffer per frame slot for an optional stream beside the records (a
// token element when the stream is off, so the frame set's binding always has a buffer).
core::Status make_host_stream(gpu::Context& ctx, uint32_t slots, VkDeviceSize bytes, std::vector<gpu::Buffer>& buffers,
                              std::vector<VkBuffer>& handles) {
    for (uint32_t i = 0; i < slots; ++i) {
        auto b = gpu::Buffer::create(ctx, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::upload);
        if (!b.ok()) return b.error();
        buffers.push_back(std::move(b).value());
        handles.push_back(buffers.back().handle());
    }
    return core::Status::success();
}

// Written in place into the slot's buffer, which only this frame reads: the submit makes it
// visible, no copy or barrier needed.
template <class T>
core::Status write_host_stream(const gpu::Buffer& buffer, std::span<const T> data, uint32_t capacity, bool enabled, const char* what) {
    if (!enabled) return core::make_error(std::string("the renderer was created without ") + what);
    if (data.size() > capacity)
        return core::make_error(std::to_string(data.size()) + " entries of " + what + " exceed the renderer's capacity of " +
                                std::to_string(capacity));
    std::memcpy(buffer.mapped(), data.data(), data.size_bytes());
    return core::Status::success();
}
} // namespace

namespace {
// Refused up front, with the limit, rather than allocated and ground through for minutes.
core::Status check_options(const gpu::Context& ctx, const RendererOptions& options) {
    if (options.max_splats == 0) return core::make_error("max_splats must be at least 1");
    const uint32_t side = ctx.caps().max_image_dimension;
    if (side && (options.width > side || options.height > side))
        return core::make_error(std::to_string(options.width) + "x" + std::to_string(options.height) + " is larger than device '" +
                                ctx.caps().name + "' draws (" + std::to_string(side) + " pixels a side at most)");
    constexpr uint64_t k_max_pixels = 8192ull * 8192ull;
    const uint64_t pixels = uint64_t(options.width) * options.height;
    if (pixels > k_max_pixels)
        return core::make_error(std::to_string(options.width) + "x" + std::to_string(options.height) + " is " + std::to_string(pixels / 1000000) +
                                " million pixels, above the renderer's limit of 67 million (8192x8192): its colour, depth and "
                                "readback images alone would take " + std::to_string(pixels * 12 * options.frames_in_flight >> 20) + " MiB");
    return core::Status::success();
}
} // namespace

core::Result<std::unique_ptr<SplatRenderer>> SplatRenderer::create(gpu::Context& ctx, const RendererOptions& options) {
    PBDSPLAT_TRY(check_options(ctx, options));
    auto r = std::unique_ptr<SplatRenderer>(new SplatRenderer());
    r->ctx_ = &ctx;
    r->options_ = options;
    PBDSPLAT_TRY(r->create_streams());
    PBDSPLAT_TRY(r->create_passes());
    PBDSPLAT_TRY(r->create_sets());
    return r;
}

core::Status SplatRenderer::create_streams() {
    gpu::Context& ctx = *ctx_;
    const RendererOptions& options = options_;
    const uint32_t n = options.frames_in_flight;
    auto frames = gpu::FrameRing::create(ctx, n);
    if (!frames.ok()) return frames.error();
    frames_ = std::move(frames).value();

    const VkDeviceSize record_bytes = VkDeviceSize(options.max_splats) * sizeof(splat::GaussianRecord);
    const gpu::UploadPath path = options.upload_path.value_or(ctx.caps().unified_memory ? gpu::UploadPath::direct
                                                                                        : gpu::UploadPath::staged);
    if (path == gpu::UploadPath::staged) {
        // Room for every frame in flight to rewrite all records, plus slack for alignment.
        auto ring = gpu::UploadRing::create(ctx, record_bytes * n + (1u << 16));
        if (!ring.ok()) return ring.error();
        ring_ = std::move(ring).value();
    }
    auto records = gpu::StreamBuffer::create(ctx, record_bytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                             path, n);
    if (!records.ok()) return records.error();
    records_ = std::move(records).value();

    auto target = OffscreenTarget::create(ctx, options.width, options.height, n);
    if (!target.ok()) return target.error();
    target_ = std::move(target).value();
    return core::Status::success();
}

core::Status SplatRenderer::create_passes() {
    gpu::Context& ctx = *ctx_;
    const RendererOptions& options = options_;
    if (options.occluders) {
        auto occluders = OccluderPass::create(ctx, options.width, options.height, options.frames_in_flight, k_depth_format);
        if (!occluders.ok()) return occluders.error();
        occluders_ = std::move(occluders).value();
    }
    auto pass = SplatPass::create(ctx, k_color_format, k_depth_format, options.path.value_or(best_splat_path(ctx.caps(), options.anisotropic)),
                                  options.shading, options.carrier, options.anisotropic, options.sh_degree,
                                  options.normalised ? k_accumulation_format : VK_FORMAT_UNDEFINED,
                                  options.occluders ? occluders_.set_layout() : VK_NULL_HANDLE, options.textures);
    if (!pass.ok()) return pass.error();
    splat_ = std::move(pass).value();
    if (options.normalised) {
        auto blend = NormalisedBlend::create(ctx, options.width, options.height, k_color_format);
        if (!blend.ok()) return blend.error();
        blend_ = std::move(blend).value();
    }
    auto ground = GroundPass::create(ctx, k_color_format, k_depth_format, splat_.set_layout());
    if (!ground.ok()) return ground.error();
    ground_ = std::move(ground).value();

    auto environment = make_environment_texture(ctx, options.environment_map, options.sky_sun);
    if (!environment.ok()) return environment.error();
    sh_ = environment->sh;
    environment_ = std::move(environment->texture);
    return core::Status::success();
}

core::Status SplatRenderer::create_sets() {
    gpu::Context& ctx = *ctx_;
    const RendererOptions& options = options_;
    const uint32_t n = options.frames_in_flight;
    gpu::FrameSetResources extra;
    extra.texture_view = environment_.view();
    extra.texture_sampler = environment_.sampler();
    for (uint32_t i = 0; i < n; ++i) extra.storage.push_back(records_.buffer(i));
    PBDSPLAT_TRY(make_host_stream(ctx, n, VkDeviceSize(options.anisotropic ? options.max_splats : 1) * sizeof(splat::GaussianShape),
                                  shapes_, extra.shapes));
    PBDSPLAT_TRY(make_host_stream(ctx, n, VkDeviceSize(options.sh_degree > 0 ? options.max_splats : 1) * sizeof(splat::GaussianSH),
                                  sh_rest_, extra.sh));
    PBDSPLAT_TRY(make_host_stream(ctx, n, VkDeviceSize(options.textures > 0 ? options.max_splats : 1) * sizeof(splat::GaussianTexcoord),
                                  texcoords_, extra.texcoords));
    auto white_texture = make_white_texture(ctx);
    if (!white_texture.ok()) return white_texture.error();
    white_ = std::move(white_texture).value();
    extra.textures.assign(SPLAT_MAX_TEXTURES, {white_.sampler(), white_.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
    // Streams drawn in the order they were written: the identity (a token entry without streams).
    const bool streams = options.anisotropic || options.sh_degree > 0 || options.textures > 0;
    const uint32_t identity_size = streams ? options.max_splats : 1u;
    auto identity = gpu::Buffer::create(ctx, VkDeviceSize(identity_size) * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                        gpu::MemoryUsage::upload);
    if (!identity.ok()) return identity.error();
    stream_identity_ = std::move(identity).value();
    auto* ids = static_cast<uint32_t*>(stream_identity_.mapped());
    for (uint32_t i = 0; i < identity_size; ++i) ids[i] = i;
    extra.order = {stream_identity_.handle()};
    auto uniforms = gpu::UniformSets::create(ctx, splat_.set_layout(), n, sizeof(gpu_types::FrameUniforms), &extra);
    if (!uniforms.ok()) return uniforms.error();
    uniforms_ = std::move(uniforms).value();
    if (options.gpu_sort) {
        std::vector<VkBuffer> records_per_slot;
        for (uint32_t i = 0; i < n; ++i) records_per_slot.push_back(records_.buffer(i));
        auto sort = GpuSort::create(ctx, options.max_splats, records_per_slot);
        if (!sort.ok()) return sort.error();
        sort_ = std::move(sort).value();
        extra.storage.clear();
        for (uint32_t i = 0; i < n; ++i) extra.storage.push_back(sort_.sorted_records(i));
        // Sorted records are drawn in the sort's order; their streams stay where they were
        // written, found through the sort's record indices.
        extra.order.clear();
        for (uint32_t i = 0; i < n; ++i) extra.order.push_back(sort_.values(i));
        auto sorted = gpu::UniformSets::create(ctx, splat_.set_layout(), n, sizeof(gpu_types::FrameUniforms), &extra);
        if (!sorted.ok()) return sorted.error();
        sorted_uniforms_ = std::move(sorted).value();
    }
    return create_slot_state();
}

core::Status SplatRenderer::create_slot_state() {
    const uint32_t n = options_.frames_in_flight;
    for (uint32_t i = 0; i < n; ++i) {
        auto timer = gpu::GpuTimer::create(*ctx_, 10);
        if (!timer.ok()) return timer.error();
        timers_.push_back(std::move(timer).value());
        auto counter = gpu::PipelineCounter::create(*ctx_, 3);  // the splat pass, discs over occluders, sums
        if (!counter.ok()) return counter.error();
        counters_.push_back(std::move(counter).value());
    }
    slot_pending_.assign(n, false);
    slot_bounds_.assign(n, SplatBounds{});
    slot_read_back_.assign(n, false);
    slot_cpu_.assign(n, GpuTimings{});
    return core::Status::success();
}

SplatRenderer::~SplatRenderer() {
    if (ctx_) (void)frames_.wait_all();
}

core::Status SplatRenderer::collect_timings(uint32_t slot) {
    if (!slot_pending_[slot]) return core::Status::success();
    slot_pending_[slot] = false;
    auto marks = timers_[slot].read(ctx_->vk());
    if (!marks.ok()) return marks.error();
    GpuTimings t = slot_cpu_[slot];
    for (const auto& [label, ms] : marks.value()) {
        if (label == "upload") t.upload_ms = ms;
        else if (label == "sort") t.sort_ms = ms;
        else if (label == "splat") t.splat_ms = ms;
        else if (label == "occluders") t.occluders_ms = ms;
        else if (label == "over occluders") t.over_occluders_ms = ms;
        else if (label == "accumulate") t.accumulate_ms = ms;
        else if (label == "resolve") t.resolve_ms = ms;
        else if (label == "readback") t.readback_ms = ms;
    }
    t.draw_ms = t.splat_ms + t.occluders_ms + t.over_occluders_ms + t.accumulate_ms + t.resolve_ms;
    auto counts = counters_[slot].read(ctx_->vk());
    if (!counts.ok()) return counts.error();
    t.splat_counts = counts.value();
    timings_ = t;
    return core::Status::success();
}

core::Result<VkCommandBuffer> SplatRenderer::begin_frame() {
    const uint32_t slot = frames_.slot();
    auto begun = frames_.begin();  // waits for this slot's previous frame
    if (!begun.ok()) return begun.error();
    cmd_ = begun.value();
    PBDSPLAT_TRY(collect_timings(slot));
    if (records_.path() == gpu::UploadPath::staged) ring_.retire(frames_.completed_serial());
    slot_cpu_[slot] = GpuTimings{};
    slot_read_back_[slot] = false;
    timers_[slot].begin(cmd_);
    timers_[slot].mark(cmd_, "start", VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT);
    counters_[slot].reset(cmd_);
    return cmd_;
}

core::Status SplatRenderer::end_frame(const VkSemaphoreSubmitInfo* wait, const VkSemaphoreSubmitInfo* signal) {
    const uint32_t slot = frames_.slot();
    PBDSPLAT_TRY(frames_.submit(wait, signal));
    slot_pending_[slot] = true;
    last_slot_ = slot;
    any_frame_ = true;
    cmd_ = VK_NULL_HANDLE;
    core::Status deferred = std::move(deferred_);
    deferred_ = core::Status::success();
    return deferred;
}

bool SplatRenderer::prepared(const SplatStyle& style) {
    if (core::Status s = splat_.prepare(style); !s.ok()) {
        if (deferred_.ok()) deferred_ = std::move(s);
        return false;
    }
    return true;
}

core::Status SplatRenderer::upload(std::span<const splat::GaussianRecord> records, std::span<const gpu::ByteRange> changed) {
    if (records.size() > options_.max_splats)
        return core::make_error(std::to_string(records.size()) + " Gaussians exceed the renderer's capacity of " +
                                std::to_string(options_.max_splats) + "; create it with a larger max_splats");
    const uint32_t slot = frames_.slot();
    const core::Stopwatch clock;
    auto written = records_.write(cmd_, slot, frames_.serial(), ring_, std::as_bytes(records), changed);
    if (!written.ok()) return written.error();
    if (has_normalised()) slot_bounds_[slot] = splat_bounds(records);
    slot_cpu_[slot].upload_cpu_ms = clock.elapsed_ms();
    slot_cpu_[slot].uploaded_bytes = written.value();
    timers_[slot].mark(cmd_, "upload", VK_PIPELINE_STAGE_2_COPY_BIT);
    return core::Status::success();
}

core::Status SplatRenderer::upload_shapes(std::span<const splat::GaussianShape> shapes) {
    return write_host_stream(shapes_[frames_.slot()], shapes, options_.max_splats, options_.anisotropic, "anisotropic shapes");
}

core::Status SplatRenderer::upload_sh(std::span<const splat::GaussianSH> sh) {
    return write_host_stream(sh_rest_[frames_.slot()], sh, options_.max_splats, options_.sh_degree > 0, "view-dependent colour");
}

core::Status SplatRenderer::upload_texcoords(std::span<const splat::GaussianTexcoord> texcoords) {
    return write_host_stream(texcoords_[frames_.slot()], texcoords, options_.max_splats, options_.textures > 0, "textured splats");
}

core::Status SplatRenderer::set_textures(std::span<const MeshTexture> textures) {
    if (textures.size() > options_.textures)
        return core::make_error(std::to_string(textures.size()) + " textures for a renderer created to read " + std::to_string(options_.textures));
    PBDSPLAT_TRY(frames_.wait_all());
    std::vector<gpu::Texture> made;
    for (const MeshTexture& t : textures) {
        auto texture = make_texture(*ctx_, t);
        if (!texture.ok()) return texture.error();
        made.push_back(std::move(texture).value());
    }
    std::vector<VkDescriptorImageInfo> images(SPLAT_MAX_TEXTURES, {white_.sampler(), white_.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
    for (size_t i = 0; i < made.size(); ++i) images[i] = {made[i].sampler(), made[i].view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    uniforms_.write_images(*ctx_, 7, images);
    if (has_gpu_sort()) sorted_uniforms_.write_images(*ctx_, 7, images);
    textures_ = std::move(made);  // the old ones only now: the sets no longer name them
    return core::Status::success();
}

void SplatRenderer::sort(const FrameInputs& inputs, uint32_t count) {
    PBDSPLAT_ASSERT(has_gpu_sort(), "SplatRenderer::sort without the GPU sort: create the renderer with options.gpu_sort");
    const uint32_t slot = frames_.slot();
    const Camera& c = inputs.camera;
    SortView v;
    v.view = math::look_at(c.eye, c.target, c.up);
    v.proj = math::perspective(math::radians(c.fov_y_degrees), float(target_.width()) / float(target_.height()), c.z_near, c.z_far);
    v.z_near = c.z_near;
    v.z_far = c.z_far;
    v.cull_radius_per_scale = splat_reach_bound(inputs.style);
    sort_.record(cmd_, slot, count, v);
    timers_[slot].mark(cmd_, "sort", VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
}

void SplatRenderer::draw(const FrameInputs& inputs, uint32_t count) {
    const uint32_t slot = frames_.slot();
    const auto uniforms = make_frame_uniforms(inputs, target_.width(), target_.height(), &sh_);
    PBDSPLAT_ASSERT(!gpu_sorted(inputs.style) || has_gpu_sort(), "SplatOrder::gpu needs a renderer created with options.gpu_sort");
    const gpu::UniformSets& sets = frame_sets(inputs.style);
    std::memcpy(sets.mapped(slot), &uniforms, sizeof(uniforms));
    const bool normalised = inputs.style.blend == Blend::normalised;
    PBDSPLAT_ASSERT(!normalised || has_normalised(),
                    "Blend::normalised needs a renderer created with options.normalised (and the graph's accumulation and resolve passes)");
    PBDSPLAT_ASSERT(!normalised || inputs.style.footprint == Footprint::gaussian,
                    "Blend::normalised weighs each splat by its Gaussian falloff: draw it with Footprint::gaussian");
    const bool occluded = render::occluded_style(inputs.style);
    PBDSPLAT_ASSERT(!occluded || has_occluders(),
                    "SplatStyle::mesh_occluders needs a renderer created with options.occluders (and the graph's occluders pass)");
    target_.begin(cmd_, inputs.background.data(), normalised || occluded);
    // Under mesh occluders the ground comes after them (draw_occluders).
    if (inputs.ground.visible && !occluded) ground_.record(cmd_, sets.set(slot), inputs.ground);
    if (prepared(inputs.style)) {
        counters_[slot].begin(cmd_);
        splat_.record(cmd_, inputs.style, sets.set(slot), splat_source(inputs, count));
        counters_[slot].end(cmd_);
    }
    target_.end(cmd_);
    timers_[slot].mark(cmd_, "splat", VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
}

bool SplatRenderer::gpu_sorted(const SplatStyle& s) { return s.blend == Blend::over && s.order == SplatOrder::gpu; }

const gpu::UniformSets& SplatRenderer::frame_sets(const SplatStyle& s) const { return gpu_sorted(s) ? sorted_uniforms_ : uniforms_; }

SplatSource SplatRenderer::splat_source(const FrameInputs& inputs, uint32_t count) const {
    const uint32_t slot = frames_.slot();
    if (gpu_sorted(inputs.style)) return {sort_.sorted_records(slot), count, sort_.control(slot)};
    return {records_.buffer(slot), count};
}

void SplatRenderer::draw_over_occluders(const FrameInputs& inputs, uint32_t count) {
    if (!render::occluded_style(inputs.style) || inputs.style.blend == Blend::normalised) return;
    if (!prepared(inputs.style)) return;
    const uint32_t slot = frames_.slot();
    target_.resume(cmd_);
    counters_[slot].begin(cmd_);
    splat_.record_paper_occluded(cmd_, inputs.style, frame_sets(inputs.style).set(slot), splat_source(inputs, count), occluders_.set());
    counters_[slot].end(cmd_);
    target_.end(cmd_);
    timers_[slot].mark(cmd_, "over occluders", VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
}

core::Status SplatRenderer::set_occluders(std::span<const Vec4f> positions, std::span<const std::array<uint32_t, 3>> triangles, size_t one_sided) {
    PBDSPLAT_ASSERT(has_occluders(), "SplatRenderer::set_occluders: create the renderer with options.occluders");
    return occluders_.set_mesh(positions, triangles, frames_.slot(), one_sided);
}

void SplatRenderer::draw_occluders(const FrameInputs& inputs) {
    if (!render::occluded_style(inputs.style)) return;
    PBDSPLAT_ASSERT(has_occluders(), "SplatStyle::mesh_occluders needs a renderer created with options.occluders");
    occluders_.record(cmd_, inputs.camera, inputs.style.occluder_push, target_.depth().view(), frames_.slot());
    // The ground after the mesh, at its own depth: drawn first, it hid the mesh's pushed-back
    // depth wherever the surface lay within the push above it (a sheet resting on the ground
    // vanished); drawn here it still hides what lies below it, splats and mesh alike.
    if (inputs.ground.visible) {
        target_.resume(cmd_);
        ground_.record(cmd_, frame_sets(inputs.style).set(frames_.slot()), inputs.ground);
        target_.end(cmd_);
    }
    timers_[frames_.slot()].mark(cmd_, "occluders", VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
}

void SplatRenderer::accumulate(const FrameInputs& inputs, uint32_t count) {
    if (inputs.style.blend != Blend::normalised || !prepared(inputs.style)) return;
    const uint32_t slot = frames_.slot();
    const PixelRect r = splat_screen_rect(slot_bounds_[slot], inputs, target_.width(), target_.height());
    normalised_area_ = {{int32_t(r.x), int32_t(r.y)}, {r.width, r.height}};
    blend_.begin_accumulation(cmd_, target_.depth().view(), normalised_area_);
    counters_[slot].begin(cmd_);
    splat_.record_accumulation(cmd_, uniforms_.set(slot), {records_.buffer(slot), count},
                               render::occluded_style(inputs.style) ? occluders_.set() : VK_NULL_HANDLE);
    counters_[slot].end(cmd_);
    blend_.end_accumulation(cmd_);
    timers_[slot].mark(cmd_, "accumulate", VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
}

void SplatRenderer::resolve(const FrameInputs& inputs) {
    if (inputs.style.blend != Blend::normalised) return;
    blend_.record_resolve(cmd_, target_.color().view(), normalised_area_);
    timers_[frames_.slot()].mark(cmd_, "resolve", VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
}

void SplatRenderer::readback() {
    const uint32_t slot = frames_.slot();
    target_.record_readback(cmd_, slot);
    slot_read_back_[slot] = true;
    timers_[slot].mark(cmd_, "readback", VK_PIPELINE_STAGE_2_COPY_BIT);
}

core::Result<core::ImageRgba8> SplatRenderer::finish() {
    PBDSPLAT_TRY(frames_.wait_all());
    for (uint32_t i = 0; i < slot_pending_.size(); ++i)
        if (i != last_slot_) PBDSPLAT_TRY(collect_timings(i));
    PBDSPLAT_TRY(collect_timings(last_slot_));  // the newest frame's timings win
    if (!any_frame_) return core::make_error("finish() before any frame was rendered");
    if (!slot_read_back_[last_slot_]) return core::make_error("the last frame did not read its image back");
    return target_.read(last_slot_);
}

} // namespace pbdsplat::render
