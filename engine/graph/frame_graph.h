#pragma once
// The frame graph: every CPU stage and GPU pass of a frame declares what it reads and writes
// through typed, versioned handles; compile() orders the passes, culls those a scene does not
// need and derives the GPU barriers between them; execute() runs what is left.
//
// Culling has two causes, both visible in describe():
//  - "needs <resource>": the pass requires a resource the scene did not provide (no volume
//    constraint without pressure, no topology stage without cut events, no readback without an
//    image to write). A culled pass's in-place writes pass through unchanged.
//  - "unused": nothing that is kept reads what the pass produces, and it has no side effect
//    (a sort whose order the splat pass does not read).
// Compile once per scene configuration; execute every frame.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <typeindex>
#include <vector>

#include "core/result.h"
#include "gpu/barriers.h"

namespace pbdsplat::graph {

enum class PassKind { cpu, gpu };

// How a GPU pass uses a buffer or image; images also name their layout.
struct GpuUse {
    VkPipelineStageFlags2 stage = VK_PIPELINE_STAGE_2_NONE;
    VkAccessFlags2 access = VK_ACCESS_2_NONE;
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    bool writes() const;
};

// What the graph needs to place barriers on a GPU resource.
struct GpuBufferRef {
    VkBuffer buffer = VK_NULL_HANDLE;
};
struct GpuImageRef {
    VkImage image = VK_NULL_HANDLE;
    VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
};

// A version of a resource. Reading takes one; writing in place returns the next.
template <class T>
struct Handle {
    uint32_t version = UINT32_MAX;
    bool valid() const { return version != UINT32_MAX; }
};

struct ExecuteContext {
    VkCommandBuffer cmd = VK_NULL_HANDLE;  // the frame's command buffer, for GPU passes
    uint64_t frame = 0;
};

class FrameGraph;

// Declares one pass's accesses; handed to the setup function of add_pass.
class PassBuilder {
public:
    // Reads `h`; the pass is culled when the resource is absent.
    template <class T>
    Handle<T> read(Handle<T> h, GpuUse use = {}) { return Handle<T>{access(h.version, use, false)}; }
    // Modifies `h` in place; returns the new version.
    template <class T>
    Handle<T> write(Handle<T> h, GpuUse use = {}) { return Handle<T>{access(h.version, use, true)}; }
    // Writes `h` without reading it (its old contents are discarded): the first writer of a
    // version created by FrameGraph::declare.
    template <class T>
    Handle<T> produce(Handle<T> h, GpuUse use = {}) { return Handle<T>{produce_version(h.version, use)}; }
    // The pass has an effect outside the graph (a file, the screen): never culled as unused.
    void side_effect();

private:
    friend class FrameGraph;
    PassBuilder(FrameGraph& g, uint32_t pass) : graph_(g), pass_(pass) {}
    uint32_t access(uint32_t version, GpuUse use, bool write);
    uint32_t produce_version(uint32_t version, GpuUse use);
    FrameGraph& graph_;
    uint32_t pass_;
};

// The resources a pass declared, resolved to their data at execution: what it reads as const,
// what it writes (through the handle its write or produce returned) as mutable. Any other
// access is a violation (FrameGraph::access_violations; in a debug build it also asserts): the
// data is still handed over, so a release build behaves as before and the tests see the list.
class PassResources {
public:
    template <class T>
    const T& read(Handle<T> h) const { return *static_cast<const T*>(lookup(h.version, typeid(T), false)); }
    template <class T>
    T& write(Handle<T> h) const { return *static_cast<T*>(lookup(h.version, typeid(T), true)); }

private:
    friend class FrameGraph;
    PassResources(const FrameGraph& g, uint32_t pass) : graph_(g), pass_(pass) {}
    void* lookup(uint32_t version, const std::type_info& type, bool write) const;
    const FrameGraph& graph_;
    uint32_t pass_;
};

struct PassInfo {
    std::string name;
    PassKind kind;
    bool culled = false;
    std::string reason;  // why it was culled
    size_t barriers = 0;  // barriers recorded before it
    uint32_t tag = 0;     // the caller's, from add_pass (what a pass's time counts towards)
};

class FrameGraph {
public:
    FrameGraph();
    ~FrameGraph();
    FrameGraph(const FrameGraph&) = delete;
    FrameGraph& operator=(const FrameGraph&) = delete;
    FrameGraph(FrameGraph&&) noexcept;
    FrameGraph& operator=(FrameGraph&&) noexcept;

