#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "mesh/procedural.h"
#include "sim/contact.h"
#include "sim/opening.h"
#include "sim/sim_fixtures.h"
#include "splat/cut_faces.h"
#include "support/why.h"
#include "topology/cut.h"
#include "topology/cut_surface.h"

using namespace pbdsplat;

namespace {

// A unit ball cut through its centre by the plane y = 0, its pieces kept closed ("cap") or
// opened ("burst").
sim::SoftBody cut_ball(topology::VolumePolicy policy) {
    sim::SoftBody b = test::make_body(mesh::icosphere(3));
    auto plane = topology::plane_cut(Vec3f::Zero(), Vec3f::UnitY());
    REQUIRE(plane.ok());
    topology::CutOptions options;
    options.volume = policy;
    auto change = topology::cut(b, plane.value(), options);
    REQUIRE_MESSAGE(change.ok(), test::why(change));
    REQUIRE(b.pieces == 2);
    return b;
}

Vec3f position_of(const splat::GaussianRecord& r) { return {r.position[0], r.position[1], r.position[2]}; }

// How many triangles span the faces `faces` draws over `b`'s cap loops.
size_t faces_triangles_total(const splat::CutFaces& faces, const sim::SoftBody& b) {
    size_t n = 0;
    for (const auto& v : b.volumes)
        for (const auto& loop : v.cap_loops)
            if (const auto* tris = faces.triangles_of(loop)) n += tris->size();
    return n;
}

// The faces of `b`'s cut (made just now), sampled at spacing h, without an interior colour.
splat::CutFaces faces_after_cut(const sim::SoftBody& b, float h) {
    splat::CutFaces faces(h, std::nullopt, Vec3f::Ones(), 1);
    faces.cut_made();
    faces.update(b);
    return faces;
}

} // namespace

