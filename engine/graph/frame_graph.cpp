#include "graph/frame_graph.h"

#include <algorithm>
#include <queue>
#include <typeindex>

#include "core/assert.h"
#include "core/timer.h"

namespace pbdsplat::graph {
namespace {
constexpr uint32_t k_none = UINT32_MAX;

constexpr VkAccessFlags2 k_write_bits = VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                                        VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT |
                                        VK_ACCESS_2_HOST_WRITE_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT |
                                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
} // namespace

bool GpuUse::writes() const { return (access & k_write_bits) != 0; }

struct FrameGraph::Impl {
    struct Resource {
        std::string name;
        void* data = nullptr;
        std::type_index type = typeid(void);
        bool persistent = false;
        int gpu = 0;  // 0 CPU data, 1 buffer, 2 image
        std::function<uint64_t(const void*)> fingerprint;  // for check_writes
    };
    struct Version {
        uint32_t resource = 0;
        uint32_t producer = k_none;   // pass that made it
        uint32_t previous = k_none;   // version it modified in place
        uint32_t modified_by = k_none;
    };
    struct Access {
        uint32_t version;   // the version read (or discarded, for produce)
        uint32_t out = k_none;  // the version written, if any
        GpuUse use;
        bool reads = true;
    };
    struct Barrier {
        uint32_t resource;
        gpu::Access before, after;
        VkImageLayout old_layout, new_layout;
    };
    struct Pass {
        std::string name;
        PassKind kind;
        uint32_t tag = 0;
        std::vector<Access> accesses;
        bool side_effect = false;
        Execute run;
        bool culled = false;
        std::string reason;
        std::vector<Barrier> barriers;
    };

    std::vector<Resource> resources;
    std::vector<Version> versions;
    std::vector<Pass> passes;
    std::vector<uint32_t> order;  // all passes, execution order
    std::vector<uint32_t> kept;   // kept passes, execution order
    std::vector<double> timings;
    std::string build_error;  // first error seen while declaring, reported by compile()
    bool check_writes = false;
    std::vector<std::string> violations;
    std::vector<std::string> access_violations;
    bool compiled = false;

    // The fingerprinted, present resources that `pass` does not declare a write to.
    std::vector<std::pair<uint32_t, uint64_t>> fingerprints_not_written(const Pass& pass) const {
        std::vector<std::pair<uint32_t, uint64_t>> out;
        for (uint32_t r = 0; r < resources.size(); ++r) {
            const Resource& res = resources[r];
            if (!res.fingerprint || !res.data) continue;
            const bool written = std::any_of(pass.accesses.begin(), pass.accesses.end(), [&](const Access& a) {
                return a.out != k_none && versions[a.out].resource == r;
            });
            if (!written) out.push_back({r, res.fingerprint(res.data)});
        }
        return out;
    }

