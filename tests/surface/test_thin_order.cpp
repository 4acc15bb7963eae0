#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "surface/thin_order.h"

using namespace pbdsplat;

namespace {
float radius(float h, int level) { return h * std::exp2(0.5f * float(level)); }

// Dart throwing on the unit square at spacing h: the kind of set the samplers make.
std::vector<Vec3f> poisson_square(float h, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Vec3f> out;
    for (int k = 0; k < 60000; ++k) {
        const Vec3f p(u(rng), u(rng), 0.0f);
        bool free = true;
        for (const Vec3f& q : out)
            if ((q - p).squaredNorm() < h * h) {
                free = false;
                break;
            }
        if (free) out.push_back(p);
    }
    return out;
}

// For each level: the samples at it or above lie at least its radius apart (of one tag), and
// every sample (of that tag) has one within the radius: any prefix of the order covers evenly.
void check_levels(const std::vector<Vec3f>& p, const std::vector<uint32_t>& tag, const std::vector<uint8_t>& level, float h) {
    REQUIRE(level.size() == p.size());
    for (int l = 1; l <= surface::k_thin_levels; ++l) {
        const float r = radius(h, l);
        size_t kept = 0, apart = 0, covered = 0;
        for (size_t i = 0; i < p.size(); ++i) {
            bool near_kept = false;
            for (size_t j = 0; j < p.size(); ++j) {
                if (j == i || (!tag.empty() && tag[j] != tag[i]) || level[j] < l) continue;
                if ((p[j] - p[i]).norm() < r) {
                    near_kept = true;
                    if (level[i] >= l) ++apart;  // two kept ones too close
                }
            }
            if (level[i] >= l) ++kept;
            if (level[i] >= l || near_kept) ++covered;
        }
        CHECK_MESSAGE(apart == 0, "level " << l);
        CHECK_MESSAGE(covered == p.size(), "level " << l);
        if (l == 1) CHECK(kept < p.size());
    }
}
} // namespace

TEST_SUITE("surface/thin_order") {
    TEST_CASE("every level of the order is a maximal Poisson-disc set, each about half the one below") {
        const float h = 0.03f;
        const std::vector<Vec3f> p = poisson_square(h, 7);
        const std::vector<Vec3f> up(p.size(), Vec3f::UnitZ());
        std::vector<uint8_t> level;
        surface::place_in_thin_order(p, up, {}, h, level);
        check_levels(p, {}, level, h);
        // Each level holds about half as many per area as the one below (radius x sqrt 2).
        std::vector<size_t> at_least(surface::k_thin_levels + 1, 0);
        for (uint8_t l : level)
            for (int k = 0; k <= int(l); ++k) ++at_least[size_t(k)];
        for (int l = 1; l <= 3; ++l) {
            const double ratio = double(at_least[size_t(l)]) / double(at_least[size_t(l - 1)]);
            CHECK_MESSAGE(ratio > 0.35, "level " << l << ": " << ratio);  // each level half the one below: 0.5, within what a Poisson-disc thinning gives
            CHECK_MESSAGE(ratio < 0.7, "level " << l << ": " << ratio);  // the same
        }
    }

    TEST_CASE("two pieces lying on each other, and the two faces of a thin part, each keep their own order") {
        const float h = 0.03f;
        const std::vector<Vec3f> a = poisson_square(h, 3);
        std::vector<Vec3f> p = a, n(a.size(), Vec3f::UnitZ());
        std::vector<uint32_t> tag(a.size(), 0u);
        // The same points again: as another piece, then as the far face (normal turned over).
        for (const Vec3f& q : a) p.push_back(q), n.push_back(Vec3f::UnitZ()), tag.push_back(1u);
        for (const Vec3f& q : a) p.push_back(q + Vec3f(0.0f, 0.0f, 0.1f * h)), n.push_back(-Vec3f::UnitZ()), tag.push_back(0u);
        std::vector<uint8_t> level;
        surface::place_in_thin_order(p, n, tag, h, level);
        // Split by what may block what: each set on its own is a maximal set at every level.
        for (int set = 0; set < 3; ++set) {
            const std::vector<Vec3f> part(p.begin() + long(set * a.size()), p.begin() + long((set + 1) * a.size()));
            const std::vector<uint8_t> lv(level.begin() + long(set * a.size()), level.begin() + long((set + 1) * a.size()));
            check_levels(part, {}, lv, h);
        }
    }

    TEST_CASE("new samples join the order, remade around them, and the gaps removed ones left are filled") {
        const float h = 0.03f;
        std::vector<Vec3f> p = poisson_square(h, 11);
        const std::vector<Vec3f> up(p.size(), Vec3f::UnitZ());
        std::vector<uint8_t> level;
        surface::place_in_thin_order(p, up, {}, h, level);
        // The samples of the coarsest three levels near (0.25, 0.6) removed, as retired ones are,
        // and a few new ones added there.
        std::vector<Vec3f> kept;
        std::vector<uint8_t> kept_level;
        for (size_t i = 0; i < p.size(); ++i) {
            if ((p[i] - Vec3f(0.25f, 0.6f, 0.0f)).norm() < 0.1f && level[i] >= surface::k_thin_levels - 2) continue;
            kept.push_back(p[i]);
            kept_level.push_back(level[i]);
        }
        const std::vector<uint8_t> before = kept_level;
        kept.push_back(Vec3f(0.25f, 0.5f, 0.0f + 1e-4f));
        kept.push_back(Vec3f(0.26f, 0.7f, 0.0f + 1e-4f));
        const std::vector<Vec3f> n(kept.size(), Vec3f::UnitZ());
        surface::place_in_thin_order(kept, n, {}, h, kept_level);
        check_levels(kept, {}, kept_level, h);
        // Away from the new ones the order is as it was.
        for (size_t i = 0; i < before.size(); ++i)
            if (kept[i].x() > 0.95f) CHECK(kept_level[i] == before[i]);
    }
}
