#include "passes/gpu_passes.h"

#include <algorithm>
#include <cstring>

namespace pbdsplat::passes {

void changed_ranges(std::span<const splat::GaussianRecord> before, std::span<const splat::GaussianRecord> after,
                    std::vector<gpu::ByteRange>& out) {
    // Blocks of 256 records (6 KiB): small enough to skip what a local drag leaves alone, large
    // enough that the copy list stays short. Touching blocks merge into one range.
    constexpr size_t k_block = 256;
    constexpr size_t k_size = sizeof(splat::GaussianRecord);
    out.clear();
    if (before.size() != after.size()) {
        out.push_back({0, after.size_bytes()});
        return;
    }
    for (size_t start = 0; start < after.size(); start += k_block) {
        const size_t n = std::min(k_block, after.size() - start);
        if (std::memcmp(before.data() + start, after.data() + start, n * k_size) == 0) continue;
        const VkDeviceSize offset = start * k_size, bytes = n * k_size;
        if (!out.empty() && out.back().offset + out.back().size == offset) out.back().size += bytes;
        else out.push_back({offset, bytes});
    }
    if (out.empty()) out.push_back({0, 0});  // nothing changed: an empty range, not "everything"
}

void GpuPassResources::refresh(const render::SplatRenderer& r) {
    records.buffer = r.records_buffer();
    readback.buffer = r.readback_buffer();
    sorted.buffer = r.sorted_records_buffer();
    sort_control.buffer = r.sort_control_buffer();
    sort_order.buffer = r.sort_order_buffer();
    color.image = r.color_image();
    depth.image = r.depth_image();
    accumulation.image = r.accumulation_image(render::SumLayer::seen_side);
    accumulation_inside.image = r.accumulation_image(render::SumLayer::inside);
    occluders.image = r.occluder_image();
}

graph::GpuUse to_graph(const render::Use& u) { return {u.access.stage, u.access.access, u.layout}; }

GpuInputHandles import_gpu_input(graph::FrameGraph& g, GpuFrameInput& input) {
    return {g.import("frame view", &input.frame), g.import("splat stream", &input.splats), g.import("occluder input", &input.occluders)};
}

namespace {

// The GPU passes of one frame, added in order: each adds its pass and hands on the handles the
// next ones read (what the upload wrote, what the splats drew).
struct GpuChain {
    graph::FrameGraph& g;
    render::SplatRenderer& renderer;
    GpuPassResources& res;
    GpuInputHandles input;
    graph::Handle<core::Status> status;
    bool gpu_sort;
    uint32_t tag;
    render::Use records_read = render::uses::records_read(renderer.path());
    // Imported first, in this order.
    graph::Handle<graph::GpuBufferRef> records = g.import("gpu records", &res.records);
    graph::Handle<graph::GpuImageRef> color = g.import("colour target", &res.color);
    graph::Handle<graph::GpuImageRef> depth = g.import("depth target", &res.depth);
    graph::Handle<graph::GpuBufferRef> readback = g.import("readback buffer", &res.readback);
    graph::Handle<graph::GpuBufferRef> uploaded, sorted, control, order;
    graph::Handle<graph::GpuImageRef> drawn, depth_drawn, occluded;

    void add_upload() {
        // On the direct path the CPU writes the records in place before the submit: no GPU access.
        const graph::GpuUse use = renderer.upload_path() == gpu::UploadPath::staged ? to_graph(render::uses::upload_write) : graph::GpuUse{};
        g.add_pass("upload", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
            b.read(input.splats);
            status = b.write(status);
            uploaded = b.write(records, use);
            return [&gpu = renderer, in_h = input.splats, st = status](const graph::PassResources& r, graph::ExecuteContext&) {
                const SplatStream& in = r.read(in_h);
                core::Status& out = r.write(st);
                const gpu::ByteRange all{0, in.records.size_bytes()};
                const std::span<const gpu::ByteRange> ranges =
                    in.changed.empty() ? std::span<const gpu::ByteRange>(&all, 1) : std::span<const gpu::ByteRange>(in.changed);
                out = gpu.upload(in.records, ranges);
                // Anisotropic bodies' axes go straight into host-visible memory (no GPU copy).
                if (out.ok() && !in.shapes.empty()) out = gpu.upload_shapes(in.shapes);
                if (out.ok() && !in.sh.empty()) out = gpu.upload_sh(in.sh);
                if (out.ok() && !in.texcoords.empty()) out = gpu.upload_texcoords(in.texcoords);
            };
        }, tag);
    }

    void add_sort() {
        sorted = g.import("sorted records", &res.sorted);
        control = g.import("sort control", &res.sort_control);
        order = g.import("sort order", &res.sort_order);
        g.add_pass("gpu sort", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
            b.read(input.frame);
            b.read(input.splats);
            b.read(uploaded, to_graph(render::uses::compute_read));
            sorted = b.write(sorted, to_graph(render::uses::compute_write));
            control = b.write(control, to_graph(render::uses::compute_write));
            order = b.write(order, to_graph(render::uses::compute_write));
            return [&gpu = renderer, in = input](const graph::PassResources& r, graph::ExecuteContext&) {
                gpu.sort(r.read(in.frame), uint32_t(r.read(in.splats).records.size()));
            };
        }, tag);
    }

