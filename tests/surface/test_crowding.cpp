#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "mesh/procedural.h"
#include "surface/crowding.h"
#include "surface/density.h"
#include "surface/edges.h"

using namespace pbdsplat;

namespace {

// A mesh with its particles at rest and its samples laid at spacing h.
struct Sampled {
    std::vector<Vec3f> rest;
    std::vector<mesh::Triangle> triangles;
    std::vector<Vec4f> x;
    std::vector<Vec3f> normals;
    float h = 0.0f;
    surface::BoundaryParticles samples;

    explicit Sampled(const mesh::TriangleMesh& m, float eta = 0.5f) : rest(m.positions), triangles(m.triangles) {
        h = surface::spacing(m, eta);
        samples = surface::sample_surface(m, {h, 7});
        for (const Vec3f& p : rest) x.emplace_back(p.x(), p.y(), p.z(), 0.0f);
        normals = mesh::vertex_normals(m);
        surface::update_boundary_particles(triangles, x, normals, samples);
    }
    // The particles are splats too (the samples were thrown clear of them).
    surface::CrowdingQuery query() const {
        surface::CrowdingQuery q;
        q.h = h;
        q.anchors_drawn = true;
        return q;
    }
    // A copy of sample i moved `d` h along its triangle's first edge: the same triangle, the same side.
    size_t add_beside(size_t i, float d) {
        const mesh::Triangle& t = triangles[samples.triangle[i]];
        const Vec3f e = (rest[t[1]] - rest[t[0]]).normalized();
        samples.triangle.push_back(samples.triangle[i]);
        samples.bary.push_back(samples.bary[i]);
        samples.position.push_back(samples.position[i] + d * h * e);
        samples.normal.push_back(samples.normal[i]);
        return samples.size() - 1;
    }
    // Scales the body about its centre (every triangle stretched alike) and carries the samples.
    void scale(float f) {
        for (size_t v = 0; v < rest.size(); ++v) x[v] = Vec4f(f * rest[v].x(), f * rest[v].y(), f * rest[v].z(), 0.0f);
        surface::update_boundary_particles(triangles, x, normals, samples);
    }
    // The largest distance from a point of the surface to its nearest splat (sample or particle).
    float largest_gap(uint32_t points = 3000) const {
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        float worst = 0.0f;
        for (uint32_t k = 0; k < points; ++k) {
            const auto& t = triangles[rng() % triangles.size()];
            float a = u(rng), b = u(rng);
            if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
            const Vec3f p = ((1.0f - a - b) * x[t[0]] + a * x[t[1]] + b * x[t[2]]).head<3>();
            float best = 1e30f;
            for (const Vec4f& q : x) best = std::min(best, (q.head<3>() - p).norm());
            for (size_t i = 0; i < samples.size(); ++i)
                if (!samples.retiring(i)) best = std::min(best, (samples.position[i] - p).norm());
            worst = std::max(worst, best);
        }
        return worst;
    }
};

size_t retiring(const surface::BoundaryParticles& s) {
    size_t n = 0;
    for (size_t i = 0; i < s.size(); ++i) n += s.retiring(i);
    return n;
}

} // namespace