TEST_SUITE("splat/cut_faces") {
    TEST_CASE("a capped cut through a ball draws both halves' faces: on the plane, covering the disc, facing out of each half") {
        const sim::SoftBody b = cut_ball(topology::VolumePolicy::cap);
        const float h = 0.05f;
        splat::CutFaces faces(h, Vec3f(0.9f, 0.5f, 0.4f), Vec3f::Ones(), 1);
        faces.cut_made();
        faces.update(b);
        CHECK(faces.faces() == 2);
        splat::Appearance look;
        look.scale = 0.5f * h;
        std::vector<splat::GaussianRecord> records;
        faces.append_records(b.particles.x, {}, look, records, nullptr);
        REQUIRE(records.size() == faces.samples());
        // The disc's area over the samples' spacing squared, for each of the two faces, within a
        // factor of two (a maximal sampling at spacing h puts one sample per 1-2 h^2).
        const double disc = M_PI * 1.0 * 1.0, per_face = double(records.size()) / 2.0;
        MESSAGE(records.size() << " samples on two faces");
        CHECK(per_face > 0.4 * disc / double(h * h));  // measured 799 a face: 0.64 of area / h^2
        CHECK(per_face < 1.2 * disc / double(h * h));  // the same
        size_t up = 0, down = 0;
        for (const splat::GaussianRecord& r : records) {
            const Vec3f p = position_of(r);
            CHECK(std::abs(p.y()) < 1e-4f);
            CHECK(std::hypot(p.x(), p.z()) <= 1.0f + 1e-4f);  // on the disc, to rounding
            const Vec3f n = splat::decode_octahedral(r.normal_oct);
            if (n.y() > 0.99f) ++up;
            else if (n.y() < -0.99f) ++down;
            CHECK(r.color[0] == 230);  // the faces' own colour (0.9 of 255)
        }
        CHECK(up + down == records.size());
        CHECK(up > 0);
        CHECK(down > 0);
        // No point of the disc farther than about h from a sample or a rim particle.
        std::vector<Vec3f> points;
        for (const splat::GaussianRecord& r : records) points.push_back(position_of(r));
        for (const Vec4f& x : b.particles.x)
            if (std::abs(x.y()) < 1e-4f) points.push_back(x.head<3>());
        float worst = 0.0f;
        for (float u = -0.9f; u <= 0.9f; u += 0.07f)
            for (float v = -0.9f; v <= 0.9f; v += 0.07f) {
                if (u * u + v * v > 0.8f) continue;
                const Vec3f q(u, 0.0f, v);
                float nearest = INFINITY;
                for (const Vec3f& p : points) nearest = std::min(nearest, (p - q).norm());
                worst = std::max(worst, nearest);
            }
        MESSAGE("farthest point of the disc from a sample: " << worst / h << " h");
        CHECK(worst < 1.5f * h);  // measured 0.78 h
    }

    TEST_CASE("a face a second cut crossed folds along the cut: the quarter's samples lie on its two planes") {
        // The halves cut again by x = 0: each quarter's loop runs over its half's older face
        // (y = 0) and the new one (x = 0). Spanned by the least area over the whole loop, the
        // face cut across the quarter and left its shell open to the eye.
        sim::SoftBody b = cut_ball(topology::VolumePolicy::cap);
        const float h = 0.05f;
        splat::CutFaces faces(h, Vec3f(0.9f, 0.5f, 0.4f), Vec3f::Ones(), 1);
        faces.cut_made();
        faces.update(b);
        auto second = topology::plane_cut(Vec3f(0.0f, 0.5f, 0.0f), Vec3f::UnitX());
        REQUIRE(second.ok());
        topology::CutOptions options;
        options.volume = topology::VolumePolicy::cap;
        auto change = topology::cut(b, second.value(), options);
        REQUIRE_MESSAGE(change.ok(), test::why(change));
        REQUIRE(b.pieces == 4);
        faces.cut_made();
        faces.update(b);
        CHECK(faces.faces() == 4);  // one folded face per quarter
        splat::Appearance look;
        look.scale = 0.5f * h;
        std::vector<splat::GaussianRecord> records;
        faces.append_records(b.particles.x, {}, look, records, nullptr);
        size_t on_x = 0;
        for (const splat::GaussianRecord& r : records) {
            const Vec3f p = position_of(r);
            const bool on_a_plane = std::abs(p.y()) < 1e-3f || std::abs(p.x()) < 1e-3f;
            CHECK_MESSAGE(on_a_plane, "a sample off both cut planes at " << p.transpose());
            on_x += std::abs(p.x()) < 1e-3f && std::abs(p.y()) > 1e-3f;
        }
        // Lit as its two planes: the fold is a crease, not averaged across.
        size_t off_plane_normal = 0;
        for (const splat::GaussianRecord& r : records) {
            const Vec3f p = position_of(r), n = splat::decode_octahedral(r.normal_oct);
            // (0.999: the octahedral code's rounding, under 0.1 degree; on the chord, either plane's)
            const bool lit_as_its_plane = (std::abs(p.x()) < 1e-3f && std::abs(n.x()) > 0.999f) || (std::abs(p.y()) < 1e-3f && std::abs(n.y()) > 0.999f);
            off_plane_normal += lit_as_its_plane ? 0 : 1;
        }
        CHECK(off_plane_normal == 0);
        // The new cut's faces (a half disc of radius 1 on each quarter) are sampled like the
        // older one: within a factor of two of their area over h^2.
        const double half_discs = 4.0 * 0.5 * M_PI;
        MESSAGE(on_x << " samples on the second cut's plane");
        CHECK(double(on_x) > 0.4 * half_discs / double(h * h));  // measured 1572: 0.63 of area / h^2
    }

    TEST_CASE("a face whose rim has warped since the cut is lit smoothly, not as the facets that span it") {
        sim::SoftBody b = cut_ball(topology::VolumePolicy::cap);
        const float h = 0.05f;
        splat::CutFaces faces = faces_after_cut(b, h);
        // The rim (the particles on the cut plane) waved up and down: the triangles that span
        // the face, laid on the flat loop, now lie at different angles.
        for (Vec4f& x : b.particles.x)
            if (std::abs(x.y()) < 1e-4f) x.y() += 0.06f * std::sin(3.0f * std::atan2(x.z(), x.x()));
        faces.update(b);
        splat::Appearance look;
        look.scale = 0.5f * h;
        std::vector<splat::GaussianRecord> records;
        faces.append_records(b.particles.x, {}, look, records, nullptr);
        REQUIRE(records.size() == faces.samples());
        // The largest turn between neighbouring samples' normals, against the largest between
        // the spanning triangles that share an edge (what lighting each by its own showed).
        float sample_turn = 0.0f;
        for (size_t i = 0; i < records.size(); ++i)
            for (size_t k = i + 1; k < records.size(); ++k) {
                if ((position_of(records[i]) - position_of(records[k])).norm() > 1.5f * h) continue;
                const Vec3f a = splat::decode_octahedral(records[i].normal_oct), c = splat::decode_octahedral(records[k].normal_oct);
                if (a.dot(c) < 0.0f) continue;  // the other half's face
                sample_turn = std::max(sample_turn, std::acos(std::clamp(a.dot(c), -1.0f, 1.0f)));
            }
        float facet_turn = 0.0f;
        for (const auto& v : b.volumes)
            for (const auto& loop : v.cap_loops) {
                const auto* tris = faces.triangles_of(loop);
                if (!tris) continue;
                const auto normal = [&](const mesh::Triangle& t) {
                    const Vec3f p0 = b.particles.x[t[0]].head<3>();
                    return Vec3f((b.particles.x[t[1]].head<3>() - p0).cross(b.particles.x[t[2]].head<3>() - p0).normalized());
                };
                for (const mesh::Triangle& t : *tris)
                    for (const mesh::Triangle& u : *tris) {
                        int shared = 0;
                        for (uint32_t i : t) shared += std::count(u.begin(), u.end(), i) > 0 ? 1 : 0;
                        if (shared == 2) facet_turn = std::max(facet_turn, std::acos(std::clamp(normal(t).dot(normal(u)), -1.0f, 1.0f)));
                    }
            }
        MESSAGE("largest turn between neighbouring samples " << sample_turn * 57.3f << " degrees, between facets " << facet_turn * 57.3f);
        CHECK(facet_turn > 0.35f);  // the facets turn sharply (measured 29.7 degrees) ...
        // ... the lighting by half as much between neighbours (measured 16.3 degrees, 0.55 of the
        // facets' turn; lit by each triangle's own normal, 33.2: 1.12)
        CHECK(sample_turn < 0.7f * facet_turn);
        // As a surface (the checks' lit mesh), each face's triangles share one corner per rim
        // particle, so the raster's vertex normals are smooth across it as the splats are.
        std::vector<Vec4f> corners;
        std::vector<mesh::Triangle> triangles;
        faces.append_surface(b.particles.x, corners, triangles);
        size_t rim = 0;
        for (const auto& v : b.volumes)
            for (const auto& loop : v.cap_loops) rim += faces.triangles_of(loop) ? loop.size() : 0;
        CHECK(corners.size() == rim);
        CHECK(triangles.size() == faces_triangles_total(faces, b));
        for (const mesh::Triangle& t : triangles)
            for (uint32_t c : t) CHECK(c < corners.size());
    }

    TEST_CASE("the faces ride on their rims: moved with the body, stretched splats grow") {
        sim::SoftBody b = cut_ball(topology::VolumePolicy::cap);
        const float h = 0.05f;
        splat::CutFaces faces = faces_after_cut(b, h);
        splat::Appearance look;
        look.scale = 0.5f * h;
        std::vector<splat::GaussianRecord> before, after;
        faces.append_records(b.particles.x, {}, look, before, nullptr);
        // The whole body moved up by 2 and stretched twice as wide along x and z.
        for (Vec4f& x : b.particles.x) x = Vec4f(2.0f * x.x(), x.y() + 2.0f, 2.0f * x.z(), x.w());
        faces.update(b);
        faces.append_records(b.particles.x, {}, look, after, nullptr);
        REQUIRE(after.size() == before.size());
        for (size_t k = 0; k < after.size(); ++k) {
            const Vec3f p = position_of(before[k]), q = position_of(after[k]);
            CHECK(q.isApprox(Vec3f(2.0f * p.x(), p.y() + 2.0f, 2.0f * p.z()), 1e-4f));
            CHECK(splat::half_to_float(after[k].scale_half) == doctest::Approx(2.0f * look.scale).epsilon(0.01));
        }
    }

    TEST_CASE("without an interior colour a face takes its rim's colour") {
        sim::SoftBody b = cut_ball(topology::VolumePolicy::cap);
        b.colors.assign(b.particle_count(), Vec3f(0.2f, 0.4f, 0.6f));
        splat::CutFaces faces(0.1f, std::nullopt, Vec3f::Ones(), 1);
        faces.cut_made();
        faces.update(b);
        std::vector<splat::GaussianRecord> records;
        faces.append_records(b.particles.x, b.colors, {}, records, nullptr);
        REQUIRE(!records.empty());
        for (const splat::GaussianRecord& r : records) {
            CHECK(r.color[0] == 51);
            CHECK(r.color[1] == 102);
            CHECK(r.color[2] == 153);
        }
    }

    TEST_CASE("a burst's openings and a tear's are not faces, and a face goes with its loop") {
        const sim::SoftBody burst = cut_ball(topology::VolumePolicy::burst);
        splat::CutFaces faces(0.05f, std::nullopt, Vec3f::Ones(), 1);
        faces.cut_made();
        faces.update(burst);
        CHECK(faces.faces() == 0);
        const sim::SoftBody capped = cut_ball(topology::VolumePolicy::cap);
        faces.cut_made();
        faces.update(capped);
        CHECK(faces.faces() == 2);
        // Loops that appear without a cut (a tear's openings) stay open, however fat.
        splat::CutFaces torn(0.05f, std::nullopt, Vec3f::Ones(), 1);
        torn.update(capped);
        CHECK(torn.faces() == 0);
        sim::SoftBody whole = test::make_body(mesh::icosphere(3));
        faces.update(whole);
        CHECK(faces.faces() == 0);
        CHECK(faces.samples() == 0);
    }

    TEST_CASE("a loop encloses a face unless it is a slit: a thin slice is a face; a loop that runs up and down encloses its spanning area") {
        const auto loop_of = [](const std::vector<Vec3f>& corners, std::vector<uint32_t>& loop, sim::Vec4Array& x) {
            loop.clear(), x.clear();
            for (uint32_t k = 0; k < corners.size(); ++k) loop.push_back(k), x.push_back(Vec4f(corners[k].x(), corners[k].y(), corners[k].z(), 1.0f));
            return corners;
        };
        std::vector<uint32_t> loop;
        sim::Vec4Array x;
        std::vector<Vec3f> rest = loop_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, loop, x);
        CHECK(sim::encloses_face(loop, x, rest));
        // A saddle: round a unit square, its edges' midpoints raised and lowered by 1 in turn (what
        // a second cut across a first cut's face leaves, bent over both). Its projected area over
        // its perimeter squared is 0.0125, below a face's 0.02; the least area spanning it, 0.0375.
        rest = loop_of({{0, 0, 0}, {0.5f, 0, 1}, {1, 0, 0}, {1, 0.5f, -1}, {1, 1, 0}, {0.5f, 1, 1}, {0, 1, 0}, {0, 0.5f, -1}}, loop, x);
        CHECK(sim::encloses_face(loop, x, rest));
        // A slit: out and back along one line, its two sides at the same rest places (a tear's).
        rest = loop_of({{0, 0, 0}, {0.5f, 0, 0}, {1, 0, 0}, {0.5f, 0, 0}}, loop, x);
        CHECK_FALSE(sim::encloses_face(loop, x, rest));
        // A thin slice a later cut takes off a piece's edge, 20 times as long as it is wide
        // (least area over perimeter squared 0.011), is a face; one as thin as a cut's rounding
        // (10,000 to 1: 2.5e-5) is a slit.
        rest = loop_of({{0, 0, 0}, {0.5f, 0, 0}, {1, 0, 0}, {1, 0.05f, 0}, {0.5f, 0.05f, 0}, {0, 0.05f, 0}}, loop, x);
        CHECK(sim::encloses_face(loop, x, rest));
        rest = loop_of({{0, 0, 0}, {0.5f, 0, 0}, {1, 0, 0}, {1, 1e-4f, 0}, {0.5f, 1e-4f, 0}, {0, 1e-4f, 0}}, loop, x);
        CHECK_FALSE(sim::encloses_face(loop, x, rest));
    }
}

