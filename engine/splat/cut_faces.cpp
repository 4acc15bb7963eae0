#include "splat/cut_faces.h"

#include <algorithm>
#include <cmath>

#include "mesh/polygon.h"
#include "sim/contact.h"
#include "splat/deformed_shape.h"
#include "surface/boundary_particles.h"

namespace pbdsplat::splat {

CutFaces::CutFaces(float h, const std::optional<Vec3f>& interior, const Vec3f& albedo, uint32_t fade_frames, uint32_t seed)
    : h_(h), interior_(interior), albedo_(albedo), fade_frames_(std::max(1u, fade_frames)), seed_(seed) {}

size_t CutFaces::faces() const {
    return size_t(std::count_if(faces_.begin(), faces_.end(), [](const Face& f) { return !f.triangles.empty(); }));
}

bool CutFaces::fading() const {
    return std::any_of(faces_.begin(), faces_.end(), [&](const Face& f) { return !f.triangles.empty() && f.age + 1 < fade_frames_; });
}

const std::vector<mesh::Triangle>* CutFaces::triangles_of(const std::vector<uint32_t>& loop) const {
    for (const Face& f : faces_)
        if (!f.triangles.empty() && f.loop == loop) return &f.triangles;
    return nullptr;
}

size_t CutFaces::samples() const {
    size_t n = 0;
    for (const Face& f : faces_) n += f.bary.size();
    return n;
}

CutFaces::Face CutFaces::make_face(const std::vector<uint32_t>& loop, const sim::SoftBody& body, std::span<const uint32_t> older) const {
    Face f;
    f.loop = loop;
    // A slit is kept, undrawn, so that it is judged once.
    if (!sim::encloses_face(loop, body.particles.x, body.rest_positions)) return f;
    std::vector<Vec3f> outline;
    outline.reserve(loop.size());
    for (uint32_t i : loop) outline.push_back(sim::xyz(body.particles.x[i]));
    // Spanned as contact spans it, folded where a cut crossed an older face (older: the cut
    // loops this follows; contact counts the model's own capped holes too, which a cut rarely
    // crosses).
    const std::vector<mesh::Triangle> local = sim::face_triangles(loop, body.particles.x, older, &f.part);
    f.triangles.reserve(local.size());
    for (const mesh::Triangle& t : local) f.triangles.push_back({loop[t[0]], loop[t[1]], loop[t[2]]});
    share_corners(f);
    // The rim's particles count as samples already placed: the shell draws them.
    std::vector<uint32_t> all(local.size());
    for (uint32_t t = 0; t < all.size(); ++t) all[t] = t;
    surface::SamplingOptions options;
    options.h = h_;
    options.seed = seed_ + uint32_t(loop.front());
    surface::BoundaryParticles s;
    surface::fill_triangles(outline, local, all, options, s);
    const auto [newell, perimeter] = measure(loop, body.particles.x);
    f.first_area = 0.5f * newell.norm(), f.first_perimeter = perimeter;
    f.sample_triangle = std::move(s.triangle);
    f.bary = std::move(s.bary);
    return f;
}

void CutFaces::share_corners(Face& f) {
    std::vector<uint64_t> keys;  // a corner's part, then its particle
    keys.reserve(3 * f.triangles.size());
    const auto key = [&](size_t t, size_t j) { return uint64_t(f.part[t]) << 32 | f.triangles[t][j]; };
    for (size_t t = 0; t < f.triangles.size(); ++t)
        for (size_t j = 0; j < 3; ++j) keys.push_back(key(t, j));
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    f.corner_particles.clear();
    for (uint64_t k : keys) f.corner_particles.push_back(uint32_t(k));
    f.corner_of.resize(3 * f.triangles.size());
    for (size_t t = 0; t < f.triangles.size(); ++t)
        for (size_t j = 0; j < 3; ++j)
            f.corner_of[3 * t + j] = uint32_t(std::lower_bound(keys.begin(), keys.end(), key(t, j)) - keys.begin());
}

void CutFaces::corner_normals(const Face& f, std::span<const Vec4f> x, const Vec3f& n, float area, std::vector<Vec3f>& normals) {
    normals.assign(f.corner_particles.size(), Vec3f::Zero());
    for (size_t t = 0; t < f.triangles.size(); ++t) {
        const mesh::Triangle& c = f.triangles[t];
        const Vec3f a = x[c[0]].head<3>();
        const Vec3f m = (x[c[1]].head<3>() - a).cross(x[c[2]].head<3>() - a);
        // Area-weighted; one that says nothing (a sliver, or one turned over against the face)
        // counts as the face's normal with next to no weight.
        const Vec3f weighted = m.norm() > 2e-4f * area && m.dot(n) > 0.0f ? m : Vec3f(1e-6f * area * n);
        for (size_t j = 0; j < 3; ++j) normals[f.corner_of[3 * t + j]] += weighted;
    }
    for (Vec3f& m : normals) m.normalize();
}

void CutFaces::update(const sim::SoftBody& body) {
    if (!(h_ > 0.0f)) return;
    for (Face& f : faces_) f.seen = false;
    const size_t before = faces_.size();
    std::vector<uint32_t> older;  // made when a new loop needs it
    bool older_made = false;
    for (const sim::VolumeConstraint& v : body.volumes) {
        // A burst piece is open: its openings are where its air went, not faces.
        if (v.piece >= body.pieces || v.leak > 0.0f) continue;
        for (const std::vector<uint32_t>& loop : v.cap_loops) {
            if (loop.size() < 3 || !v.is_opening(loop)) continue;
            const auto known = std::find_if(faces_.begin(), faces_.begin() + long(before), [&](const Face& f) { return f.loop == loop; });
            if (known != faces_.begin() + long(before)) {
                known->seen = true;
                known->age = std::min(known->age + 1, fade_frames_);
                continue;
            }
            if (cut_pending_) {
                if (!older_made) {
                    std::vector<const std::vector<uint32_t>*> loops;
                    for (size_t k = 0; k < before; ++k) loops.push_back(&faces_[k].loop);
                    older = sim::loop_particles(loops), older_made = true;
                }
                faces_.push_back(make_face(loop, body, older));
            } else {  // not a cut's: kept undrawn, so that it is judged once
                faces_.emplace_back().loop = loop;
            }
            faces_.back().seen = true;
        }
    }
    cut_pending_ = false;
    std::erase_if(faces_, [](const Face& f) { return !f.seen; });
}

std::pair<Vec3f, float> CutFaces::measure(const std::vector<uint32_t>& loop, std::span<const Vec4f> x) {
    // The loop winds out of its piece (as the volume constraint closes it): so does the normal.
    Vec3f newell = Vec3f::Zero();
    float perimeter = 0.0f;
    for (size_t k = 0; k < loop.size(); ++k) {
        const Vec3f a = x[loop[k]].head<3>(), b = x[loop[(k + 1) % loop.size()]].head<3>();
        newell += a.cross(b);
        perimeter += (b - a).norm();
    }
    return {newell, perimeter};
}

void CutFaces::append_records(std::span<const Vec4f> x, std::span<const Vec3f> colors, const Appearance& look,
                              std::vector<GaussianRecord>& out, std::vector<GaussianShape>* shapes,
                              std::span<const uint32_t> model_of_particle) const {
    Appearance inside = look;
    std::vector<Vec3f> normals;  // one face's, at its shared corners
    for (const Face& f : faces_) {
        if (f.bary.empty()) continue;
        inside.albedo = albedo_of(f, colors, x.size());
        const auto [newell, perimeter] = measure(f.loop, x);
        const float area = 0.5f * newell.norm();
        if (!(area > 0.0f)) continue;
        const Vec3f n = newell.normalized();
        const float fade = float(f.age + 1) / float(fade_frames_);
        // The samples were spaced on the face as first seen: where the piece has stretched it
        // since (a deflating half's rim pulled wide), they stand farther apart and their splats
        // grow to match (at most 3x, as the shell's stretch-scaled splats), or the face shows
        // holes between them.
        const float stretch = std::clamp(std::max(perimeter / f.first_perimeter, std::sqrt(area / f.first_area)), 1.0f, 3.0f);
        const float scale = look.scale * stretch;
        corner_normals(f, x, n, area, normals);
        for (size_t k = 0; k < f.bary.size(); ++k) {
            const uint32_t ti = f.sample_triangle[k];
            const mesh::Triangle& t = f.triangles[ti];
            const uint32_t* corner = &f.corner_of[3 * size_t(ti)];
            const Vec2f b = f.bary[k];
            const Vec3f p = (1.0f - b.x() - b.y()) * x[t[0]].head<3>() + b.x() * x[t[1]].head<3>() + b.y() * x[t[2]].head<3>();
            const Vec3f blend = (1.0f - b.x() - b.y()) * normals[corner[0]] + b.x() * normals[corner[1]] + b.y() * normals[corner[2]];
            const Vec3f nt = blend.norm() > 1e-6f ? Vec3f(blend.normalized()) : n;
            out.push_back(make_record(p, nt, inside, std::min(1.0f, fade)));
            out.back().scale_half = float_to_half(scale);
            if (t[0] < model_of_particle.size()) set_model(out.back(), model_of_particle[t[0]]);
            if (shapes) {
                const Vec3f t1 = nt.unitOrthogonal(), t2 = nt.cross(t1);
                Eigen::Matrix3f axes;
                axes.col(0) = scale * t1, axes.col(1) = scale * t2, axes.col(2) = scale * DeformedShapes::k_flatness * nt;
                shapes->push_back(make_shape(axes));
                out.back().scale_half = float_to_half(shape_reach(axes));
            }
        }
    }
}

Vec3f CutFaces::albedo_of(const Face& f, std::span<const Vec3f> colors, size_t particles) const {
    if (interior_) return *interior_;
    if (colors.size() != particles || f.loop.empty()) return albedo_;
    Vec3f sum = Vec3f::Zero();
    for (uint32_t i : f.loop) sum += colors[i];
    return sum / float(f.loop.size());
}

void CutFaces::append_surface(std::span<const Vec4f> x, std::vector<Vec4f>& out_x, std::vector<mesh::Triangle>& triangles,
                              std::span<const Vec3f> colors, std::vector<Vec3f>* out_colors) const {
    for (const Face& f : faces_) {
        const uint32_t first = uint32_t(out_x.size());
        for (uint32_t i : f.corner_particles) out_x.push_back(x[i]);
        if (out_colors) out_colors->insert(out_colors->end(), f.corner_particles.size(), albedo_of(f, colors, x.size()));
        for (size_t t = 0; t < f.triangles.size(); ++t)
            triangles.push_back({first + f.corner_of[3 * t], first + f.corner_of[3 * t + 1], first + f.corner_of[3 * t + 2]});
    }
}

} // namespace pbdsplat::splat
