#include "sim/closed_surface.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "mesh/closest_point.h"
#include "mesh/polygon.h"

namespace pbdsplat::sim {

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

namespace {

// The solid angle of triangle (a, b, c) seen from the origin, over 4 pi (Van Oosterom and
// Strackee): positive when the triangle winds counter-clockwise seen from the origin's side
// its normal points away from.
double winding_of(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    return 2.0 * std::atan2(num, den) / (4.0 * std::numbers::pi);
}

} // namespace

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

} // namespace pbdsplat::sim