    // Brings outside data into the graph. `data` may be null: the resource is then absent and
    // every pass that reads or writes it is culled. `persistent`: its final state outlives the
    // frame (simulation state), so writing it is a side effect.
    template <class T>
    Handle<T> import(std::string name, T* data, bool persistent = false) {
        return Handle<T>{import_resource(std::move(name), data, typeid(T), persistent, gpu_kind<T>())};
    }
    // A version whose producer is declared later (out-of-order graphs, and tests of ordering).
    template <class T>
    Handle<T> declare(std::string name, T* data) {
        return Handle<T>{declare_resource(std::move(name), data, typeid(T), gpu_kind<T>())};
    }

    using Execute = std::function<void(const PassResources&, ExecuteContext&)>;
    // `setup` declares the accesses and returns the function to run each frame. `tag`: the
    // caller's own label, handed back by describe() (timings grouped by stage, not by name).
    void add_pass(std::string name, PassKind kind, const std::function<Execute(PassBuilder&)>& setup, uint32_t tag = 0);

    // Orders, culls and derives barriers; fails on a cycle or a version written twice.
    core::Status compile();
    // Runs the kept passes in order, recording barriers before GPU passes. Returns, per kept
    // pass, its CPU milliseconds (in the order of describe()'s kept passes).
    const std::vector<double>& execute(ExecuteContext& ctx);

    // The passes in execution order, culled ones included and marked.
    std::vector<PassInfo> describe() const;
    // Graphviz dot of passes and resources; culled passes dashed and grey.
    std::string to_dot() const;
    size_t kept_pass_count() const;

    // ---- Checking declared writes (tests and debugging; it costs a fingerprint per pass). ----
    // A fingerprint of a CPU resource's contents: equal before and after a pass that did not
    // declare a write to it, or the pass wrote it undeclared.
    template <class T>
    void set_fingerprint(Handle<T> h, std::function<uint64_t(const T&)> f) {
        set_fingerprint_untyped(h.version, [f = std::move(f)](const void* data) { return f(*static_cast<const T*>(data)); });
    }
    // From now on execute() fingerprints, around every kept pass, each fingerprinted resource the
    // pass does not declare a write to, and notes every change as a violation.
    void check_writes(bool on);
    // "pass 'events' changed 'appearance' without declaring a write", in the order met.
    const std::vector<std::string>& write_violations() const;
    // Accesses through PassResources that the pass did not declare, always checked: "pass
    // 'sort' writes 'sort' through a read", "pass 'x' reads 'y', which it did not declare";
    // each once, in the order met.
    const std::vector<std::string>& access_violations() const;

private:
    friend class PassBuilder;
    friend class PassResources;
    struct Impl;
    template <class T>
    static int gpu_kind() {
        if constexpr (std::is_same_v<T, GpuBufferRef>) return 1;
        else if constexpr (std::is_same_v<T, GpuImageRef>) return 2;
        else return 0;
    }
    uint32_t import_resource(std::string name, void* data, const std::type_info& type, bool persistent, int gpu);
    void set_fingerprint_untyped(uint32_t version, std::function<uint64_t(const void*)> f);
    uint32_t declare_resource(std::string name, void* data, const std::type_info& type, int gpu);
    std::unique_ptr<Impl> impl_;
};

} // namespace pbdsplat::graph