    // The version a reader really sees once culled in-place writers pass their input through.
    uint32_t resolve(uint32_t v) const {
        while (versions[v].producer != k_none && passes[versions[v].producer].culled && versions[v].previous != k_none)
            v = versions[v].previous;
        return v;
    }
    bool available(uint32_t v) const {
        v = resolve(v);
        const Version& ver = versions[v];
        if (!resources[ver.resource].data) return false;  // absent import
        if (ver.producer == k_none) return ver.previous == k_none && ver.resource < resources.size() &&
                                           !declared_only(v);
        return !passes[ver.producer].culled;
    }
    std::vector<bool> declared;  // per version: made by declare(), so it needs a producer
    bool declared_only(uint32_t v) const { return v < declared.size() && declared[v]; }
    // The steps of compile(), in order.
    core::Status order_passes();
    void cull_absent();
    void cull_unused();
    void place_barriers();
};

FrameGraph::FrameGraph() : impl_(std::make_unique<Impl>()) {}
FrameGraph::~FrameGraph() = default;
FrameGraph::FrameGraph(FrameGraph&&) noexcept = default;
FrameGraph& FrameGraph::operator=(FrameGraph&&) noexcept = default;

uint32_t FrameGraph::import_resource(std::string name, void* data, const std::type_info& type, bool persistent, int gpu) {
    impl_->resources.push_back({std::move(name), data, type, persistent, gpu, {}});
    impl_->versions.push_back({uint32_t(impl_->resources.size() - 1), k_none, k_none, k_none});
    impl_->declared.push_back(false);
    impl_->compiled = false;
    return uint32_t(impl_->versions.size() - 1);
}

uint32_t FrameGraph::declare_resource(std::string name, void* data, const std::type_info& type, int gpu) {
    const uint32_t v = import_resource(std::move(name), data, type, false, gpu);
    impl_->declared[v] = true;
    return v;
}

void PassBuilder::side_effect() { graph_.impl_->passes[pass_].side_effect = true; }

uint32_t PassBuilder::access(uint32_t version, GpuUse use, bool write) {
    auto& g = *graph_.impl_;
    PBDSPLAT_ASSERT(version < g.versions.size(), "pass '" + g.passes[pass_].name + "' uses an invalid handle");
    FrameGraph::Impl::Access a{version, k_none, use, true};
    if (write) {
        if (g.versions[version].modified_by != k_none && g.build_error.empty())
            g.build_error = "passes '" + g.passes[g.versions[version].modified_by].name + "' and '" + g.passes[pass_].name +
                            "' both modify the same version of '" + g.resources[g.versions[version].resource].name +
                            "'; chain the second on the first one's output";
        g.versions[version].modified_by = pass_;
        g.versions.push_back({g.versions[version].resource, pass_, version, k_none});
        g.declared.push_back(false);
        a.out = uint32_t(g.versions.size() - 1);
    }
    g.passes[pass_].accesses.push_back(a);
    return write ? a.out : version;
}

uint32_t PassBuilder::produce_version(uint32_t version, GpuUse use) {
    auto& g = *graph_.impl_;
    PBDSPLAT_ASSERT(version < g.versions.size(), "pass '" + g.passes[pass_].name + "' produces an invalid handle");
    if (g.versions[version].producer != k_none && g.build_error.empty())
        g.build_error = "'" + g.resources[g.versions[version].resource].name + "' is produced by both '" +
                        g.passes[g.versions[version].producer].name + "' and '" + g.passes[pass_].name + "'";
    g.versions[version].producer = pass_;
    g.declared[version] = false;
    g.passes[pass_].accesses.push_back({version, version, use, false});
    return version;
}

void* PassResources::lookup(uint32_t version, const std::type_info& type, bool write) const {
    auto& g = *graph_.impl_;
    PBDSPLAT_ASSERT(version < g.versions.size(), "PassResources: invalid handle");
    const auto& r = g.resources[g.versions[version].resource];
    PBDSPLAT_ASSERT(r.type == std::type_index(type), "PassResources: '" + r.name + "' has another type");
    const auto& pass = g.passes[pass_];
    const bool declared = std::any_of(pass.accesses.begin(), pass.accesses.end(), [&](const FrameGraph::Impl::Access& a) {
        return a.out == version || (!write && a.reads && a.version == version);
    });
    if (!declared) {
        const bool read_only = std::any_of(pass.accesses.begin(), pass.accesses.end(),
                                           [&](const FrameGraph::Impl::Access& a) { return a.version == version; });
        std::string what = "pass '" + pass.name + "' " + (write ? "writes '" : "reads '") + r.name + "'" +
                           (write && read_only ? " through a read" : ", which it did not declare");
        PBDSPLAT_DEBUG_ASSERT(false, what);
        if (std::find(g.access_violations.begin(), g.access_violations.end(), what) == g.access_violations.end())
            g.access_violations.push_back(std::move(what));
    }
    return r.data;
}

void FrameGraph::add_pass(std::string name, PassKind kind, const std::function<Execute(PassBuilder&)>& setup, uint32_t tag) {
    impl_->passes.push_back({std::move(name), kind, tag, {}, false, {}, false, {}, {}});
    PassBuilder builder(*this, uint32_t(impl_->passes.size() - 1));
    Execute run = setup(builder);
    impl_->passes.back().run = std::move(run);
    impl_->compiled = false;
}

// 1. Order: producers before readers, readers of a version before whoever modifies it.
core::Status FrameGraph::Impl::order_passes() {
    Impl& g = *this;
    const size_t n = g.passes.size();
    std::vector<std::vector<uint32_t>> next(n);
    std::vector<uint32_t> incoming(n, 0);
    auto edge = [&](uint32_t from, uint32_t to) {
        if (from == k_none || from == to) return;
        next[from].push_back(to);
        ++incoming[to];
    };
    for (uint32_t p = 0; p < n; ++p)
        for (const auto& a : g.passes[p].accesses) {
            if (a.reads) edge(g.versions[a.version].producer, p);
            const uint32_t modifier = g.versions[a.version].modified_by;
            if (modifier != k_none && modifier != p) edge(p, modifier);  // read before overwrite
        }
    std::priority_queue<uint32_t, std::vector<uint32_t>, std::greater<>> ready;  // declaration order breaks ties
    for (uint32_t p = 0; p < n; ++p)
        if (incoming[p] == 0) ready.push(p);
    g.order.clear();
    while (!ready.empty()) {
        const uint32_t p = ready.top();
        ready.pop();
        g.order.push_back(p);
        for (uint32_t q : next[p])
            if (--incoming[q] == 0) ready.push(q);
    }
    if (g.order.size() != n) {
        std::string cycle;
        for (uint32_t p = 0; p < n; ++p)
            if (incoming[p] > 0) cycle += (cycle.empty() ? "'" : ", '") + g.passes[p].name + "'";
        return core::make_error("frame graph: the passes " + cycle + " depend on each other in a cycle");
    }

    return core::Status::success();
}

// 2. Culling by absence, in order (availability flows forward).
void FrameGraph::Impl::cull_absent() {
    Impl& g = *this;
    for (uint32_t p : g.order) {
        for (const auto& a : g.passes[p].accesses) {
            if (!a.reads) continue;
            if (!g.available(a.version)) {
                g.passes[p].culled = true;
                g.passes[p].reason = "needs " + g.resources[g.versions[a.version].resource].name;
                break;
            }
        }
    }

}

// 3. Culling by use: keep what a side effect (or persistent state) depends on.
void FrameGraph::Impl::cull_unused() {
    Impl& g = *this;
    const size_t n = g.passes.size();
    std::vector<bool> live(n, false);
    for (uint32_t p = 0; p < n; ++p) {
        if (g.passes[p].culled) continue;
        bool sink = g.passes[p].side_effect;
        for (const auto& a : g.passes[p].accesses)
            if (a.out != k_none && g.resources[g.versions[a.out].resource].persistent) sink = true;
        live[p] = sink;
    }
    for (auto it = g.order.rbegin(); it != g.order.rend(); ++it) {
        if (!live[*it]) continue;
        for (const auto& a : g.passes[*it].accesses) {
            if (!a.reads) continue;
            const uint32_t producer = g.versions[g.resolve(a.version)].producer;
            if (producer != k_none && !g.passes[producer].culled) live[producer] = true;
        }
    }
    for (uint32_t p = 0; p < n; ++p)
        if (!g.passes[p].culled && !live[p]) g.passes[p].culled = true, g.passes[p].reason = "unused";

}

// 4. Barriers between the kept GPU passes. A frame starts from the state the previous one left
//    (the last use in this order); images start undefined when first written.
void FrameGraph::Impl::place_barriers() {
    Impl& g = *this;
    g.kept.clear();
    for (uint32_t p : g.order)
        if (!g.passes[p].culled) g.kept.push_back(p);
    struct State {
        bool used = false;
        gpu::Access last_write{};
        VkPipelineStageFlags2 read_stages = 0, visible_stages = 0;
        VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    };
    std::vector<State> state(g.resources.size());
    std::vector<GpuUse> final_use(g.resources.size());
    for (uint32_t p : g.kept)
        for (const auto& a : g.passes[p].accesses)
            if (g.resources[g.versions[a.version].resource].gpu) final_use[g.versions[a.version].resource] = a.use;
    std::vector<bool> first(g.resources.size(), true);
    for (uint32_t p : g.kept) {
        Impl::Pass& pass = g.passes[p];
        for (const auto& a : pass.accesses) {
            const uint32_t r = g.versions[a.version].resource;
            if (!g.resources[r].gpu || a.use.stage == VK_PIPELINE_STAGE_2_NONE) continue;
            State& s = state[r];
            if (first[r]) {  // steady state: the previous frame's last use
                first[r] = false;
                const GpuUse& f = final_use[r];
                s.used = true;
                s.last_write = f.writes() ? gpu::Access{f.stage, f.access} : gpu::Access{};
                s.read_stages = f.writes() ? 0 : f.stage;
                s.visible_stages = 0;
                s.layout = (a.use.writes() || !a.reads) ? VK_IMAGE_LAYOUT_UNDEFINED : f.layout;
            }
            const bool layout_change = g.resources[r].gpu == 2 && s.layout != a.use.layout;
            if (a.use.writes()) {
                if (s.used || layout_change)
                    pass.barriers.push_back({r, {s.last_write.stage | s.read_stages, s.last_write.access},
                                             {a.use.stage, a.use.access}, s.layout, a.use.layout});
                s.last_write = {a.use.stage, a.use.access};
                s.read_stages = 0;
                s.visible_stages = a.use.stage;
            } else {
                if ((s.last_write.stage && !(s.visible_stages & a.use.stage)) || layout_change) {
                    // Chain through the stages an earlier barrier made the write (and its layout
                    // transition) visible to, so this reader is ordered after that transition too.
                    pass.barriers.push_back({r, {s.last_write.stage | s.visible_stages, s.last_write.access},
                                             {a.use.stage, a.use.access}, s.layout, a.use.layout});
                    s.visible_stages |= a.use.stage;
                }
                s.read_stages |= a.use.stage;
            }
            s.layout = a.use.layout;
            s.used = true;
        }
    }
}

core::Status FrameGraph::compile() {
    Impl& g = *impl_;
    if (!g.build_error.empty()) return core::make_error("frame graph: " + g.build_error);
    for (auto& p : g.passes) p.culled = false, p.reason.clear(), p.barriers.clear();
    PBDSPLAT_TRY(g.order_passes());
    g.cull_absent();
    g.cull_unused();
    g.place_barriers();
    g.timings.assign(g.kept.size(), 0.0);
    g.compiled = true;
    return core::Status::success();
}

const std::vector<double>& FrameGraph::execute(ExecuteContext& ctx) {
    Impl& g = *impl_;
    PBDSPLAT_ASSERT(g.compiled, "FrameGraph::execute before a successful compile()");
    for (size_t k = 0; k < g.kept.size(); ++k) {
        Impl::Pass& pass = g.passes[g.kept[k]];
        const PassResources resources(*this, g.kept[k]);
        const core::Stopwatch clock;
        if (ctx.cmd != VK_NULL_HANDLE)
            for (const auto& b : pass.barriers) {
                const Impl::Resource& r = g.resources[b.resource];
                // A handle left null this frame (a swapchain image that could not be acquired)
                // gets no barrier; the passes that use it skip their work too.
                if (r.gpu == 1) {
                    const VkBuffer buffer = static_cast<GpuBufferRef*>(r.data)->buffer;
                    if (buffer != VK_NULL_HANDLE) gpu::buffer_barrier(ctx.cmd, buffer, b.before, b.after);
                } else {
                    const auto* img = static_cast<GpuImageRef*>(r.data);
                    if (img->image != VK_NULL_HANDLE)
                        gpu::image_barrier(ctx.cmd, img->image, img->aspect, b.before, b.old_layout, b.after, b.new_layout);
                }
            }
        std::vector<std::pair<uint32_t, uint64_t>> before;  // (resource, fingerprint) the pass may not change
        if (g.check_writes) before = g.fingerprints_not_written(pass);
        if (pass.run) pass.run(resources, ctx);
        g.timings[k] = clock.elapsed_ms();
        for (const auto& [r, print] : before)
            if (g.resources[r].fingerprint(g.resources[r].data) != print)
                g.violations.push_back("pass '" + pass.name + "' changed '" + g.resources[r].name + "' without declaring a write");
    }
    return g.timings;
}

void FrameGraph::set_fingerprint_untyped(uint32_t version, std::function<uint64_t(const void*)> f) {
    PBDSPLAT_ASSERT(version < impl_->versions.size(), "FrameGraph::set_fingerprint: a handle of this graph, please");
    impl_->resources[impl_->versions[version].resource].fingerprint = std::move(f);
}

void FrameGraph::check_writes(bool on) {
    impl_->check_writes = on;
    impl_->violations.clear();
}

const std::vector<std::string>& FrameGraph::write_violations() const { return impl_->violations; }

const std::vector<std::string>& FrameGraph::access_violations() const { return impl_->access_violations; }

std::vector<PassInfo> FrameGraph::describe() const {
    std::vector<PassInfo> out;
    for (uint32_t p : impl_->order) {
        const auto& pass = impl_->passes[p];
        out.push_back({pass.name, pass.kind, pass.culled, pass.reason, pass.barriers.size(), pass.tag});
    }
    return out;
}

size_t FrameGraph::kept_pass_count() const { return impl_->kept.size(); }

std::string FrameGraph::to_dot() const {
    const Impl& g = *impl_;
    auto quote = [](const std::string& s) {
        std::string o = "\"";
        for (char c : s) o += (c == '"' ? std::string("\\\"") : std::string(1, c));
        return o + "\"";
    };
    std::string dot = "digraph frame {\n  rankdir=LR;\n  node [fontname=\"sans-serif\", fontsize=10];\n";
    for (size_t r = 0; r < g.resources.size(); ++r)
        dot += "  r" + std::to_string(r) + " [shape=ellipse, label=" + quote(g.resources[r].name) +
               (g.resources[r].data ? "" : ", style=dashed, fontcolor=grey") + "];\n";
    for (uint32_t p : g.order) {
        const auto& pass = g.passes[p];
        std::string label = pass.name + (pass.kind == PassKind::gpu ? " [gpu]" : " [cpu]");
        if (pass.culled) label += "\\nculled: " + pass.reason;
        dot += "  p" + std::to_string(p) + " [shape=box, label=" + quote(label) +
               (pass.culled ? ", style=dashed, color=grey, fontcolor=grey" : ", style=filled, fillcolor=\"#e8f0ff\"") + "];\n";
        for (const auto& a : pass.accesses) {
            const std::string r = "r" + std::to_string(g.versions[a.version].resource);
            if (a.reads) dot += "  " + r + " -> p" + std::to_string(p) + ";\n";
            if (a.out != k_none) dot += "  p" + std::to_string(p) + " -> " + r + ";\n";
        }
    }
    return dot + "}\n";
}

} // namespace pbdsplat::graph
