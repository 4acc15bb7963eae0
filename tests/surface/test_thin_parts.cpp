#include <doctest/doctest.h>

#include <array>
#include <cmath>

#include "mesh/procedural.h"
#include "surface/boundary_particles.h"
#include "surface/thin_parts.h"

using namespace pbdsplat;

namespace {
// Samples on each of a +-x-long rod's four long faces (+y, -y, +z, -z), by their triangle's
// flat normal: the faces a view from each side sees.
std::array<size_t, 4> samples_on_long_faces(const mesh::TriangleMesh& m, const surface::BoundaryParticles& s) {
    std::array<size_t, 4> count{};
    for (size_t i = 0; i < s.size(); ++i) {
        const mesh::Triangle& t = m.triangles[s.triangle[i]];
        const Vec3f n = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).normalized();
        if (n.y() > 0.9f) ++count[0];
        if (n.y() < -0.9f) ++count[1];
        if (n.z() > 0.9f) ++count[2];
        if (n.z() < -0.9f) ++count[3];
    }
    return count;
}
} // namespace

TEST_SUITE("surface/thin_parts") {
    TEST_CASE("mean thickness 4V/A: a rod's diameter, a square post's side") {
        const float r = 0.1f, L = 2.0f;
        CHECK(surface::mean_thickness(M_PI * r * r * L, 2.0 * M_PI * r * L) == doctest::Approx(2.0f * r));
        const float a = 0.03f;
        CHECK(surface::mean_thickness(a * a * L, 4.0 * a * L) == doctest::Approx(a));
        CHECK(surface::mean_thickness(1.0, 0.0) == 0.0f);
    }

    TEST_CASE("a rod 2 cm thick, one box of 12 triangles, is sampled on every long face") {
        const mesh::TriangleMesh rod = mesh::box(Vec3f(1.0f, 0.02f, 0.02f), 1);
        const float thin = surface::spacing_for_thin_parts(rod);
        // V = 0.0004, A = 0.0808: 4 V / A = 0.0198.
        CHECK(thin == doctest::Approx(surface::k_spacing_over_thickness * 4.0f * 0.0004f / 0.0808f).epsilon(0.01));
        CHECK(std::isinf(surface::spacing_for_thin_parts(rod, 0.5f * thin)));  // asks for no less than given
        CHECK(surface::spacing_for_thin_parts(rod, 2.0f * thin) == thin);
        const float by_edge = surface::spacing(rod, 0.5f);
        REQUIRE(by_edge > 10.0f * thin);  // its edges are a metre long
        const auto coarse = samples_on_long_faces(rod, surface::sample_surface(rod, {by_edge, 1}));
        const auto fine = samples_on_long_faces(rod, surface::sample_surface(rod, {thin, 1}));
        MESSAGE("samples on the long faces at eta x edge " << coarse[0] << " " << coarse[1] << " " << coarse[2] << " " << coarse[3]
                << ", at the thin part's spacing " << fine[0] << " " << fine[1] << " " << fine[2] << " " << fine[3]);
        // At the edge's spacing a sample blocks the rod across: some face is left bare.
        CHECK(*std::min_element(coarse.begin(), coarse.end()) == 0);
        // A metre of face 2 cm wide at spacing 7 mm: about 260 samples; each face is covered.
        for (size_t c : fine) CHECK(c > 60);
    }

    TEST_CASE("open surfaces and small parts leave the spacing to the edge") {
        CHECK(std::isinf(surface::spacing_for_thin_parts(mesh::grid_sheet(8, 1.0f))));
        // A ball of radius 1 with a pin 1 cm thick beside it, far under 1 % of the area.
        mesh::TriangleMesh m = mesh::icosphere(3, 1.0f);
        mesh::append(m, mesh::box(Vec3f(0.1f, 0.01f, 0.01f), 1), Eigen::Affine3f(Eigen::Translation3f(3.0f, 0.0f, 0.0f)));
        const float h = surface::spacing_for_thin_parts(m);
        CHECK(h == doctest::Approx(surface::k_spacing_over_thickness * 4.0f / 3.0f).epsilon(0.05));  // the ball's 4 r / 3
        // A rod as thin, long enough to hold 3 % of the area, sets the spacing.
        mesh::append(m, mesh::box(Vec3f(10.0f, 0.01f, 0.01f), 1), Eigen::Affine3f(Eigen::Translation3f(0.0f, 5.0f, 0.0f)));
        CHECK(surface::spacing_for_thin_parts(m) == doctest::Approx(surface::k_spacing_over_thickness * 0.01f).epsilon(0.01));
    }
}
