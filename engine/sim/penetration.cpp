#include "sim/penetration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <vector>

#include "mesh/closest_point.h"
#include "mesh/polygon.h"

namespace pbdsplat::sim {
namespace {

struct Corner3 {
    Vec3f a, b, c;
};

// One closed piece's surface as plain triangles (its own and its caps' fans), with its box.
struct ClosedSurface {
    uint32_t piece = 0;
    std::vector<Corner3> triangles;
    Eigen::AlignedBox3f box;
};

// `rest`: the surfaces as they lay at rest (where the body keeps rest positions).
std::vector<ClosedSurface> closed_surfaces(const SoftBody& body, bool rest, const FaceLookup& faces) {
    const auto at = [&](uint32_t i) { return rest ? body.rest_positions[i] : xyz(body.particles.x[i]); };
    std::vector<int> slot(body.pieces, -1);
    std::vector<ClosedSurface> out;
    for (const VolumeConstraint& v : body.volumes) {
        // A burst piece is open, as the contact solver takes it: what lies inside it may have
        // come in through the rip.
        if (v.piece >= body.pieces || slot[v.piece] >= 0 || v.leak > 0.0f) continue;
        slot[v.piece] = int(out.size());
        ClosedSurface& s = out.emplace_back();
        s.piece = v.piece;
        // Each cap as contact closes it (sim/contact.h): the least-area surface spanning its loop.
        std::vector<Vec3f> outline;
        for (const std::vector<uint32_t>& loop : v.cap_loops) {
            if (loop.size() < 3) continue;
            if (const std::vector<mesh::Triangle>* known = faces ? faces(loop) : nullptr) {
                for (const mesh::Triangle& t : *known) s.triangles.push_back({at(t[0]), at(t[1]), at(t[2])});
                continue;
            }
            outline.clear();
            for (uint32_t i : loop) outline.push_back(at(i));
            for (const std::array<uint32_t, 3>& t : mesh::triangulate_least_area(outline)) s.triangles.push_back({outline[t[0]], outline[t[1]], outline[t[2]]});
        }
    }
    for (const mesh::Triangle& t : body.triangles) {
        const int k = slot[body.piece_of_particle[t[0]]];
        if (k >= 0) out[size_t(k)].triangles.push_back({at(t[0]), at(t[1]), at(t[2])});
    }
    for (ClosedSurface& s : out)
        for (const Corner3& t : s.triangles) s.box.extend(t.a), s.box.extend(t.b), s.box.extend(t.c);
    return out;
}

// The solid angle of triangle (a, b, c) seen from the origin, over 4 pi (Van Oosterom and
// Strackee): positive when the triangle winds counter-clockwise seen from the origin's side
// its normal points away from.
double winding_of(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    return 2.0 * std::atan2(num, den) / (4.0 * std::numbers::pi);
}

bool inside(const ClosedSurface& s, const Vec3f& p) {
    if (!s.box.contains(p)) return false;
    const Vec3d pd = p.cast<double>();
    double w = 0.0;
    for (const Corner3& t : s.triangles) w += winding_of(t.a.cast<double>() - pd, t.b.cast<double>() - pd, t.c.cast<double>() - pd);
    return std::abs(w) > 0.5;
}

float distance_to(const ClosedSurface& s, const Vec3f& p) {
    float best = std::numeric_limits<float>::infinity();
    for (const Corner3& t : s.triangles) {
        const Vec2f w = mesh::closest_point_barycentric(p, t.a, t.b, t.c);
        const Vec3f q = (1.0f - w.x() - w.y()) * t.a + w.x() * t.b + w.y() * t.c;
        best = std::min(best, (p - q).squaredNorm());
    }
    return std::sqrt(best);
}

} // namespace

Penetration deepest_penetration(const SoftBody& body, const FaceLookup& faces) {
    Penetration deepest;
    const std::vector<ClosedSurface> surfaces = closed_surfaces(body, false, faces);
    const bool rest_known = body.rest_positions.size() == body.particle_count();
    const std::vector<ClosedSurface> at_rest = rest_known ? closed_surfaces(body, true, faces) : std::vector<ClosedSurface>{};
    const bool parts_known = body.part_of_particle.size() == body.particle_count();
    // Per (part, surface): whether some particle of the part lay inside that piece at rest (the
    // part sits in another in the file: suzanne's eyes, a teapot's lid). Contact leaves such parts
    // to their own shells (sim/contact.h), so how they settle into each other is not measured.
    std::map<std::pair<uint32_t, size_t>, bool> overlapped;  // (part, surface) -> decided
    std::vector<uint32_t> part_of_piece(body.pieces, UINT32_MAX);
    if (parts_known)
        for (size_t j = 0; j < body.particle_count(); ++j)
            if (body.piece_of_particle[j] < body.pieces) part_of_piece[body.piece_of_particle[j]] = body.part_of_particle[j];
    // The other side of a cut is the same part: never left out, however its rim lies on the face.
    const auto overlapped_at_rest = [&](uint32_t part, size_t k) {
        if (part == part_of_piece[at_rest[k].piece]) return false;
        const auto [it, fresh] = overlapped.try_emplace({part, k}, false);
        if (fresh)
            for (size_t j = 0; j < body.particle_count() && !it->second; ++j)
                it->second = body.part_of_particle[j] == part && body.piece_of_particle[j] != at_rest[k].piece &&
                             inside(at_rest[k], body.rest_positions[j]);
        return it->second;
    };
    for (size_t k = 0; k < surfaces.size(); ++k) {
        const ClosedSurface& s = surfaces[k];
        for (size_t i = 0; i < body.particle_count(); ++i) {
            if (body.piece_of_particle[i] == s.piece) continue;
            const Vec3f p = xyz(body.particles.x[i]);
            if (!inside(s, p)) continue;
            // A particle that lay inside this piece at rest has not come through it; nor has a
            // part that lay partly inside it.
            if (rest_known && inside(at_rest[k], body.rest_positions[i])) continue;
            if (rest_known && parts_known && overlapped_at_rest(body.part_of_particle[i], k)) continue;
            const float d = distance_to(s, p);
            if (d > deepest.depth) deepest = {d, uint32_t(i), s.piece};
        }
    }
    return deepest;
}

} // namespace pbdsplat::sim