TEST_SUITE("splat/cut_faces") {
    TEST_CASE("a body's enclosed volume closes each cut loop by its drawn face: a ball cut in quarters keeps its volume") {
        // Off the origin, so that a face's share of the volume is not zero.
        mesh::TriangleMesh m = mesh::icosphere(3);
        for (Vec3f& p : m.positions) p += Vec3f(0.3f, 0.2f, 0.1f);
        sim::SoftBody b = test::make_body(std::move(m));
        const double whole = sim::opening_report(b).volume;
        splat::CutFaces faces(0.05f, std::nullopt, Vec3f::Ones(), 1);
        const auto drawn = [&faces](const std::vector<uint32_t>& loop) { return faces.triangles_of(loop); };
        for (const Vec3f& normal : {Vec3f(1, 0, 0), Vec3f(0, 0, 1)}) {
            auto plane = topology::plane_cut(Vec3f(0.3f, 0.2f, 0.1f), normal);
            REQUIRE(plane.ok());
            REQUIRE(topology::cut(b, plane.value(), topology::CutOptions{}).ok());
            faces.cut_made();
            faces.update(b);
            // One cut: a planar face, which a fan closes as well.
            if (b.pieces == 2) CHECK(sim::opening_report(b, drawn).volume == doctest::Approx(sim::opening_report(b).volume).epsilon(1e-6));
        }
        REQUIRE(b.pieces == 4);
        const double fanned = sim::opening_report(b).volume / whole, faced = sim::opening_report(b, drawn).volume / whole;
        MESSAGE("quarters' volume over the ball's: fans " << fanned << ", drawn faces " << faced);
        CHECK(faced == doctest::Approx(1.0).epsilon(1e-4));  // the faces are the cut planes' exactly
        CHECK(std::abs(fanned - 1.0) > 0.1);                  // measured 1.32: a fan across a fold is no face
    }
}