TEST_SUITE("surface/crowding") {
    TEST_CASE("a sample pressed against a kept one retires; the older one stays") {
        Sampled s(mesh::icosphere(3));
        surface::CrowdingResult clean = surface::thin_crowds(s.x, s.normals, s.triangles, s.query(), s.samples);
        CHECK(clean.retired == 0);  // a fresh maximal set at spacing h has no crowd
        CHECK(clean.gaps.empty());  // nor a gap
        const size_t close = s.add_beside(10, 0.4f);
        const surface::CrowdingResult r = surface::thin_crowds(s.x, s.normals, s.triangles, s.query(), s.samples);
        CHECK(r.retired == 1);
        CHECK(s.samples.retiring(close));
        CHECK_FALSE(s.samples.retiring(10));
        CHECK(s.samples.fade_step[close] == doctest::Approx(-s.query().fade_step));
        // Once retiring it is no one's neighbour: a second pass retires nothing more.
        CHECK(surface::thin_crowds(s.x, s.normals, s.triangles, s.query(), s.samples).retired == 0);
    }

    TEST_CASE("one candidate among many kept: every kept sample within reach finds it, wherever the cells fall") {
        // One shrunk triangle among 1,280: its lone sample is the only candidate, so the kept
        // samples meet it through the cell bitmap that prefilters a small set against a large
        // one. Placed in random directions at 0.5-0.69 h from a kept sample of a neighbouring
        // triangle, it must retire every time, wherever it falls against the cell faces.
        Sampled base(mesh::icosphere(3));
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        int retired = 0;
        constexpr int k_trials = 300;
        for (int trial = 0; trial < k_trials; ++trial) {
            Sampled s = base;
            const size_t i = rng() % s.samples.size();
            const uint32_t t = s.samples.triangle[i];
            const mesh::Triangle& c = s.triangles[t];
            // A neighbour of t across its first edge: the candidate's triangle.
            uint32_t neighbour = t;
            for (uint32_t f = 0; f < s.triangles.size() && neighbour == t; ++f) {
                const mesh::Triangle& o = s.triangles[f];
                const int shared = int(std::count(o.begin(), o.end(), c[0])) + int(std::count(o.begin(), o.end(), c[1]));
                if (f != t && shared == 2) neighbour = f;
            }
            REQUIRE(neighbour != t);
            const Vec3f n = (s.rest[c[1]] - s.rest[c[0]]).cross(s.rest[c[2]] - s.rest[c[0]]).normalized();
            const Vec3f e1 = (s.rest[c[1]] - s.rest[c[0]]).normalized(), e2 = n.cross(e1);
            const float angle = 6.2831853f * u(rng), d = 0.5f + 0.19f * u(rng);
            const size_t k = s.add_beside(i, 0.0f);
            s.samples.triangle[k] = neighbour;
            s.samples.position[k] = s.samples.position[i] + d * s.h * (std::cos(angle) * e1 + std::sin(angle) * e2);
            std::vector<uint8_t> changed(s.triangles.size(), 0);
            changed[neighbour] = surface::k_shrank;
            surface::CrowdingQuery q = s.query();
            q.changed = changed;
            q.gap = 0.0f;
            const surface::CrowdingResult r = surface::thin_crowds(s.x, s.normals, s.triangles, q, s.samples);
            CAPTURE(trial);
            CAPTURE(d);
            CHECK(s.samples.retiring(k));
            retired += int(r.retired);
        }
        CHECK(retired == k_trials);  // only the candidate, every time
    }

    TEST_CASE("samples fading in give way to settled ones") {
        Sampled s(mesh::icosphere(3));
        const size_t n = s.samples.size();
        surface::fade_in(s.samples, n - 1, 6);  // the last sample is new
        // An older sample moved next to it: the newcomer yields, though it comes later in order.
        s.samples.position[0] = s.samples.position[n - 1] + Vec3f(0.0f, 0.0f, 0.0f);
        s.samples.triangle[0] = s.samples.triangle[n - 1];
        s.samples.bary[0] = s.samples.bary[n - 1];
        surface::thin_crowds(s.x, s.normals, s.triangles, s.query(), s.samples);
        CHECK(s.samples.retiring(n - 1));
        CHECK_FALSE(s.samples.retiring(0));
    }

    TEST_CASE("the two faces of a fold are no neighbours, a second layer is") {
        // Two sheets 0.3 h apart, each sampled on its own: facing away from each other (a fold
        // pressed flat) or the same way (a second layer).
        const mesh::TriangleMesh sheet = mesh::grid_sheet(8, 1.0f);
        for (bool fold : {true, false}) {
            CAPTURE(fold);
            mesh::TriangleMesh both = sheet;
            const float h = surface::spacing(sheet, 0.5f);
            const uint32_t base = uint32_t(both.positions.size()), first = uint32_t(sheet.triangles.size());
            for (const Vec3f& p : sheet.positions) both.positions.push_back(p + Vec3f(0.0f, 0.3f * h, 0.0f));
            for (const mesh::Triangle& t : sheet.triangles)
                both.triangles.push_back(fold ? mesh::Triangle{t[0] + base, t[2] + base, t[1] + base}
                                              : mesh::Triangle{t[0] + base, t[1] + base, t[2] + base});
            Sampled s(both);
            s.samples = surface::sample_surface(sheet, {h, 7});
            const size_t one = s.samples.size();
            for (size_t i = 0; i < one; ++i) {
                s.samples.triangle.push_back(s.samples.triangle[i] + first);
                const Vec2f b = s.samples.bary[i];
                s.samples.bary.push_back(fold ? Vec2f(b.y(), b.x()) : b);  // the corners 1 and 2 swapped
            }
            surface::update_boundary_particles(s.triangles, s.x, s.normals, s.samples);
            REQUIRE(std::abs(s.samples.position[one][1] - s.samples.position[0][1] - 0.3f * h) < 1e-5f);
            const surface::CrowdingResult r = surface::thin_crowds(s.x, s.normals, s.triangles, s.query(), s.samples);
            if (fold) {
                CHECK(r.retired == 0);
            } else {
                // Every sample of the upper sheet has the lower one's twin 0.3 h below.
                CHECK(r.retired == one);
                for (size_t i = one; i < s.samples.size(); ++i) CHECK(s.samples.retiring(i));
            }
        }
    }

    TEST_CASE("edge samples never retire and crowd no one") {
        Sampled s(mesh::grid_sheet(8, 1.0f));
        const size_t interior = s.samples.size();
        REQUIRE(surface::lay_edge_samples(s.rest, s.triangles, s.h, {}, s.samples) > 0);
        surface::update_boundary_particles(s.triangles, s.x, s.normals, s.samples);
        const surface::CrowdingResult r = surface::thin_crowds(s.x, s.normals, s.triangles, s.query(), s.samples);
        CHECK(r.retired == 0);
        for (size_t i = interior; i < s.samples.size(); ++i) CHECK_FALSE(s.samples.retiring(i));
    }

    TEST_CASE("a triangle no sample reaches is a gap, and the density control fills it") {
        Sampled s(mesh::icosphere(3), 0.25f);
        const float sampled = s.largest_gap();
        // Empty a cap: the samples above y = 0.6 (the particles stay, but they are 4 h apart).
        s.samples.keep_if([&](size_t i) { return s.samples.position[i].y() < 0.6f; });
        surface::update_boundary_particles(s.triangles, s.x, s.normals, s.samples);
        const float opened = s.largest_gap();
        REQUIRE(opened > 1.5f * s.h);  // the cap emptied leaves 4 h between its particles
        const surface::CrowdingResult r = surface::thin_crowds(s.x, s.normals, s.triangles, s.query(), s.samples);
        REQUIRE_FALSE(r.gaps.empty());
        for (uint32_t t : r.gaps) {
            const mesh::Triangle& c = s.triangles[t];
            CHECK((s.rest[c[0]] + s.rest[c[1]] + s.rest[c[2]]).y() / 3.0f > 0.6f);  // only in the cap
        }
        // The body swells by 6 %: too little for the triangles' own trigger (density_grow 1.1), so
        // only the samples' trigger can see the gap, once the change (over 5 %) wakes it.
        surface::DensityControl control(s.rest, s.triangles, {});
        s.scale(1.06f);
        for (int f = 0; f < 8; ++f) control.update(s.x, s.normals, s.triangles, true, s.h, 3, s.samples);
        CHECK(s.largest_gap() < 1.15f * 1.06f * sampled);  // as closed as the sampler left it
        CHECK(retiring(s.samples) == 0);
    }

    TEST_CASE("through the density control: a crowding sample fades out and leaves") {
        Sampled s(mesh::icosphere(3));
        const size_t n = s.samples.size();
        s.add_beside(5, 0.3f);
        surface::DensityOptions o;
        surface::DensityControl control(s.rest, s.triangles, o);
        // While nothing changes shape the samples' trigger does not run (it costs nothing), and
        // growing is no reason to look for crowds.
        for (float f : {1.0f, 1.06f})
            for (uint32_t k = 0; k < 2 * o.settle_frames; ++k) {
                s.scale(f);
                REQUIRE(control.update(s.x, s.normals, s.triangles, true, s.h, 3, s.samples).crowded == 0);
            }
        s.scale(0.94f);  // a shrink the triangles' trigger lets pass (density_shrink 0.9), the samples' does not
        uint32_t crowded = 0;
        for (uint32_t f = 0; f < o.settle_frames + o.fade_frames + 1; ++f)
            crowded += control.update(s.x, s.normals, s.triangles, true, s.h, 3, s.samples).crowded;
        CHECK(crowded == 1);
        CHECK(s.samples.size() == n);
        // Switched off, it leaves the crowd alone.
        s.add_beside(5, 0.3f);
        o.crowd_spacing = 0.0f;
        o.gap_spacing = 0.0f;
        surface::DensityControl off(s.rest, s.triangles, o);
        s.scale(1.0f);
        for (uint32_t f = 0; f < 2 * o.settle_frames; ++f) off.update(s.x, s.normals, s.triangles, true, s.h, 3, s.samples);
        CHECK(s.samples.size() == n + 1);
        CHECK(retiring(s.samples) == 0);
    }
}
