#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <string>

#include "mesh/procedural.h"
#include "sim/soft_body.h"
#include "surface/density.h"
#include "surface/spacing_report.h"

using namespace pbdsplat;

namespace {

// A sphere whose particles are scaled about its centre: a uniform stretch of every triangle.
struct Balloon {
    sim::SoftBody body;
    float h = 0.0f;
    surface::BoundaryParticles samples;
    surface::DensityControl density;

    Balloon() {
        auto b = sim::make_soft_body(mesh::icosphere(3), {});
        REQUIRE(b.ok());
        body = std::move(b).value();
        const mesh::TriangleMesh rest{body.rest_positions, body.triangles, {}, {}, {}};
        h = surface::spacing(rest, 0.5f);
        samples = surface::sample_surface(rest, {h, 7});
        density = surface::DensityControl(body.rest_positions, body.triangles, {});
        scale(1.0f);
    }
    void scale(float s) { scale_axes(Vec3f::Constant(s)); }
    // Per axis: a squash stretches no triangle but compresses the equator's along the axis.
    void scale_axes(const Vec3f& s) {
        for (size_t i = 0; i < body.particle_count(); ++i) {
            const Vec3f& r = body.rest_positions[i];
            body.particles.x[i] = Vec4f(s.x() * r.x(), s.y() * r.y(), s.z() * r.z(), 0.0f);
        }
        surface::update_boundary_particles(body.triangles, body.particles.x, body.normals, samples);
    }
    surface::DensityStats frame() { return density.update(body.particles.x, body.normals, body.triangles, true, h, 3, samples); }
    // Every splat: the samples and the particles (the vertices are drawn too).
    std::vector<Vec3f> splats() const {
        std::vector<Vec3f> out = samples.position;
        for (const Vec4f& x : body.particles.x) out.push_back(x.head<3>());
        return out;
    }
    // The largest distance from a random point of the deformed surface to its nearest splat.
    float largest_gap(uint32_t points = 4000) const {
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        const std::vector<Vec3f> s = splats();
        float worst = 0.0f;
        for (uint32_t k = 0; k < points; ++k) {
            const auto& t = body.triangles[rng() % body.triangles.size()];
            float a = u(rng), b = u(rng);
            if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
            const Vec3f p = ((1.0f - a - b) * body.particles.x[t[0]] + a * body.particles.x[t[1]] + b * body.particles.x[t[2]]).head<3>();
            float best = 1e30f;
            for (const Vec3f& q : s) best = std::min(best, (q - p).norm());
            worst = std::max(worst, best);
        }
        return worst;
    }
};

bool on_their_triangles(const surface::BoundaryParticles& s) {
    for (size_t i = 0; i < s.size(); ++i) {
        const Vec2f b = s.bary[i];
        if (!(b.x() >= -1e-6f && b.y() >= -1e-6f && b.x() + b.y() <= 1.0f + 1e-6f)) return false;
    }
    return true;
}

} // namespace

