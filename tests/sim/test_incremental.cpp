#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "mesh/procedural.h"
#include "sim/constraint_order.h"
#include "sim/integrate.h"
#include "sim/slack_lists.h"

using namespace pbdsplat;

namespace {
std::vector<sim::DistanceConstraint> ring_edges(uint32_t n) {
    std::vector<sim::DistanceConstraint> c;
    for (uint32_t i = 0; i < n; ++i) c.push_back({i, (i + 1) % n, 1.0f, 0.0f});
    for (uint32_t i = 0; i < n; ++i) c.push_back({i, (i + 7) % n, 2.0f, 0.0f});
    return c;
}
} // namespace

TEST_SUITE("sim/incremental") {
    TEST_CASE("slack lists: grown lists move, shrunk ones stay, compaction keeps every list") {
        sim::SlackLists<uint32_t> l;
        const std::vector<uint32_t> start{0, 2, 2, 5}, items{1, 2, 3, 4, 5};
        l.build(start, items);
        CHECK(std::ranges::equal(l.of(0), std::vector<uint32_t>{1, 2}));
        CHECK(l.of(1).empty());
        const std::vector<uint32_t> big{9, 8, 7, 6, 5, 4, 3};
        const size_t pool = l.pool_size();
        l.assign(1, big);  // more than its slack: moves to the end
        CHECK(l.pool_size() > pool);
        CHECK(std::ranges::equal(l.of(1), big));
        l.assign(2, std::vector<uint32_t>{42});
        CHECK(std::ranges::equal(l.of(2), std::vector<uint32_t>{42}));
        l.grow(5);
        CHECK(l.of(4).empty());
        sim::SlackLists<uint32_t> before = l;
        l.compact();
        CHECK(l == before);
        CHECK(l.abandoned() == 0);
    }

    TEST_CASE("slack lists: push stays in place while the room lasts, then moves; erase keeps the order") {
        sim::SlackLists<uint32_t> l;
        const std::vector<uint32_t> start{0, 3, 4}, items{1, 2, 3, 4};
        l.build(start, items);
        const size_t pool = l.pool_size();
        for (uint32_t k = 0; k < sim::SlackLists<uint32_t>::k_slack; ++k) l.push(0, 10 + k);
        CHECK(l.pool_size() == pool);  // the slack took them
        CHECK(std::ranges::equal(l.of(0), std::vector<uint32_t>{1, 2, 3, 10, 11}));
        CHECK(std::ranges::equal(l.of(1), std::vector<uint32_t>{4}));
        l.push(0, 99);  // past the room: the list moves to the pool's end
        CHECK(l.pool_size() > pool);
        CHECK(std::ranges::equal(l.of(0), std::vector<uint32_t>{1, 2, 3, 10, 11, 99}));
        l.erase(0, 2);
        CHECK(std::ranges::equal(l.of(0), std::vector<uint32_t>{1, 3, 10, 11, 99}));
        l.erase(0, 99);
        l.erase(1, 4);
        CHECK(std::ranges::equal(l.of(0), std::vector<uint32_t>{1, 3, 10, 11}));
        CHECK(l.of(1).empty());
    }

    TEST_CASE("rings updated for the touched vertices equal a full build") {
        mesh::TriangleMesh m = mesh::icosphere(2);
        sim::VertexRings r = sim::build_vertex_rings(m.triangles, m.positions.size());
        // Flip the diagonal of two triangles sharing an edge, append one triangle with a new vertex.
        const uint32_t nv = uint32_t(m.positions.size());
        m.triangles.push_back({m.triangles[0][0], m.triangles[0][1], nv});
        m.triangles[3] = {m.triangles[3][1], m.triangles[3][2], m.triangles[3][0]};  // same triangle, rotated
        std::vector<uint32_t> touched{m.triangles.back()[0], m.triangles.back()[1], nv};
        for (uint32_t v : m.triangles[3]) touched.push_back(v);
        std::sort(touched.begin(), touched.end());
        touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
        const std::vector<uint32_t> extra{3, uint32_t(m.triangles.size() - 1)};
        sim::update_vertex_rings(r, m.triangles, nv + 1, touched, extra);
        const sim::VertexRings fresh = sim::build_vertex_rings(m.triangles, nv + 1);
        CHECK(r.ring == fresh.ring);
        CHECK(r.triangles == fresh.triangles);
    }

    TEST_CASE("distance groups stay valid through removals and additions, reuse slots, and regroup") {
        const uint32_t n = 64;
        std::vector<sim::DistanceConstraint> c = ring_edges(n);
        sim::DistanceGroups g = sim::make_distance_groups(c, n);
        std::vector<float> lambda(c.size(), 0.0f);
        REQUIRE(sim::distance_groups_valid(c, g, n));
        std::mt19937 rng(3);
        size_t particles = n;
        for (int round = 0; round < 200; ++round) {
            // Remove up to three live constraints, add three new ones (some on new particles).
            std::vector<uint32_t> remove;
            for (int k = 0; k < 3; ++k) {
                const uint32_t s = uint32_t(rng() % c.size());
                if (c[s].alive() && std::find(remove.begin(), remove.end(), s) == remove.end()) remove.push_back(s);
            }
            if (round % 10 == 0) ++particles;
            std::vector<sim::DistanceConstraint> add;
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = uint32_t(rng() % particles), b = uint32_t(rng() % particles);
                if (a != b) add.push_back({a, b, 1.0f, float(k)});
            }
            const std::vector<uint32_t> placed = sim::replace_distance_constraints(c, g, lambda, particles, remove, add);
            REQUIRE(sim::distance_groups_valid(c, g, particles));
            REQUIRE(lambda.size() == c.size());
            for (size_t k = 0; k < add.size(); ++k) {
                REQUIRE(placed[k] < c.size());
                CHECK((c[placed[k]].i == add[k].i && c[placed[k]].j == add[k].j && c[placed[k]].compliance == add[k].compliance));
            }
        }
        CHECK(g.slots_reused > 0);
        CHECK(g.slots_appended > 0);
        CHECK(g.regroupings > 0);
    }

    TEST_CASE("a constraint that finds no dead slot goes into an existing colour, moving one constraint per later group") {
        const uint32_t n = 64;
        std::vector<sim::DistanceConstraint> c = ring_edges(n);
        sim::DistanceGroups g = sim::make_distance_groups(c, n);
        std::vector<float> lambda(c.size(), 0.0f);
        for (size_t k = 0; k < lambda.size(); ++k) lambda[k] = float(k);  // follows its constraint when moved
        const size_t groups = g.start.size() - 1;
        REQUIRE(groups >= 2);
        // Each ring vertex to a new particle: no removal, so no dead slot to take, and a ring vertex
        // uses four of the colours, so one is free at both ends.
        std::vector<sim::DistanceConstraint> add{{0, n, 3.0f, 0.5f}, {16, n + 1, 3.0f, 0.25f}, {8, n + 2, 3.0f, 0.125f}};
        std::vector<std::pair<sim::DistanceConstraint, float>> kept;
        for (size_t k = 0; k < c.size(); ++k) kept.push_back({c[k], lambda[k]});
        const std::vector<uint32_t> placed = sim::replace_distance_constraints(c, g, lambda, n + 3, {}, add);
        REQUIRE(sim::distance_groups_valid(c, g, n + 3));
        CHECK(g.start.size() - 1 == groups);  // no group of their own
        CHECK(g.colours_added == 0);
        CHECK(g.regroupings == 0);
        CHECK(g.slots_appended == add.size());
        for (size_t k = 0; k < add.size(); ++k) {
            REQUIRE(placed[k] < c.size());
            CHECK((c[placed[k]].i == add[k].i && c[placed[k]].j == add[k].j));
            CHECK(lambda[placed[k]] == 0.0f);
        }
        // Every constraint that was there still is, with its own multiplier.
        for (const auto& [old, l] : kept) {
            const auto at = std::find_if(c.begin(), c.end(), [&](const sim::DistanceConstraint& x) { return x.i == old.i && x.j == old.j; });
            REQUIRE(at != c.end());
            CHECK(lambda[size_t(at - c.begin())] == l);
        }
    }
}
