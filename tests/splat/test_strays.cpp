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

    TEST_CASE("a crowd does not make the samples of a smoother stretch strays; a dot off the surface still is one") {
        // A plane sampled on a grid at h, most of it crowded four times as densely (a crumpled
        // skin's folds): the median spacing is h / 4, and the stretch's samples lie h apart.
        const float h = 0.1f;
        std::vector<Vec3f> centres;
        for (int i = 0; i < 80; ++i)
            for (int j = 0; j < 80; ++j) centres.emplace_back(0.25f * h * float(i), 0.0f, 0.25f * h * float(j));
        for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 6; ++j) centres.emplace_back(3.0f + h * float(i), 0.0f, h * float(j));
        const splat::StrayReport crowded = splat::count_strays(centres, h);
        CHECK(crowded.median_spacing == doctest::Approx(0.25f * h));
        CHECK(crowded.strays == 0);  // against 3x the median alone, all 36 of the stretch's
        centres.emplace_back(3.2f, 0.5f, 0.2f);  // five spacings above the stretch
        CHECK(splat::count_strays(centres, h).strays == 1);
    }
}