TEST_SUITE("surface/density") {
    TEST_CASE("inflating a sphere to twice its area keeps the spacing and closes every gap") {
        Balloon b;
        const size_t at_rest = b.samples.size();
        const float stretch = std::sqrt(2.0f);
        for (int f = 1; f <= 30; ++f) {
            b.scale(1.0f + (stretch - 1.0f) * float(std::min(f, 20)) / 20.0f);
            b.frame();
            // Throughout, not only at the end: the control keeps pace with the inflation.
            const surface::SpacingReport r = surface::spacing_report(b.splats(), b.h);
            CHECK_MESSAGE(r.within >= 0.95f, "frame " << f << ": " << r.within << " within [0.7 h, 1.4 h], p05 " << r.p05 << ", p95 " << r.p95);  // the surfaces goal: 95 % of samples in band
        }
        CHECK(b.samples.size() > at_rest + at_rest / 2);  // twice the area: far more samples
        CHECK(on_their_triangles(b.samples));
        // Maximal: no point of the inflated surface is farther than about h from a splat.
        CHECK(b.largest_gap() < 1.05f * b.h);
        // The new samples have faded in.
        for (size_t i = 0; i < b.samples.size(); ++i) REQUIRE(b.samples.fade_of(i) == 1.0f);
    }

    TEST_CASE("deflating retires samples without opening gaps") {
        Balloon b;
        const float stretch = std::sqrt(2.0f);
        for (int f = 1; f <= 30; ++f) {
            b.scale(1.0f + (stretch - 1.0f) * float(std::min(f, 20)) / 20.0f);
            b.frame();
        }
        const size_t inflated = b.samples.size();
        float worst_gap = 0.0f;
        for (int f = 1; f <= 40; ++f) {
            b.scale(stretch - (stretch - 1.0f) * float(std::min(f, 20)) / 20.0f);
            b.frame();
            if (f % 5 == 0) worst_gap = std::max(worst_gap, b.largest_gap(1500));
        }
        CHECK(b.samples.size() < inflated * 3 / 4);
        const surface::SpacingReport r = surface::spacing_report(b.splats(), b.h);
        CHECK_MESSAGE(r.within >= 0.95f, r.within << " within [0.7 h, 1.4 h], p05 " << r.p05 << ", p95 " << r.p95);  // the surfaces goal
        // Retired samples leave only where a kept one stands close by.
        CHECK(worst_gap < 1.2f * b.h);
        CHECK(on_their_triangles(b.samples));
    }

    TEST_CASE("a squash one way thins the crowded samples, and springing back fills the gaps") {
        Balloon b;
        const size_t at_rest = b.samples.size();
        auto squash = [](float f) { return Vec3f(1.0f, f, 1.0f); };
        for (int f = 1; f <= 30; ++f) {
            b.scale_axes(squash(1.0f - 0.4f * float(std::min(f, 20)) / 20.0f));  // to 0.6 of its height
            b.frame();
        }
        // The largest stretch never moved; the samples crowded along the squashed direction.
        const surface::SpacingReport squashed = surface::spacing_report(b.splats(), b.h);
        CHECK_MESSAGE(squashed.within >= 0.95f, squashed.within << " within [0.7 h, 1.4 h], p05 " << squashed.p05);  // the surfaces goal
        CHECK(b.samples.size() < at_rest);
        for (int f = 1; f <= 30; ++f) {
            b.scale_axes(squash(0.6f + 0.4f * float(std::min(f, 20)) / 20.0f));
            b.frame();
        }
        const surface::SpacingReport back = surface::spacing_report(b.splats(), b.h);
        CHECK_MESSAGE(back.within >= 0.95f, back.within << " within [0.7 h, 1.4 h], p95 " << back.p95);  // the surfaces goal
        CHECK(b.largest_gap() < 1.05f * b.h);  // a maximal set leaves no gap past h; 5 % for the facets
        CHECK(on_their_triangles(b.samples));
    }

    TEST_CASE("between the thresholds nothing changes: no flicker") {
        Balloon b;
        const size_t n = b.samples.size();
        for (int f = 0; f < 60; ++f) {
            b.scale(1.0f + 0.04f * std::sin(0.3f * float(f)));  // breathing by 4 %
            const surface::DensityStats s = b.frame();
            REQUIRE(s.inserted == 0);
            REQUIRE(s.retired == 0);
        }
        CHECK(b.samples.size() == n);
    }

    TEST_CASE("the per-frame budget spreads a sudden inflation over frames") {
        Balloon b;
        surface::DensityOptions o;
        o.budget = 64;
        b.density = surface::DensityControl(b.body.rest_positions, b.body.triangles, o);
        b.scale(1.5f);
        // It waits for the stretch to last (settle_frames), then works through the budget.
        for (uint32_t f = 1; f < o.settle_frames; ++f) REQUIRE(b.frame().resampled == 0);
        const surface::DensityStats first = b.frame();
        CHECK(first.resampled == 64);
        CHECK(first.pending == b.body.triangles.size() - 64);
        uint32_t frames = 1;
        while (b.frame().pending > 0 && frames < 100) ++frames;
        CHECK(frames == (b.body.triangles.size() + 63) / 64 - 1);
    }

    TEST_CASE("a triangle's splats grow with its stretch past the refill threshold, and back to 1 once refilled") {
        Balloon b;
        const float grow = surface::DensityOptions{}.grow;
        b.frame();
        for (float g : b.samples.triangle_growth) REQUIRE(g == doctest::Approx(1.0f).epsilon(1e-5));  // at rest
        // Within the threshold the set still closes: the splats keep their size.
        b.scale(1.05f);
        b.frame();
        for (float g : b.samples.triangle_growth) REQUIRE(g == doctest::Approx(1.0f).epsilon(1e-5));
        // Inflated by 1.3 at once: before the settle frames run out nothing is resampled, and
        // every triangle's splats grow by the stretch past the threshold.
        b.scale(1.3f);
        b.frame();
        REQUIRE(b.samples.triangle_growth.size() == b.body.triangles.size());
        for (float g : b.samples.triangle_growth) REQUIRE(g == doctest::Approx(1.3f / grow).epsilon(1e-3));
        // Refilled, each starts again from its new samples (the budget spreads the work).
        for (int f = 0; f < 30; ++f) b.frame();
        for (float g : b.samples.triangle_growth) CHECK(g == doctest::Approx(1.0f).epsilon(1e-5));
        // Shrinking never shrinks a splat below its size; a stretch past twice the threshold stops at 2.
        b.scale(1.0f);
        b.frame();
        for (float g : b.samples.triangle_growth) CHECK(g == doctest::Approx(1.0f).epsilon(1e-5));
        b.scale(3.5f);
        b.frame();
        for (float g : b.samples.triangle_growth) CHECK(g == doctest::Approx(2.0f));
    }

    TEST_CASE("with the control off, the samples and their splats stay as they are") {
        Balloon b;
        surface::DensityOptions o;
        o.enabled = false;
        b.density = surface::DensityControl(b.body.rest_positions, b.body.triangles, o);
        b.scale(1.4f);
        for (int f = 0; f < 10; ++f) CHECK(b.frame().inserted == 0);
        for (size_t t = 0; t < b.body.triangles.size(); ++t) CHECK(b.samples.growth_of(uint32_t(t)) == 1.0f);
    }

    TEST_CASE("fades ramp monotonically in and out, and a faded-out sample leaves") {
        Balloon b;
        const size_t n = b.samples.size();
        surface::fade_in(b.samples, n - 3, 4);
        b.samples.fade_step[0] = -0.25f;  // retiring
        std::vector<float> last(b.samples.size(), 0.0f);
        last[0] = 1.0f;
        for (int f = 0; f < 4; ++f) {
            uint32_t fading = 0;
            const size_t removed = surface::advance_fades(b.samples, &fading);
            if (f < 3) {
                CHECK(removed == 0);
                CHECK(b.samples.fade[0] < last[0]);
                last[0] = b.samples.fade[0];
                for (size_t i = n - 3; i < n; ++i) {
                    CHECK(b.samples.fade[i] > last[i]);
                    last[i] = b.samples.fade[i];
                }
            } else {
                CHECK(removed == 1);
                CHECK(fading == 0);
            }
        }
        CHECK(b.samples.size() == n - 1);
        for (size_t i = 0; i < b.samples.size(); ++i) CHECK(b.samples.fade_of(i) == 1.0f);
    }

    TEST_CASE("the spacing report measures the first points only, against all of them") {
        // A row one h apart (all within the band), then two points crowding its ends.
        std::vector<Vec3f> p;
        for (int i = 0; i < 8; ++i) p.emplace_back(float(i), 0.0f, 0.0f);
        p.emplace_back(0.0f, 0.5f, 0.0f);
        p.emplace_back(7.0f, 0.5f, 0.0f);
        const surface::SpacingReport head = surface::spacing_report(std::span(p).first(8), 1.0f);
        CHECK(head.points == 8);
        CHECK(head.within == 1.0f);
        // Measured against the neighbours: the row's two ends now have one 0.5 h away.
        const surface::SpacingReport row = surface::spacing_report(p, 1.0f, {0.7f, 1.4f, 8, {}});
        CHECK(row.points == 8);
        CHECK(row.within == doctest::Approx(6.0 / 8.0));
        CHECK(row.p05 == doctest::Approx(0.5f));
        // Every point measured: the two crowding points count too.
        CHECK(surface::spacing_report(p, 1.0f).within == doctest::Approx(6.0 / 10.0));
    }

    TEST_CASE("with normals, the far face of a fold is no neighbour") {
        // Two rows h apart, folded flat onto each other 0.3 h apart: facing opposite ways.
        std::vector<Vec3f> p, n;
        for (int i = 0; i < 8; ++i) p.emplace_back(float(i), 0.0f, 0.0f), n.emplace_back(0.0f, 1.0f, 0.0f);
        for (int i = 0; i < 8; ++i) p.emplace_back(float(i), 0.3f, 0.0f), n.emplace_back(0.0f, -1.0f, 0.0f);
        // In space every point has the other sheet 0.3 h away.
        CHECK(surface::spacing_report(p, 1.0f).within == 0.0f);
        // Along the surface each row is one h apart.
        const surface::SpacingReport folded = surface::spacing_report(p, 1.0f, {0.7f, 1.4f, SIZE_MAX, n});
        CHECK(folded.within == 1.0f);
        CHECK(folded.p05 == doctest::Approx(1.0f));
        // Facing the same way (a second layer, not a fold), the close sheet still counts.
        std::vector<Vec3f> same(p.size(), Vec3f(0.0f, 1.0f, 0.0f));
        CHECK(surface::spacing_report(p, 1.0f, {0.7f, 1.4f, SIZE_MAX, same}).within == 0.0f);
    }
}

