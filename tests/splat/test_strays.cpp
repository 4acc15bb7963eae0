#include <doctest/doctest.h>

#include "mesh/procedural.h"
#include "splat/strays.h"
#include "surface/boundary_particles.h"

using namespace pbdsplat;

TEST_SUITE("splat/strays") {
    TEST_CASE("a sampled surface has no strays; one splat placed far away is one") {
        const mesh::TriangleMesh m = mesh::icosphere(4);
        const float h = surface::spacing(m, 0.5f);
        const surface::BoundaryParticles s = surface::sample_surface(m, {h, 1});
        std::vector<Vec3f> centres = m.positions;
        centres.insert(centres.end(), s.position.begin(), s.position.end());
        CHECK(splat::count_strays(centres, h).strays == 0);
        centres.push_back(Vec3f(0.0f, 1.5f, 0.0f));  // floats half a unit above the sphere
        const splat::StrayReport r = splat::count_strays(centres, h);
        CHECK(r.strays == 1);
        CHECK(r.median_spacing > 0.5f * h);  // a maximal sampling at h: its nearest neighbours lie 1-2 h apart
        CHECK(r.median_spacing < 2.0f * h);  // the same
    }
}