    // What a pass that draws the splats reads: the frame, and the uploaded records or the sort's.
    void read_draw_records(graph::PassBuilder& b) const {
        b.read(input.frame);
        b.read(input.splats);
        if (gpu_sort) {
            b.read(sorted, to_graph(records_read));
            b.read(control, to_graph(render::uses::indirect_read));
            b.read(order, to_graph(render::uses::streams_read(renderer.path())));
        } else {
            b.read(uploaded, to_graph(records_read));
        }
    }

    void add_splat() {
        g.add_pass("splat", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
            read_draw_records(b);
            drawn = b.write(color, to_graph(render::uses::color_attachment));
            depth_drawn = b.write(depth, to_graph(render::uses::depth_attachment));
            b.side_effect();  // the colour target is what a frame is for (presented or read back)
            return [&gpu = renderer, in = input](const graph::PassResources& r, graph::ExecuteContext&) {
                gpu.draw(r.read(in.frame), uint32_t(r.read(in.splats).records.size()));
            };
        }, tag);
    }

    // The surface mesh's depth and its distance image, then the ground over them.
    void add_occluders() {
        const auto occluders = g.import("occluder image", &res.occluders);
        g.add_pass("occluders", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
            b.read(input.frame);
            b.read(input.occluders);
            status = b.write(status);
            drawn = b.write(drawn, to_graph(render::uses::color_attachment));
            depth_drawn = b.write(depth_drawn, to_graph(render::uses::depth_attachment));
            occluded = b.write(occluders, to_graph(render::uses::color_attachment));
            return [&gpu = renderer, in = input, st = status](const graph::PassResources& r, graph::ExecuteContext&) {
                const OccluderInput& mesh = r.read(in.occluders);
                if (core::Status& out = r.write(st); out.ok()) out = gpu.set_occluders(mesh.positions, mesh.triangles, mesh.one_sided);
                gpu.draw_occluders(r.read(in.frame));
            };
        }, tag);
    }

    // The paper's disc, drawn against the occluders.
    void add_splat_over_occluders() {
        g.add_pass("splat over occluders", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
            read_draw_records(b);
            b.read(occluded, to_graph(renderer.occluder_read()));
            drawn = b.write(drawn, to_graph(render::uses::color_attachment));
            depth_drawn = b.write(depth_drawn, to_graph(render::uses::depth_attachment));
            b.side_effect();
            return [&gpu = renderer, in = input](const graph::PassResources& r, graph::ExecuteContext&) {
                gpu.draw_over_occluders(r.read(in.frame), uint32_t(r.read(in.splats).records.size()));
            };
        }, tag);
    }

    // Normalised blending: the front fragments summed against the visibility depth the splat pass
    // left, then divided and blended over the colour target. Normalised frames are never sorted
    // (the sums do not depend on order), so the records are the uploaded ones.
    void add_normalised() {
        const auto accumulation = g.import("accumulation image", &res.accumulation);
        const auto accumulation_inside = g.import("accumulation image, inside", &res.accumulation_inside);
        graph::Handle<graph::GpuImageRef> summed, summed_inside;
        g.add_pass("splat accumulate", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
            b.read(input.frame);
            b.read(input.splats);
            b.read(uploaded, to_graph(records_read));
            if (renderer.has_occluders()) b.read(occluded, to_graph(renderer.occluder_read()));
            b.write(depth_drawn, to_graph(render::uses::depth_attachment));
            summed = b.write(accumulation, to_graph(render::uses::color_attachment));
            summed_inside = b.write(accumulation_inside, to_graph(render::uses::color_attachment));
            return [&gpu = renderer, in = input](const graph::PassResources& r, graph::ExecuteContext&) {
                gpu.accumulate(r.read(in.frame), uint32_t(r.read(in.splats).records.size()));
            };
        }, tag);
        g.add_pass("splat resolve", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
            b.read(input.frame);
            b.read(summed, to_graph(render::uses::accumulation_sampled));
            b.read(summed_inside, to_graph(render::uses::accumulation_sampled));
            drawn = b.write(drawn, to_graph(render::uses::color_attachment));
            b.side_effect();  // as the splat pass: the colour target is what a frame is for
            return [&gpu = renderer, in_h = input.frame](const graph::PassResources& r, graph::ExecuteContext&) { gpu.resolve(r.read(in_h)); };
        }, tag);
    }

    void add_readback(graph::Handle<ImageSink> sink) {
        g.add_pass("readback", graph::PassKind::gpu, [&](graph::PassBuilder& b) {
            b.read(drawn, to_graph(render::uses::color_copy_source));
            b.write(readback, to_graph(render::uses::readback_write));
            b.write(sink);
            b.side_effect();
            return [&gpu = renderer](const graph::PassResources&, graph::ExecuteContext&) { gpu.readback(); };
        }, tag);
    }
};

} // namespace

graph::Handle<graph::GpuImageRef> add_gpu_passes(graph::FrameGraph& g, render::SplatRenderer& renderer,
                                                 GpuPassResources& res, const GpuInputHandles& input,
                                                 graph::Handle<core::Status> status, graph::Handle<ImageSink> sink, bool gpu_sort,
                                                 uint32_t tag) {
    GpuChain chain{g, renderer, res, input, status, gpu_sort, tag};
    chain.add_upload();
    if (gpu_sort) chain.add_sort();
    chain.add_splat();
    if (renderer.has_occluders()) chain.add_occluders();
    if (renderer.has_occluders() && !renderer.has_normalised()) chain.add_splat_over_occluders();
    if (renderer.has_normalised()) chain.add_normalised();
    chain.add_readback(sink);
    return chain.drawn;
}

} // namespace pbdsplat::passes