TEST_SUITE("surface/density") {
    TEST_CASE("a check of the samples that finds nothing doubles the wait for the next, up to four settle periods") {
        Balloon b;
        const surface::DensityOptions o;
        std::vector<int> checks;
        std::vector<uint32_t> found;
        // An even, slow inflation: the triangles' own trigger keeps up, and the samples' checks
        // (called by every 5 % of change) find no gap and no crowd.
        for (int f = 1; f <= 120; ++f) {
            b.scale(1.0f + 0.004f * float(f));
            const surface::DensityStats s = b.frame();
            if (s.checked) checks.push_back(f), found.push_back(s.crowded + s.gaps);
        }
        REQUIRE(checks.size() >= 4);
        for (size_t k = 0; k < checks.size(); ++k) CHECK_MESSAGE(found[k] == 0, "check at frame " << checks[k] << " found " << found[k]);
        const int settle = int(o.settle_frames);
        // A check also waits for a change of 5 %, so the gaps are at least the waits.
        std::string at;
        for (int c : checks) at += " " + std::to_string(c);
        INFO("checks at frames" << at);
        CHECK(checks[1] - checks[0] >= 2 * settle);
        for (size_t k = 2; k < checks.size(); ++k) CHECK(checks[k] - checks[k - 1] >= 4 * settle);
        // And no longer than needed: the 5 % come within a few frames here.
        CHECK(checks.back() - checks[checks.size() - 2] < 6 * settle);
        // A changed topology brings the short wait back: the next check comes as soon as the
        // settle frames since the last have passed.
        int last = checks.back(), f = 120;
        while (f < last + settle) b.scale(1.0f + 0.004f * float(++f)), b.frame();
        b.density.topology_changed(b.body.rest_positions, b.body.triangles, {});
        b.scale(1.0f + 0.004f * float(++f));
        CHECK(b.frame().checked);
    }
}
