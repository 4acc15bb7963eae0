#include <doctest/doctest.h>

#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "graph/frame_graph.h"

using namespace pbdsplat;
using graph::FrameGraph;
using graph::PassBuilder;
using graph::PassKind;

namespace {
// CPU-only mock passes that log their execution.
using Log = std::vector<std::string>;

FrameGraph::Execute logger(Log& log, std::string name) {
    return [&log, name](const graph::PassResources&, graph::ExecuteContext&) { log.push_back(name); };
}

const graph::PassInfo& info(const std::vector<graph::PassInfo>& all, const std::string& name) {
    for (const auto& p : all)
        if (p.name == name) return p;
    FAIL("no pass named " << name);
    return all.front();
}
} // namespace

TEST_SUITE("graph/frame_graph") {
    TEST_CASE("passes run in dependency order, whatever the declaration order") {
        FrameGraph g;
        Log log;
        int x = 0, y = 0;
        auto hx = g.declare("x", &x);
        auto hy = g.declare("y", &y);
        g.add_pass("consume", PassKind::cpu, [&](PassBuilder& b) {
            b.read(hy);
            b.side_effect();
            return logger(log, "consume");
        });
        g.add_pass("middle", PassKind::cpu, [&](PassBuilder& b) {
            b.read(hx);
            b.produce(hy);
            return logger(log, "middle");
        });
        g.add_pass("make", PassKind::cpu, [&](PassBuilder& b) {
            b.produce(hx);
            return logger(log, "make");
        });
        REQUIRE(g.compile().ok());
        graph::ExecuteContext ctx;
        g.execute(ctx);
        CHECK(log == Log{"make", "middle", "consume"});
    }

    TEST_CASE("a cycle is refused, naming its passes") {
        FrameGraph g;
        int x = 0, y = 0;
        auto hx = g.declare("x", &x);
        auto hy = g.declare("y", &y);
        g.add_pass("a", PassKind::cpu, [&](PassBuilder& b) {
            b.read(hy);
            b.produce(hx);
            b.side_effect();
            return FrameGraph::Execute{};
        });
        g.add_pass("b", PassKind::cpu, [&](PassBuilder& b) {
            b.read(hx);
            b.produce(hy);
            return FrameGraph::Execute{};
        });
        const auto s = g.compile();
        REQUIRE_FALSE(s.ok());
        CHECK(s.error().message == "frame graph: the passes 'a', 'b' depend on each other in a cycle");
    }

    TEST_CASE("two passes modifying the same version are refused") {
        FrameGraph g;
        int x = 0;
        auto hx = g.import("x", &x, true);
        g.add_pass("one", PassKind::cpu, [&](PassBuilder& b) { b.write(hx); return FrameGraph::Execute{}; });
        g.add_pass("two", PassKind::cpu, [&](PassBuilder& b) { b.write(hx); return FrameGraph::Execute{}; });
        const auto s = g.compile();
        REQUIRE_FALSE(s.ok());
        CHECK(s.error().message.find("'one' and 'two' both modify the same version of 'x'") != std::string::npos);
    }

    // The simulation chain of a frame: a stage whose input the scene lacks is culled, and the
    // in-place state passes through it to the next stage.
    TEST_CASE("a stage needing an absent resource is culled and the chain still runs") {
        for (bool pressure : {false, true}) {
            FrameGraph g;
            Log log;
            int body = 0, volumes = 0;
            auto b0 = g.import("body", &body, true);
            auto vc = g.import("volume constraints", pressure ? &volumes : static_cast<int*>(nullptr));
            graph::Handle<int> b1, b2, b3;
            g.add_pass("forces", PassKind::cpu, [&](PassBuilder& b) { b1 = b.write(b0); return logger(log, "forces"); });
            g.add_pass("distance", PassKind::cpu, [&](PassBuilder& b) { b2 = b.write(b1); return logger(log, "distance"); });
            g.add_pass("volume", PassKind::cpu, [&](PassBuilder& b) {
                b.read(vc);
                b3 = b.write(b2);
                return logger(log, "volume");
            });
            g.add_pass("integrate", PassKind::cpu, [&](PassBuilder& b) { b.write(b3); return logger(log, "integrate"); });
            REQUIRE(g.compile().ok());
            const auto passes = g.describe();
            CHECK(info(passes, "volume").culled == !pressure);
            if (!pressure) CHECK(info(passes, "volume").reason == "needs volume constraints");
            graph::ExecuteContext ctx;
            g.execute(ctx);
            if (pressure) CHECK(log == Log{"forces", "distance", "volume", "integrate"});
            else CHECK(log == Log{"forces", "distance", "integrate"});
        }
    }

    TEST_CASE("a pass whose output nobody reads is culled as unused") {
        for (bool sorted : {false, true}) {
            FrameGraph g;
            Log log;
            int records = 0, order = 0, image = 0;
            auto r = g.import("records", &records);
            auto o = g.declare("draw order", &order);
            auto img = g.import("image", &image);
            g.add_pass("sort", PassKind::cpu, [&](PassBuilder& b) {
                b.read(r);
                b.produce(o);
                return logger(log, "sort");
            });
            g.add_pass("splat", PassKind::cpu, [&](PassBuilder& b) {
                b.read(r);
                if (sorted) b.read(o);
                b.write(img);
                b.side_effect();
                return logger(log, "splat");
            });
            REQUIRE(g.compile().ok());
            CHECK(info(g.describe(), "sort").culled == !sorted);
            if (!sorted) CHECK(info(g.describe(), "sort").reason == "unused");
            graph::ExecuteContext ctx;
            CHECK(g.execute(ctx).size() == (sorted ? 2u : 1u));
        }
    }

    TEST_CASE("GPU barriers come from the declared uses") {
        FrameGraph g;
        graph::GpuBufferRef buffer;  // no real buffer: compile only
        graph::GpuImageRef color;
        auto buf = g.import("records", &buffer);
        auto img = g.import("color", &color);
        const graph::GpuUse copy_write{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT};
        const graph::GpuUse vertex_read{VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT};
        const graph::GpuUse attachment{VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                                       VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
        const graph::GpuUse transfer_src{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                                         VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
        graph::Handle<graph::GpuBufferRef> b1;
        graph::Handle<graph::GpuImageRef> i1;
        g.add_pass("upload", PassKind::gpu, [&](PassBuilder& b) { b1 = b.write(buf, copy_write); return FrameGraph::Execute{}; });
        g.add_pass("visibility", PassKind::gpu, [&](PassBuilder& b) {
            b.read(b1, vertex_read);
            i1 = b.write(img, attachment);
            return FrameGraph::Execute{};
        });
        g.add_pass("colour", PassKind::gpu, [&](PassBuilder& b) {
            b.read(b1, vertex_read);  // same stage as before: already visible
            i1 = b.write(i1, attachment);
            return FrameGraph::Execute{};
        });
        g.add_pass("readback", PassKind::gpu, [&](PassBuilder& b) {
            b.read(i1, transfer_src);
            b.side_effect();
            return FrameGraph::Execute{};
        });
        REQUIRE(g.compile().ok());
        const auto passes = g.describe();
        CHECK(info(passes, "upload").barriers == 1);      // after last frame's vertex reads
        CHECK(info(passes, "visibility").barriers == 2);  // copy -> vertex; undefined -> attachment
        CHECK(info(passes, "colour").barriers == 1);      // attachment write after write
        CHECK(info(passes, "readback").barriers == 1);    // attachment -> transfer source
        CHECK(g.to_dot().find("digraph frame") == 0);
    }

    TEST_CASE("a pass that changes a resource it did not declare a write to is caught, one that declared it is not") {
        FrameGraph g;
        int counter = 0, other = 0;
        auto c = g.import("counter", &counter, true);
        auto o = g.import("other", &other, true);
        g.set_fingerprint<int>(c, [](const int& v) { return uint64_t(v); });
        g.set_fingerprint<int>(o, [](const int& v) { return uint64_t(v); });
        g.add_pass("honest", PassKind::cpu, [&](PassBuilder& b) {
            c = b.write(c);
            return [c](const graph::PassResources& r, graph::ExecuteContext&) { ++r.write(c); };
        });
        g.add_pass("sneaky", PassKind::cpu, [&](PassBuilder& b) {
            b.read(c);
            o = b.write(o);
            // Declares a write of `other` only, and changes `counter` too.
            return [&counter, o](const graph::PassResources& r, graph::ExecuteContext&) { ++r.write(o), ++counter; };
        });
        REQUIRE(g.compile().ok());
        g.check_writes(true);
        graph::ExecuteContext ctx;
        g.execute(ctx);
        REQUIRE(g.write_violations().size() == 1);
        CHECK(g.write_violations()[0] == "pass 'sneaky' changed 'counter' without declaring a write");
        g.check_writes(false);
        g.execute(ctx);
        CHECK(g.write_violations().empty());
        CHECK(counter == 4);
        CHECK(other == 2);
    }

    TEST_CASE("a pass reaches only what it declared: reads as const, writes through the handle its write returned") {
        FrameGraph g;
        int a = 1, b = 2, c = 3;
        auto ha = g.import("a", &a, true);
        auto hb = g.import("b", &b, true);
        auto hc = g.import("c", &c, true);
        // Reads `a` as declared; writes `b` through the version its write returned.
        g.add_pass("honest", PassKind::cpu, [&](PassBuilder& p) {
            p.read(ha);
            hb = p.write(hb);
            static_assert(std::is_same_v<decltype(std::declval<const graph::PassResources&>().read(ha)), const int&>,
                          "a read hands out const data");
            return [ha, hb](const graph::PassResources& r, graph::ExecuteContext&) { r.write(hb) += r.read(ha); };
        });
        REQUIRE(g.compile().ok());
        graph::ExecuteContext ctx;
        g.execute(ctx);
        CHECK(b == 3);
        CHECK(g.access_violations().empty());

        // Writes through a handle it declared only as a read, and reads one it never declared.
        FrameGraph bad;
        ha = bad.import("a", &a, true);
        hb = bad.import("b", &b, true);
        hc = bad.import("c", &c, true);
        bad.add_pass("sneaky", PassKind::cpu, [&](PassBuilder& p) {
            p.read(ha);
            hb = p.write(hb);
            return [ha, hb, hc](const graph::PassResources& r, graph::ExecuteContext&) {
                r.write(ha) = r.read(hc) + r.read(hb);
            };
        });
        REQUIRE(bad.compile().ok());
#ifdef NDEBUG
        bad.execute(ctx);
        REQUIRE(bad.access_violations().size() == 2);
        CHECK(bad.access_violations()[0] == "pass 'sneaky' reads 'c', which it did not declare");
        CHECK(bad.access_violations()[1] == "pass 'sneaky' writes 'a' through a read");
        bad.execute(ctx);  // each once
        CHECK(bad.access_violations().size() == 2);
#else
        CHECK_THROWS(bad.execute(ctx));  // a debug build stops at the first
#endif
    }
}

#include "graph/blackboard.h"

TEST_SUITE("graph/frame_graph") {
    TEST_CASE("the blackboard hands on the newest version, and refuses a missing or mistyped key by name") {
        FrameGraph g;
        graph::Blackboard board;
        int value = 0;
        constexpr graph::Key<int> k_value{"value"};
        constexpr graph::Key<float> k_value_as_float{"value"};  // the same name, another type
        constexpr graph::Key<int> k_missing{"missing"};
        graph::import_into(g, board, k_value, &value);
        graph::Handle<int> h = board.get(k_value);
        // A module writes it and puts the new version back: the next module reads that one.
        g.add_pass("write", PassKind::cpu, [&](PassBuilder& b) {
            h = b.write(h);
            return [h](const graph::PassResources& r, graph::ExecuteContext&) { r.write(h) = 7; };
        });
        board.put(k_value, h);
        int seen = -1;
        g.add_pass("read", PassKind::cpu, [&](PassBuilder& b) {
            const graph::Handle<int> in = board.get(k_value);
            b.read(in);
            b.side_effect();
            return [in, &seen](const graph::PassResources& r, graph::ExecuteContext&) { seen = r.read(in); };
        });
        REQUIRE(g.compile().ok());
        graph::ExecuteContext ctx;
        g.execute(ctx);
        CHECK(seen == 7);

        auto missing = board.find(k_missing);
        REQUIRE(!missing.ok());
        CHECK(missing.error().to_string().find("'missing'") != std::string::npos);
        auto mistyped = board.find(k_value_as_float);
        REQUIRE(!mistyped.ok());
        CHECK(mistyped.error().to_string().find("'value' holds") != std::string::npos);
        CHECK(board.has("value"));
        CHECK(!board.has("missing"));
        // Several at once, each under its own key and type.
        constexpr graph::Key<float> k_other{"other"};
        board.put_all(std::pair{k_value, graph::Handle<int>{41}}, std::pair{k_other, graph::Handle<float>{42}});
        CHECK(board.get(k_value).version == 41);
        CHECK(board.get(k_other).version == 42);
    }
}
