#include "sim/contact.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <tuple>

#include "mesh/closest_point.h"
#include "mesh/polygon.h"
#include "sim/enclosure.h"
#include "sim/over_triangle.h"

namespace pbdsplat::sim {

ContactScale contact_scale(float mean_rest_edge, const ContactSettings& s) {
    ContactScale c;
    c.edge = mean_rest_edge;
    c.thickness = s.thickness > 0.0f ? s.thickness : k_auto_thickness * mean_rest_edge;
    // As deep as the thickness: deeper than a resting contact's error gets, far shallower than
    // the far side of a thin part (a particle that deep came through it, and pushing it out would
    // be wrong). A particle that was outside at the substep's start is pushed out from any depth.
    c.margin = c.thickness;
    // Two and a half edges: the particle's ring and the next (its surface's own curvature and
    // the triangles around it), so a resting surface never pushes itself apart.
    c.exclusion = 2.5f * mean_rest_edge + c.thickness;
    // A quarter edge: the search reaches this much further, so its candidates last until some
    // particle has moved half of it (resting contact then searches about once in many frames).
    c.slack = 0.25f * mean_rest_edge;
    return c;
}

template <class Real>
float mean_rest_edge(const SoftBodyT<Real>& body) {
    double sum = 0.0;
    size_t n = 0;
    for (const DistanceConstraint& d : body.distance)
        if (d.alive()) sum += double(d.rest), ++n;
    return n ? float(sum / double(n)) : 0.0f;
}

template <class Real>
bool encloses_face(const std::vector<uint32_t>& loop, const Vec4ArrayT<Real>& x, const std::vector<Vec3f>& rest) {
    const bool use_rest = rest.size() == x.size();
    std::vector<Vec3f> outline;
    outline.reserve(loop.size());
    for (uint32_t i : loop) outline.push_back(use_rest ? rest[i] : Vec3f(x[i].template head<3>().template cast<float>()));
    float perimeter = 0.0f;
    for (size_t k = 0; k < outline.size(); ++k) perimeter += (outline[(k + 1) % outline.size()] - outline[k]).norm();
    double area = 0.0;
    for (const std::array<uint32_t, 3>& t : mesh::triangulate_least_area(outline))
        area += 0.5 * double((outline[t[1]] - outline[t[0]]).cross(outline[t[2]] - outline[t[0]]).norm());
    return area >= 0.002 * double(perimeter) * double(perimeter);
}

template <class Real>
std::vector<std::array<uint32_t, 3>> face_triangles(const std::vector<uint32_t>& loop, const Vec4ArrayT<Real>& x,
                                                    std::span<const uint32_t> older, std::vector<uint8_t>* parts) {
    std::vector<Vec3f> outline;
    std::vector<uint8_t> on_older;
    outline.reserve(loop.size()), on_older.reserve(loop.size());
    for (uint32_t i : loop) {
        outline.push_back(Vec3f(x[i].template head<3>().template cast<float>()));
        on_older.push_back(std::binary_search(older.begin(), older.end(), i) ? 1 : 0);
    }
    return mesh::triangulate_across_older(outline, on_older, parts);
}

std::vector<uint32_t> loop_particles(std::span<const std::vector<uint32_t>* const> loops) {
    std::vector<uint32_t> out;
    for (const std::vector<uint32_t>* loop : loops) out.insert(out.end(), loop->begin(), loop->end());
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

namespace {

// How far behind a surface (over the mean edge) a particle may lie at rest and still count as on
// it: the copies a cut made of one vertex lie on each other's cut faces, behind them by rounding.
constexpr float k_on_surface = 1e-3f;

// A hash grid cell's key; the table's size is a power of two.
inline uint32_t cell_hash(int x, int y, int z) {
    return (uint32_t(x) * 73856093u) ^ (uint32_t(y) * 19349663u) ^ (uint32_t(z) * 83492791u);
}
inline Eigen::Vector3i cell_of(const Vec3f& p, float inv_cell) {
    return {int(std::floor(p.x() * inv_cell)), int(std::floor(p.y() * inv_cell)), int(std::floor(p.z() * inv_cell))};
}

} // namespace

template <class Real>
const typename ContactSolverT<Real>::CapFace& ContactSolverT<Real>::cap_face(const std::vector<uint32_t>& loop, const SoftBodyT<Real>& body) {
    const Vec4ArrayT<Real>& x = body.particles.x;
    for (CapFace& f : cap_faces_)
        if (f.loop == loop) {
            f.used = true;
            return f;
        }
    // The loops known before this one: a cut across one of their faces folds the new face there.
    std::vector<const std::vector<uint32_t>*> known;
    known.reserve(cap_faces_.size());
    for (const CapFace& k : cap_faces_) known.push_back(&k.loop);
    const std::vector<uint32_t> older = loop_particles(known);
    CapFace& f = cap_faces_.emplace_back();
    f.loop = loop;
    f.used = true;
    f.encloses = encloses_face(loop, x, body.rest_positions);
    if (f.encloses) f.triangles = face_triangles(loop, x, older);
    return f;
}

template <class Real>
void ContactSolverT<Real>::build_faces(const SoftBodyT<Real>& body) {
    faces_.clear(), face_vertices_.clear(), face_triangles_.clear();
    face_chunks_ = 0;
    closed_.assign(body.pieces, 0);
    for (CapFace& f : cap_faces_) f.used = false;
    for (const VolumeConstraint& v : body.volumes) {
        // A burst piece is open from the moment it bursts, not once its gas has leaked: what
        // comes in through its openings (the other half of a cut balloon rolling into its bowl)
        // has not come through a wall.
        if (v.piece >= body.pieces || v.leak > 0.0f) continue;
        closed_[v.piece] = 1;
        for (const std::vector<uint32_t>& loop : v.cap_loops) {
            if (loop.size() < 3) continue;
            const CapFace& cap = cap_face(loop, body);
            if (!cap.encloses) continue;
            CutFace f;
            f.first = uint32_t(face_vertices_.size()), f.count = uint32_t(loop.size()), f.piece = v.piece;
            f.cut = v.is_opening(loop);
            face_vertices_.insert(face_vertices_.end(), loop.begin(), loop.end());
            uint32_t k = 0;
            for (const std::array<uint32_t, 3>& t : cap.triangles) {
                // In chunks of k_fan_chunk triangles: a part of the face, a group of the broad phase.
                if (k++ % k_fan_chunk == 0) ++face_chunks_;
                face_triangles_.push_back({uint32_t(faces_.size()), loop[t[0]], loop[t[1]], loop[t[2]], face_chunks_ - 1});
            }
            faces_.push_back(f);
        }
    }
    std::erase_if(cap_faces_, [](const CapFace& f) { return !f.used; });
}

template <class Real>
void ContactSolverT<Real>::update_faces(const ParticlesT<Real>& p) {
    for (CutFace& f : faces_) {
        Vec3f newell = Vec3f::Zero();
        for (uint32_t k = 0; k < f.count; ++k)
            newell += pos3(p.x[face_vertices_[f.first + k]]).cross(pos3(p.x[face_vertices_[f.first + (k + 1) % f.count]]));
        // The loop winds out of the piece, as the volume constraint closes it.
        f.normal = newell.norm() > 0.0f ? Vec3f(newell.normalized()) : Vec3f::Zero();
    }
}

template <class Real>
void ContactSolverT<Real>::build_seam_pairs(const SoftBodyT<Real>& body) {
    seam_pairs_.clear();
    if (body.rest_positions.size() != body.particles.size() || faces_.size() < 2) return;
    struct Key {
        Vec3f rest;
        uint32_t part, particle, face;
        bool operator<(const Key& o) const {
            return std::tie(part, rest.x(), rest.y(), rest.z(), particle) < std::tie(o.part, o.rest.x(), o.rest.y(), o.rest.z(), o.particle);
        }
        bool same_place(const Key& o) const { return part == o.part && rest == o.rest; }
    };
    std::vector<Key> keys;
    keys.reserve(face_vertices_.size());
    for (uint32_t f = 0; f < faces_.size(); ++f)
        for (uint32_t k = 0; k < faces_[f].count; ++k) {
            const uint32_t i = face_vertices_[faces_[f].first + k];
            keys.push_back({body.rest_positions[i], part_[i], i, f});
        }
    std::sort(keys.begin(), keys.end());
    for (size_t k = 0; k + 1 < keys.size(); ++k) {
        const Key &a = keys[k], &b = keys[k + 1];
        if (!a.same_place(b) || a.particle == b.particle || faces_[a.face].piece == faces_[b.face].piece) continue;
        // Three copies at one place (a vertex two cuts went through): which two face each other
        // is not known, and the faces' contact holds them.
        if ((k + 2 < keys.size() && keys[k + 2].same_place(a)) || (k > 0 && keys[k - 1].same_place(a))) continue;
        seam_pairs_.push_back({a.particle, b.particle, a.face, b.face});
    }
}

template <class Real>
void ContactSolverT<Real>::project_seams(SoftBodyT<Real>& body, const ContactSettings& s, bool rigid) {
    ParticlesT<Real>& p = body.particles;
    // Slid more than an edge apart along the faces, the two no longer bear on each other: the
    // faces' contact takes over. More than an edge behind each other, they did not pass through
    // each other in a substep: the pieces parted and turned (two halves of a small ball rolling
    // apart read 1.9 m deep, and the push flung them off at 68 m/s).
    const float reach2 = scale_.edge * scale_.edge;
    for (const SeamPair& sp : seam_pairs_) {
        // From b's face toward a's: the mean of b's outward normal and a's turned round. Faces
        // turned more than 120 degrees from each other no longer face each other.
        const Vec3f nf = faces_[sp.face_b].normal - faces_[sp.face_a].normal;
        const float len = nf.norm();
        if (!(len > 1.0f)) continue;
        if (rigid) {
            if (const Sides sd = pair_sides_[contacts_.size() + size_t(&sp - seam_pairs_.data())]; sd.any()) {
                const Vec3f nu = nf / len, d = pos3(p.x[sp.a]) - pos3(p.x[sp.b]);
                const float C = d.dot(nu);
                if (C < 0.0f && -C <= scale_.edge && (d - C * nu).squaredNorm() <= reach2) {
                    const float overlap = std::max(0.0f, -(pos3(p.x_prev[sp.a]) - pos3(p.x_prev[sp.b])).dot(nu));
                    note_push(body, sp.a, {sp.b, sp.b, sp.b}, -C);
                    separate(p, s, sp.a, {sp.b, sp.b, sp.b}, {1.0f, 0.0f, 0.0f}, sd, nu, -C, std::min(overlap, -C), lift(body, sp.a, sp.b));
                }
                continue;
            }
        }
        const Vec4<Real> n = to4<Real>(Vec3f(nf / len));
        const Vec4<Real> d = p.x[sp.a] - p.x[sp.b];
        const Real C = d.dot(n);
        const Lift l = lift(body, sp.a, sp.b);
        const Real wa = Real(l.particle) * p.w[sp.a], wb = Real(l.surface) * p.w[sp.b];
        const Real w = wa + wb;
        if (C >= Real(0) || !(w > Real(0)) || float(-C) > scale_.edge) continue;
        if (float((d - C * n).squaredNorm()) > reach2) continue;
        const Real depth = -C;
        note_push(body, sp.a, {sp.b, sp.b, sp.b}, float(depth));
        const auto apply = [&](const Vec4<Real>& v) {
            p.x[sp.a] += wa * v;
            p.x[sp.b] -= wb * v;
        };
        apply((depth / w) * n);
        // Coulomb friction on their relative motion since the substep began, as for contacts.
        const Vec4<Real> rel = (p.x[sp.a] - p.x_prev[sp.a]) - (p.x[sp.b] - p.x_prev[sp.b]);
        const Vec4<Real> tangential = rel - rel.dot(n) * n;
        apply((-friction_share(s.friction, tangential.norm(), depth) / w) * tangential);
    }
}

template <class Real>
typename ContactSolverT<Real>::Corners ContactSolverT<Real>::corners_of(const SoftBodyT<Real>& body, uint32_t t) const {
    const size_t real = body.triangles.size();
    if (t < real) {
        const mesh::Triangle& tri = body.triangles[t];
        return {tri[0], tri[1], tri[2], nullptr};
    }
    const FaceTriangle& ft = face_triangles_[t - real];
    return {ft.a, ft.b, ft.c, &faces_[ft.face]};
}

template <class Real>
void ContactSolverT<Real>::touching_pieces(const SoftBodyT<Real>& body, std::vector<std::pair<uint32_t, uint32_t>>& out) const {
    const size_t first = out.size();
    const std::vector<uint32_t>& piece = body.piece_of_particle;
    for (const Contact& c : contacts_) {
        const uint32_t a = piece[c.particle], b = piece[corners_of(body, c.triangle).ia];
        if (a == b) continue;
        const std::pair<uint32_t, uint32_t> pair(std::min(a, b), std::max(a, b));
        // A particle's candidates lie together and mostly on one piece: the sort gets few repeats.
        if (out.size() == first || out.back() != pair) out.push_back(pair);
    }
    std::sort(out.begin() + std::ptrdiff_t(first), out.end());
    out.erase(std::unique(out.begin() + std::ptrdiff_t(first), out.end()), out.end());
}

template <class Real>
typename ContactSolverT<Real>::Neighbourhood ContactSolverT<Real>::neighbourhood_of(const SoftBodyT<Real>& body, uint32_t i, uint32_t pi,
                                                                                  uint32_t piece, const Corners& tk, bool closed,
                                                                                  float r_ex2) const {
    const bool near = pi == piece || (model_[i] == model_[tk.ia] && (part_[i] != part_[tk.ia] || !tk.face));
    if (!near) return {};
    if (pi == piece && tk.face) return {true, true, false};
    if (body.rest_positions.size() != body.particles.size()) return {true, true, false};
    const Vec3f& r = body.rest_positions[i];
    if ((r - body.rest_positions[tk.ia]).squaredNorm() < r_ex2 || (r - body.rest_positions[tk.ib]).squaredNorm() < r_ex2 ||
        (r - body.rest_positions[tk.ic]).squaredNorm() < r_ex2) {
        if (!closed || pi == piece || part_[i] != part_[tk.ia] || !on_rim_[i]) return {true, true, false};
        return {false, true, true};
    }
    return {false, true, false};
}

template <class Real>
bool ContactSolverT<Real>::rest_gap(const SoftBodyT<Real>& body, uint32_t i, const Corners& tk, float side, float& thickness) const {
    const Vec3f& ra = body.rest_positions[tk.ia];
    const Vec3f& rb = body.rest_positions[tk.ib];
    const Vec3f& rc = body.rest_positions[tk.ic];
    const Vec3f rn = unit_normal(ra, rb, rc);
    if (rn.isZero()) return true;
    const Over rest = over_triangle(body.rest_positions[i], ra, rb, rc, rn);
    if (rest.lateral <= scale_.thickness && std::abs(rest.height) < scale_.thickness) {
        if (side * rest.height < -k_on_surface * scale_.edge) return false;
        thickness = std::max(0.0f, std::min(thickness, side * rest.height));
    }
    return true;
}

namespace {

// The side of a triangle a particle is kept on, from its height over the triangle's plane at the
// substep's start: outside a closed piece, or shallowly inside it (pushed out); an open piece
// keeps a particle on the side it started on. A particle of the same piece that started behind
// is in a fold that was there before: which way is out is not known, so it is left alone (0).
// A part that lay wholly inside a closed part at load (`enclosed`) is kept inside it, as the
// rest are kept out: left alone only once it is further out than the margin.
float side_kept(bool closed, bool same_piece, bool enclosed, float h_then, float margin) {
    if (closed && !same_piece && enclosed) return h_then > margin ? 0.0f : -1.0f;
    if (closed && !same_piece) return h_then < -margin ? 0.0f : 1.0f;
    const float side = h_then >= 0.0f ? 1.0f : -1.0f;
    return closed && side < 0.0f ? 0.0f : side;
}

} // namespace

template <class Real>
void ContactSolverT<Real>::test_pair(const SoftBodyT<Real>& body, uint32_t patch, uint32_t group, float r_ex2,
                                     std::vector<Contact>& out) {
    const bool rest_known = body.rest_positions.size() == body.particles.size();
    const float reach = scale_.thickness + scale_.margin + scale_.slack + extra_reach_;
    const Eigen::AlignedBox3f& patch_box = particle_box_[patch];
    for (uint32_t q = group_start_[group]; q < group_start_[group + 1]; ++q) {
        const uint32_t t = group_triangles_[q];
        if (!triangle_box_[q].intersects(patch_box)) continue;
        const Corners tk = corners_of(body, t);
        const uint32_t ia = tk.ia, ib = tk.ib, ic = tk.ic;
        const Vec3f a = now_[ia], b = now_[ib], c = now_[ic];
        const Vec3f a0 = then_[ia], b0 = then_[ib], c0 = then_[ic];
        const uint32_t piece = tk.face ? tk.face->piece : body.piece_of_particle[ia];
        if (piece >= body.pieces) continue;
        const Eigen::AlignedBox3f box(triangle_box_[q].min() - Vec3f::Constant(reach), triangle_box_[q].max() + Vec3f::Constant(reach));
        Vec3f nrm = Vec3f::Zero(), nrm0 = Vec3f::Zero();
        float d_now = 0.0f, d_then = 0.0f;
        bool planes = false;
        const bool closed = closed_[piece] != 0;
        const bool nested = !body.enclosed_parts.empty();
        for (uint32_t e = patch_start_[patch]; e < patch_start_[patch + 1]; ++e) {
            const uint32_t i = patch_particles_[e];
            if (!box.contains(now_[i]) && !box.contains(then_[i])) continue;
            if (i == ia || i == ib || i == ic) continue;
            const uint32_t pi = body.piece_of_particle[i];
            if (pi == k_no_piece) continue;
            if (!self_ && pi == piece) continue;
            // An enclosed part is met by its container wherever it comes, near at rest or not:
            // left alone near the wall, it fell through the container's floor.
            const bool enclosed = nested && part_encloses(body.enclosed_parts, part_[tk.ia], part_[i]);
            const bool container = nested && !enclosed && part_encloses(body.enclosed_parts, part_[i], part_[tk.ia]);
            const Neighbourhood nb = enclosed || container ? Neighbourhood{} : neighbourhood_of(body, i, pi, piece, tk, closed, r_ex2);
            if (nb.skip) continue;
            if (!planes) {
                nrm = unit_normal(a, b, c), nrm0 = unit_normal(a0, b0, c0);
                d_now = a.dot(nrm), d_then = a0.dot(nrm0);
                planes = true;
            }
            if (nrm.isZero() || nrm0.isZero()) break;
            // A cut face's triangle turned over since the face was made (its outline bent back
            // across it) faces into its piece and would push a particle the wrong way: left out
            // while it stays turned.
            if (tk.face && nrm.dot(tk.face->normal) < 0.0f) break;
            // Heights over the planes first (cheap), the closest points after.
            const float h_then = then_[i].dot(nrm0) - d_then, h_now = now_[i].dot(nrm) - d_now;
            const float side = side_kept(closed, pi == piece, enclosed, h_then, scale_.margin);
            if (side == 0.0f) continue;
            if (side * h_now > reach) continue;  // clear of it at the end of the sweep
            if (std::abs(h_now) >= farthest_kept(i)) continue;
            const Over now = over_triangle(now_[i], a, b, c, nrm), then = over_triangle(then_[i], a0, b0, c0, nrm0);
            const float beside = scale_.thickness + scale_.slack + extra_reach_;
            if (now.lateral > beside && then.lateral > beside) continue;  // beside it
            float thickness = nb.seam ? 0.0f : scale_.thickness;
            if (!nb.near && rest_known && !rest_gap(body, i, tk, side, thickness)) continue;
            keep(out, {i, t, side, thickness, std::abs(h_now) + std::min(now.lateral, then.lateral)});
        }
    }
}

template <class Real>
float ContactSolverT<Real>::farthest_kept(uint32_t i) const {
    if (kept_[i] < k_max_candidates) return std::numeric_limits<float>::infinity();
    const float* key = &slot_key_[size_t(i) * k_max_candidates];
    return *std::max_element(key, key + k_max_candidates);
}

template <class Real>
void ContactSolverT<Real>::keep(std::vector<Contact>& out, const Contact& c) {
    const float distance = c.key;
    const size_t base = size_t(c.particle) * k_max_candidates;
    uint32_t& kept = kept_[c.particle];
    if (kept < k_max_candidates) {
        slot_[base + kept] = uint32_t(out.size());
        slot_key_[base + kept] = distance;
        ++kept;
        out.push_back(c);
        return;
    }
    // Full: the new one takes the farthest's place (in the list too, so the order of every
    // particle under the limit is the search's).
    float* key = &slot_key_[base];
    const size_t far = size_t(std::max_element(key, key + k_max_candidates) - key);
    if (!(distance < key[far])) return;
    out[slot_[base + far]] = c;
    key[far] = distance;
}

template <class Real>
void ContactSolverT<Real>::update_origins(const SoftBodyT<Real>& body) {
    // From the body where it keeps them (make_soft_body and the topology edits do); else the
    // pieces the solver first met, one model, and particles added since taking a neighbour's.
    const size_t n = body.particles.size();
    const bool parts = body.part_of_particle.size() == n, models = body.model_of_particle.size() == n;
    if (parts) part_ = body.part_of_particle;
    if (models) model_ = body.model_of_particle;
    if (parts && models) return;
    const auto extend = [&](std::vector<uint32_t>& v, const std::vector<uint32_t>& first) {
        if (v.size() > n || v.empty()) v.assign(first.begin(), first.begin() + long(std::min(n, first.size())));
        if (v.size() == n) return;
        v.resize(n, k_no_piece);
        for (int pass = 0; pass < 3; ++pass)
            for (const mesh::Triangle& t : body.triangles)
                for (int c = 0; c < 3; ++c)
                    if (v[t[size_t(c)]] == k_no_piece)
                        for (int d = 1; d < 3; ++d)
                            if (const uint32_t o = v[t[size_t((c + d) % 3)]]; o != k_no_piece) {
                                v[t[size_t(c)]] = o;
                                break;
                            }
    };
    if (!parts) extend(part_, body.piece_of_particle);
    if (!models) {
        if (model_.size() > n || model_.empty()) model_.assign(n, 0);
        extend(model_, model_);
    }
}

template <class Real>
void ContactSolverT<Real>::build_patches(const SoftBodyT<Real>& body) {
    // A patch is one piece's particles in one rest-space cell: the two sides of a cut share
    // cells but go their own ways. Rest positions only grow (a cut's new particles get theirs),
    // so the patches are kept until the particle count, the pieces or the edge length change.
    const size_t n = body.particles.size();
    if (patch_of_.size() == n && patch_edge_ == scale_.edge && patch_pieces_ == body.pieces && !patch_start_.empty()) return;
    patch_edge_ = scale_.edge, patch_pieces_ = body.pieces;
    const bool rest_known = body.rest_positions.size() == n;
    const float inv_cell = 2.0f / scale_.exclusion;
    struct Keyed {
        uint32_t piece;
        int x, y, z;
        uint32_t i;
        bool operator<(const Keyed& o) const { return std::tie(piece, x, y, z, i) < std::tie(o.piece, o.x, o.y, o.z, o.i); }
        bool same_patch(const Keyed& o) const { return piece == o.piece && x == o.x && y == o.y && z == o.z; }
    };
    std::vector<Keyed> keyed(n);
    for (uint32_t i = 0; i < n; ++i) {
        const Eigen::Vector3i c = rest_known ? cell_of(body.rest_positions[i], inv_cell) : Eigen::Vector3i(int(i / 16), 0, 0);
        keyed[i] = {body.piece_of_particle[i], c.x(), c.y(), c.z(), i};
    }
    std::sort(keyed.begin(), keyed.end());
    patch_of_.resize(n), patch_particles_.resize(n);
    patch_start_.assign(1, 0);
    for (uint32_t k = 0; k < n; ++k) {
        if (k > 0 && !keyed[k].same_patch(keyed[k - 1])) patch_start_.push_back(k);
        patch_particles_[k] = keyed[k].i;
        patch_of_[keyed[k].i] = uint32_t(patch_start_.size() - 1);
    }
    patch_start_.push_back(uint32_t(n));
}

template <class Real>
typename ContactSolverT<Real>::Worth ContactSolverT<Real>::candidates_hold(const SoftBodyT<Real>& body, const ContactSettings& s) {
    // The last search's candidates hold while no particle has moved half the slack since it (and
    // the topology is the same): every pair that could come within reach is among them. A body
    // at rest, or pieces resting on each other, search once in many frames.
    const ParticlesT<Real>& p = body.particles;
    const size_t n = p.size();
    if (!s.enabled || n == 0 || n != anchor_.size() || body.triangles.size() != anchor_triangles_ || body.pieces != anchor_pieces_ ||
        s.self != self_)
        return Worth::none;
    const float limit2 = 0.25f * scale_.slack * scale_.slack;
    away_.assign(body.pieces, 0);
    bool moved = false;
    for (size_t i = 0; i < n; ++i)
        if (!((pos3(p.x[i]) - anchor_[i]).squaredNorm() < limit2)) {
            const uint32_t k = body.piece_of_particle[i];
            if (k >= body.pieces || s.self) return Worth::none;
            away_[k] = 1, moved = true;
        }
    if (!moved || moved_pieces_apart(body)) return Worth::hold;
    // A heap of many pieces keeps a few of them rocking at any time: searching the moved ones
    // alone costs what they hold. Past half the particles a whole search is as cheap.
    size_t in_moved = 0;
    for (size_t i = 0; i < n; ++i) in_moved += body.piece_of_particle[i] < body.pieces && away_[body.piece_of_particle[i]];
    return 2 * in_moved <= n ? Worth::moved_only : Worth::none;
}

template <class Real>
void ContactSolverT<Real>::hold_unmoved(const SoftBodyT<Real>& body) {
    // The candidates between pieces that did not move, by the patch of their particle: each
    // patch's are kept again as its search begins, so the nearest still win and the order is
    // the patch order of a whole search.
    const uint32_t patches = uint32_t(patch_start_.size() - 1);
    const auto unmoved = [&](uint32_t piece) { return piece < away_.size() && !away_[piece]; };
    held_start_.assign(patches + 2, 0);
    held_.clear();
    for (const Contact& c : contacts_) {
        const Corners k = corners_of(body, c.triangle);
        if (unmoved(body.piece_of_particle[c.particle]) && unmoved(k.face ? k.face->piece : body.piece_of_particle[k.ia]))
            ++held_start_[patch_of_[c.particle] + 2], held_.push_back(c);
    }
    for (uint32_t g = 0; g < patches; ++g) held_start_[g + 2] += held_start_[g + 1];
    held_sorted_.resize(held_.size());
    for (const Contact& c : held_) held_sorted_[held_start_[patch_of_[c.particle] + 1]++] = c;
    held_.swap(held_sorted_);
}

template <class Real>
bool ContactSolverT<Real>::moved_pieces_apart(const SoftBodyT<Real>& body) {
    // A piece that moved (falling free after a cut, thrown, sliding off a stack) but whose path
    // this substep lies two reaches from every other piece's meets no pair a search would find:
    // without this, each of its substeps searched the whole body again. Pairs are only ever
    // between pieces (self-contact, within one, returned above).
    const ParticlesT<Real>& p = body.particles;
    swept_box_.assign(body.pieces, Eigen::AlignedBox3f());
    for (size_t i = 0; i < p.size(); ++i) {
        const uint32_t k = body.piece_of_particle[i];
        if (k < body.pieces) swept_box_[k].extend(pos3(p.x[i])).extend(pos3(p.x_prev[i]));
    }
    const float apart = 2.0f * (scale_.thickness + scale_.margin + scale_.slack);
    for (size_t a = 0; a < body.pieces; ++a) {
        if (!away_[a]) continue;
        for (size_t b = 0; b < body.pieces; ++b)
            if (b != a && !swept_box_[b].isEmpty() && !(swept_box_[a].exteriorDistance(swept_box_[b]) > apart)) return false;
    }
    // Such a piece's candidates were left behind when it moved off: out of reach, they would
    // still name the pieces it touched (and wake them).
    std::erase_if(contacts_, [&](const Contact& c) {
        return away_[body.piece_of_particle[c.particle]] || away_[body.piece_of_particle[corners_of(body, c.triangle).ia]];
    });
    return true;
}

template <class Real>
void ContactSolverT<Real>::find(const SoftBodyT<Real>& body, const ContactSettings& s, float shape_stiffness) {
    const ParticlesT<Real>& p = body.particles;
    const size_t n = p.size();
    rigid_.map(body.shapes, p.w, shape_stiffness);
    rigid_ready_ = false;
    heights_ready_ = false;
    // One piece without self-contact has nothing to meet (its own cap faces close it along its
    // rim), so a body alone pays for no search; its loops' faces are still made as they appear,
    // since a face keeps the shape it had then.
    if (body.pieces < 2 && !s.self) {
        contacts_.clear(), seam_pairs_.clear(), anchor_.clear();
        stacked_ = false;
        if (s.enabled) build_faces(body);
        return;
    }
    scale_ = contact_scale(mean_rest_edge(body), s);
    const Worth worth = candidates_hold(body, s);
    if (worth == Worth::hold) return;
    partial_ = worth == Worth::moved_only;
    extra_reach_ = partial_ ? 0.5f * scale_.slack : 0.0f;
    seam_pairs_.clear();
    stacked_ = false;
    if (!s.enabled || n == 0 || body.triangles.empty() || !(scale_.edge > 0.0f)) {
        contacts_.clear(), anchor_.clear();
        return;
    }
    ++searches_;
    partial_searches_ += partial_ ? 1 : 0;
    build_faces(body);
    update_faces(p);

    // Broad phase over patches: the particles of one cell of a rest-space grid (cells half the
    // exclusion radius wide, so a patch is a compact piece of surface), each with the swept box
    // of its particles (grown by the reach) and of the triangles whose first corner it holds; a
    // cap loop's face is a triangle group of its own. A pair of groups whose boxes meet is tested
    // particle by triangle, unless both lie in one piece and their rest boxes are within half the
    // exclusion radius (a surface resting against itself, everywhere on a body at rest: that is
    // what makes the search cost next to nothing where nothing touches). So the parts of a piece
    // that never touch are those within 1 to 2.2 exclusion radii of each other at rest.
    const float reach = scale_.thickness + scale_.margin + scale_.slack + extra_reach_;
    now_.resize(n), then_.resize(n);
    for (size_t i = 0; i < n; ++i) now_[i] = pos3(p.x[i]), then_[i] = pos3(p.x_prev[i]);
    self_ = s.self;
    update_origins(body);
    on_rim_.assign(n, 0);
    for (uint32_t i : face_vertices_) on_rim_[i] = 1;
    build_seam_pairs(body);
    build_patches(body);
    if (partial_) hold_unmoved(body);
    box_patches(body, reach);
    group_triangles(body);
    build_grid(body);
    search_pairs(body);
    note_search(body);
}

template <class Real>
void ContactSolverT<Real>::note_search(const SoftBodyT<Real>& body) {
    const size_t n = body.particles.size();
    // Stacked: a piece on another's cut face, or one model on another. Not the parts of one
    // model on each other's own capped holes (a teapot's lid in its pot). A burst piece has no
    // faces (counted, the random-cut stress test's heap of burst flakes ran 150 times slower).
    stacked_ = std::any_of(seam_pairs_.begin(), seam_pairs_.end(), [&](const SeamPair& sp) { return faces_[sp.face_a].cut; }) ||
               std::any_of(contacts_.begin(), contacts_.end(), [&](const Contact& c) {
                   const Corners k = corners_of(body, c.triangle);
                   return k.face ? k.face->cut && k.face->piece != body.piece_of_particle[c.particle] : model_[c.particle] != model_[k.ia];
               });
    if (!partial_) anchor_ = now_;
    else
        for (size_t i = 0; i < n; ++i)
            if (body.piece_of_particle[i] < body.pieces && away_[body.piece_of_particle[i]]) anchor_[i] = now_[i];
    anchor_triangles_ = body.triangles.size(), anchor_pieces_ = body.pieces;
}

template <class Real>
void ContactSolverT<Real>::box_patches(const SoftBodyT<Real>& body, float reach) {
    const size_t n = body.particles.size();
    const uint32_t patches = uint32_t(patch_start_.size() - 1);
    const uint32_t groups = patches + face_chunks_;
    particle_box_.assign(patches, Eigen::AlignedBox3f());
    rest_box_.assign(patches, Eigen::AlignedBox3f());
    group_box_.assign(groups, Eigen::AlignedBox3f());
    patch_piece_.assign(groups, k_no_piece);
    const bool rest_known = body.rest_positions.size() == n;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t g = patch_of_[i], pi = body.piece_of_particle[i];
        if (pi == k_no_piece) continue;
        particle_box_[g].extend(now_[i]).extend(then_[i]);
        if (rest_known) rest_box_[g].extend(body.rest_positions[i]);
        patch_piece_[g] = pi;  // a patch holds one piece
    }
    for (Eigen::AlignedBox3f& b : particle_box_)
        if (!b.isEmpty()) b = Eigen::AlignedBox3f(b.min() - Vec3f::Constant(reach), b.max() + Vec3f::Constant(reach));
}

template <class Real>
void ContactSolverT<Real>::group_triangles(const SoftBodyT<Real>& body) {
    const size_t real = body.triangles.size();
    const uint32_t patches = uint32_t(patch_start_.size() - 1);
    const uint32_t groups = patches + face_chunks_;
    group_start_.assign(groups + 1, 0);
    for (size_t t = 0; t < real; ++t) ++group_start_[patch_of_[body.triangles[t][0]] + 1];
    for (const FaceTriangle& ft : face_triangles_) ++group_start_[patches + ft.chunk + 1];
    for (uint32_t g = 0; g < groups; ++g) group_start_[g + 1] += group_start_[g];
    group_triangles_.resize(group_start_.back());
    std::vector<uint32_t>& cursor = cursor_;
    cursor.assign(group_start_.begin(), group_start_.end() - 1);
    triangle_box_.resize(group_triangles_.size());
    const auto swept = [](const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& a0, const Vec3f& b0, const Vec3f& c0) {
        return Eigen::AlignedBox3f(a.cwiseMin(b).cwiseMin(c).cwiseMin(a0).cwiseMin(b0).cwiseMin(c0),
                                   a.cwiseMax(b).cwiseMax(c).cwiseMax(a0).cwiseMax(b0).cwiseMax(c0));
    };
    for (uint32_t t = 0; t < real; ++t) {
        const mesh::Triangle& tri = body.triangles[t];
        const uint32_t g = patch_of_[tri[0]];
        const uint32_t q = cursor[g]++;
        group_triangles_[q] = t;
        triangle_box_[q] = swept(now_[tri[0]], now_[tri[1]], now_[tri[2]], then_[tri[0]], then_[tri[1]], then_[tri[2]]);
        group_box_[g].extend(triangle_box_[q]);
    }
    for (uint32_t k = 0; k < face_triangles_.size(); ++k) {
        const CutFace& face = faces_[face_triangles_[k].face];
        const uint32_t g = patches + face_triangles_[k].chunk;
        const uint32_t q = cursor[g]++;
        group_triangles_[q] = uint32_t(real + k);
        const Corners tk = corners_of(body, uint32_t(real + k));
        triangle_box_[q] = swept(now_[tk.ia], now_[tk.ib], now_[tk.ic], then_[tk.ia], then_[tk.ib], then_[tk.ic]);
        group_box_[g].extend(triangle_box_[q]);
        patch_piece_[g] = face.piece;
    }
}

template <class Real>
bool ContactSolverT<Real>::cell_range(const Eigen::AlignedBox3f& b, Eigen::Vector3i& lo, Eigen::Vector3i& hi) const {
    lo = cell_of(b.min(), inv_cell_), hi = cell_of(b.max(), inv_cell_);
    return ((hi - lo).array() < k_span).all();
}

template <class Real>
template <class Fn>
void ContactSolverT<Real>::each_cell(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi, const Fn& fn) const {
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x) fn(cell_hash(x, y, z) & (table_ - 1));
}

template <class Real>
bool ContactSolverT<Real>::meets_another(const Eigen::AlignedBox3f& b, uint32_t piece, size_t pieces) const {
    if (!by_piece_ || piece >= pieces) return true;
    for (uint32_t q = 0; q < piece_box_.size(); ++q)
        if (q != piece && piece_box_[q].intersects(b)) return true;
    return false;
}

// The triangle groups into a hash grid of cells about a patch wide; each particle patch reads
// the cells its box meets. A box more than k_span cells wide (a cap across the body, a patch
// stretched along a seam) stays out of the grid: it is tested against every box of the other kind.
template <class Real>
void ContactSolverT<Real>::build_grid(const SoftBodyT<Real>& body) {
    const uint32_t patches = uint32_t(patch_start_.size() - 1);
    const uint32_t groups = patches + face_chunks_;
    float extent = 0.0f;
    size_t boxes = 0;
    for (const Eigen::AlignedBox3f& b : particle_box_)
        if (!b.isEmpty()) extent += b.sizes().maxCoeff(), ++boxes;
    inv_cell_ = boxes ? float(boxes) / extent : 1.0f;
    table_ = std::bit_ceil(std::max(16u, 4 * groups));
    cell_start_.assign(table_ + 1, 0);
    // Without self-contact a box that meets no other piece's box has nothing to meet: with the
    // pieces resting on each other, only the patches and groups along where they touch take part.
    // (Past k_piece_boxes pieces the pieces' boxes cost more than they save.)
    constexpr size_t k_piece_boxes = 64;
    by_piece_ = !self_ && body.pieces <= k_piece_boxes;
    piece_box_.assign(by_piece_ ? body.pieces : 0, Eigen::AlignedBox3f());
    if (by_piece_) {
        for (uint32_t g = 0; g < patches; ++g)
            if (!particle_box_[g].isEmpty() && patch_piece_[g] < body.pieces) piece_box_[patch_piece_[g]].extend(particle_box_[g]);
        for (uint32_t g = patches; g < groups; ++g)
            if (!group_box_[g].isEmpty() && patch_piece_[g] < body.pieces) piece_box_[patch_piece_[g]].extend(group_box_[g]);
    }
    in_play_.assign(groups, 0);
    for (uint32_t g = 0; g < groups; ++g)
        in_play_[g] = !(g < patches ? particle_box_[g] : group_box_[g]).isEmpty() &&
                      meets_another(g < patches ? particle_box_[g] : group_box_[g], patch_piece_[g], body.pieces);
    const auto left_out = [&](uint32_t g) {
        return group_box_[g].isEmpty() || (by_piece_ && !in_play_[g] && !meets_another(group_box_[g], patch_piece_[g], body.pieces));
    };
    big_groups_.clear();
    for (uint32_t g = 0; g < groups; ++g) {
        if (left_out(g)) continue;
        Eigen::Vector3i lo, hi;
        if (cell_range(group_box_[g], lo, hi)) each_cell(lo, hi, [&](uint32_t key) { ++cell_start_[key + 1]; });
        else big_groups_.push_back(g);
    }
    for (uint32_t k = 0; k < table_; ++k) cell_start_[k + 1] += cell_start_[k];
    cell_particles_.resize(cell_start_.back());
    cursor_.assign(cell_start_.begin(), cell_start_.end() - 1);
    for (uint32_t g = 0; g < groups; ++g) {
        Eigen::Vector3i lo, hi;
        if (left_out(g)) continue;
        if (cell_range(group_box_[g], lo, hi)) each_cell(lo, hi, [&](uint32_t key) { cell_particles_[cursor_[key]++] = g; });
    }
    // Without self-contact a patch meets nothing of its own piece, and most entries of the cells
    // it reads are its own surface's. A cell's entries run in group order, which is piece order
    // for the patches (sorted by piece; the cut faces' groups follow), so each entry notes where
    // its piece's run ends: a patch passes its own piece's run in one step.
    entry_piece_.resize(cell_particles_.size());
    run_end_.resize(cell_particles_.size());
    for (uint32_t k = 0; k < table_; ++k) {
        const uint32_t begin = cell_start_[k], end = cell_start_[k + 1];
        for (uint32_t e = begin; e < end; ++e) entry_piece_[e] = patch_piece_[cell_particles_[e]];
        for (uint32_t e = end; e-- > begin;)
            run_end_[e] = e + 1 < end && entry_piece_[e + 1] == entry_piece_[e] ? run_end_[e + 1] : e + 1;
    }
}

template <class Real>
void ContactSolverT<Real>::search_pairs(const SoftBodyT<Real>& body) {
    const uint32_t patches = uint32_t(patch_start_.size() - 1);
    kept_.assign(body.particles.size(), 0);
    slot_.resize(body.particles.size() * k_max_candidates);
    slot_key_.resize(slot_.size());
    // Patches in contiguous chunks, one list of candidates each, joined in chunk order: the
    // candidates and their order are the one-thread search's for any thread count. A patch's
    // particles are its own, so the chunks write disjoint slots.
    const unsigned chunks = pool_ && pool_->size() > 1 && patches >= k_patches_per_chunk * pool_->chunks() ? pool_->chunks() : 1u;
    chunk_.resize(chunks);
    const auto run = [&](unsigned chunk, size_t begin, size_t end) {
        ChunkScratch& c = chunk_[chunk];
        c.contacts.clear();
        search_patches(body, uint32_t(begin), uint32_t(end), c);
    };
    if (chunks > 1) pool_->parallel_for(patches, run);
    else run(0, 0, patches);
    contacts_.clear();
    if (chunks == 1) return contacts_.swap(chunk_[0].contacts);
    for (unsigned k = 0; k < chunks; ++k) contacts_.insert(contacts_.end(), chunk_[k].contacts.begin(), chunk_[k].contacts.end());
}

template <class Real>
void ContactSolverT<Real>::search_patches(const SoftBodyT<Real>& body, uint32_t first, uint32_t last, ChunkScratch& c) {
    const uint32_t patches = uint32_t(patch_start_.size() - 1);
    const uint32_t groups = patches + face_chunks_;
    const bool rest_known = body.rest_positions.size() == body.particles.size();
    c.seen.assign(groups, UINT32_MAX);
    const float r_ex2 = scale_.exclusion * scale_.exclusion;
    const auto moved = [&](uint32_t piece) { return !partial_ || (piece < away_.size() && away_[piece]); };
    const auto near_moved = [&](const Eigen::AlignedBox3f& box) {
        for (uint32_t k = 0; k < away_.size(); ++k)
            if (away_[k] && box.intersects(swept_box_[k])) return true;
        return false;
    };
    for (uint32_t A = first; A < last; ++A) {
        if (partial_)
            for (uint32_t e = held_start_[A]; e < held_start_[A + 1]; ++e) keep(c.contacts, held_[e]);
        if (particle_box_[A].isEmpty() || !in_play_[A]) continue;
        // A patch of a piece that did not move meets only the moved pieces' groups anew.
        const bool a_moved = moved(patch_piece_[A]);
        if (!a_moved && !near_moved(particle_box_[A])) continue;
        const auto visit = [&](uint32_t B) {
            if (c.seen[B] == A) return;
            c.seen[B] = A;
            if (!a_moved && !moved(patch_piece_[B])) return;
            if (!particle_box_[A].intersects(group_box_[B])) return;
            if (patch_piece_[A] == patch_piece_[B] && (B >= patches || !self_)) return;  // a piece's own cap closes it along its rim
            if (B < patches && patch_piece_[A] == patch_piece_[B] && rest_known && rest_box_[A].exteriorDistance(rest_box_[B]) < 0.5f * scale_.exclusion)
                return;
            test_pair(body, A, B, r_ex2, c.contacts);
        };
        Eigen::Vector3i lo, hi;
        if (!brute_force_ && cell_range(particle_box_[A], lo, hi)) {
            const uint32_t own = self_ ? k_no_piece : patch_piece_[A];
            each_cell(lo, hi, [&](uint32_t key) {
                for (uint32_t e = cell_start_[key], end = cell_start_[key + 1]; e < end;) {
                    if (entry_piece_[e] == own) {
                        e = run_end_[e];
                        continue;
                    }
                    visit(cell_particles_[e++]);
                }
            });
        } else {
            for (uint32_t B = 0; B < groups; ++B)
                if (!group_box_[B].isEmpty()) visit(B);
        }
        for (uint32_t B : big_groups_) visit(B);
    }
}

template <class Real>
void ContactSolverT<Real>::touch_clusters(const SoftBodyT<Real>& body) {
    touch_.clear();
    pair_sides_.clear();
    const auto touch = [&](Sides sd) {
        pair_sides_.push_back(sd);
        if (sd.particle != RigidResponseT<Real>::k_none) touch_.push_back(sd.particle);
        if (sd.surface != RigidResponseT<Real>::k_none) touch_.push_back(sd.surface);
    };
    for (const Contact& ct : contacts_) {
        const Corners k = corners_of(body, ct.triangle);
        touch(sides_of(ct.particle, {k.ia, k.ib, k.ic}));
    }
    for (const SeamPair& sp : seam_pairs_) touch(sides_of(sp.a, {sp.b, sp.b, sp.b}));
}

template <class Real>
typename ContactSolverT<Real>::Sides ContactSolverT<Real>::sides_of(uint32_t i, const std::array<uint32_t, 3>& corners) const {
    constexpr uint32_t none = RigidResponseT<Real>::k_none;
    // A soft body on either side: both answer particle by particle (RigidResponseT::k_soft).
    if (rigid_.soft(i) || rigid_.soft(corners[0]) || rigid_.soft(corners[1]) || rigid_.soft(corners[2])) return Sides{};
    Sides sd{rigid_.cluster_of(i), rigid_.cluster_of(corners[0])};
    if (rigid_.cluster_of(corners[1]) != sd.surface || rigid_.cluster_of(corners[2]) != sd.surface) sd.surface = none;
    // Both in one cluster (a fold, two welded parts): a rigid answer would move both alike.
    if (sd.particle == sd.surface) sd = Sides{};
    return sd;
}

template <class Real>
void ContactSolverT<Real>::separate(ParticlesT<Real>& p, const ContactSettings& s, uint32_t i, const std::array<uint32_t, 3>& k,
                                    const std::array<float, 3>& u, Sides sd, const Vec3f& n, float depth, float overlap, Lift lift) {
    constexpr uint32_t none = RigidResponseT<Real>::k_none;
    const Vec3f xi = pos3(p.x[i]);
    Vec3f q = Vec3f::Zero();
    for (int j = 0; j < 3; ++j)
        if (u[j] != 0.0f) q += u[j] * pos3(p.x[k[j]]);
    const auto inverse_mass = [&](const Vec3f& dir) {
        float w = lift.particle * (sd.particle != none ? rigid_.inverse_mass(sd.particle, xi, dir) : float(p.w[i]));
        if (sd.surface != none) return w + lift.surface * rigid_.inverse_mass(sd.surface, q, dir);
        for (int j = 0; j < 3; ++j) w += lift.surface * u[j] * u[j] * float(p.w[k[j]]);
        return w;
    };
    // `impulse` on the particle, its opposite on the surface point.
    const auto move = [&](const Vec3f& impulse, bool vote, float settle) {
        const Vec3f up_side = lift.particle * impulse, down_side = lift.surface * impulse;
        const Vec4<Real> j4 = to4<Real>(up_side), s4 = to4<Real>(settle * up_side);
        if (sd.particle != none) rigid_.push(sd.particle, xi, up_side, vote, settle);
        else p.x[i] += p.w[i] * j4, p.x_prev[i] += p.w[i] * s4;
        const Vec4<Real> k4 = to4<Real>(down_side), t4 = to4<Real>(settle * down_side);
        if (sd.surface != none) rigid_.push(sd.surface, q, -down_side, vote, settle);
        else
            for (int j = 0; j < 3; ++j)
                if (u[j] != 0.0f) p.x[k[j]] -= (p.w[k[j]] * Real(u[j])) * k4, p.x_prev[k[j]] -= (p.w[k[j]] * Real(u[j])) * t4;
    };
    const float denom = inverse_mass(n);
    if (!(denom > 0.0f)) return;
    move((depth / denom) * n, true, std::clamp(overlap / depth, 0.0f, 1.0f));
    Vec3f rel = pos3(p.x[i]) - pos3(p.x_prev[i]);
    for (int j = 0; j < 3; ++j)
        if (u[j] != 0.0f) rel -= u[j] * (pos3(p.x[k[j]]) - pos3(p.x_prev[k[j]]));
    const Vec3f tangential = rel - rel.dot(n) * n;
    const float length = tangential.norm();
    if (!(length > 0.0f)) return;
    const Vec3f dir = tangential / length;
    const float rub = friction_share(s.friction, length, depth) * length;
    const float along = inverse_mass(dir);
    if (!(rub > 0.0f && along > 0.0f)) return;
    move((-rub / along) * dir, false, 0.0f);
}

template <class Real>
void ContactSolverT<Real>::take_heights(const SoftBodyT<Real>& body) {
    heights_ready_ = true;
    piece_height_.assign(body.pieces, 0.0f);
    piece_weight_.assign(body.pieces, 0.0f);
    if (up_.isZero()) return;
    // Once a substep: the counts reuse a kept buffer; a pinned particle marks its piece with -1.
    piece_count_.assign(body.pieces, 0);
    for (size_t i = 0; i < body.particles.size(); ++i) {
        const uint32_t piece = body.piece_of_particle[i];
        if (piece >= body.pieces) continue;
        const float w = float(body.particles.w[i]);
        piece_height_[piece] += pos3(body.particles.x[i]).dot(up_), ++piece_count_[piece];
        if (!(w > 0.0f)) piece_weight_[piece] = -INFINITY;
        else piece_weight_[piece] += 1.0f / w;
    }
    for (uint32_t k = 0; k < body.pieces; ++k)
        if (piece_count_[k]) piece_height_[k] /= float(piece_count_[k]), piece_weight_[k] = std::max(0.0f, piece_weight_[k] / float(piece_count_[k]));
}

template <class Real>
typename ContactSolverT<Real>::Lift ContactSolverT<Real>::lift(const SoftBodyT<Real>& body, uint32_t particle, uint32_t corner) const {
    if (up_.isZero()) return {};
    const uint32_t a = body.piece_of_particle[particle], b = body.piece_of_particle[corner];
    if (a == b || a >= piece_height_.size() || b >= piece_height_.size()) return {};
    const float mp = piece_weight_[a], ms = piece_weight_[b];
    if (!(mp > 0.0f && ms > 0.0f)) return {};
    // Pieces of like weight (a cut's, one model's parts) are left alone, and cost no more.
    if (mp <= k_lift_ratio * ms && ms <= k_lift_ratio * mp) return {};
    const float d = std::clamp((piece_height_[a] - piece_height_[b]) / (k_lift_span * scale_.edge), -1.0f, 1.0f);
    Lift out;
    if (d > 0.0f && mp > ms) out.surface = std::pow(ms / mp, d);
    if (d < 0.0f && ms > mp) out.particle = std::pow(mp / ms, -d);
    return out;
}

template <class Real>
void ContactSolverT<Real>::note_push(const SoftBodyT<Real>& body, uint32_t i, const std::array<uint32_t, 3>& k, float depth) {
    const float thickness = scale_.thickness;
    const SleepState& st = body.sleep;
    if (!(depth > thickness) || st.sleeping == 0) return;
    for (uint32_t j : {i, k[0], k[1], k[2]}) {
        if (j >= st.held_w.size() || !(st.held_w[j] > 0.0f)) continue;
        const uint32_t piece = body.piece_of_particle[j];
        if (std::find(pressed_sleepers_.begin(), pressed_sleepers_.end(), piece) == pressed_sleepers_.end()) pressed_sleepers_.push_back(piece);
    }
}

namespace {

// Candidate `ct` against the triangle of particles `k` as they lie now: its unit normal and where
// the particle is over it, or nothing where the particle is clear of its plane or beside it (past
// `beside` of it: over a convex edge or corner a neighbour takes over, and pushing along this
// triangle's normal there would shove the particle sideways off a face it rests on).
struct Touch {
    Vec3f normal;
    Over over;
};
template <class Real>
std::optional<Touch> touch_of(const ParticlesT<Real>& p, const Contact& ct, const std::array<uint32_t, 3>& k, float beside) {
    const Vec3f xi = pos3(p.x[ct.particle]);
    const Vec3f a = pos3(p.x[k[0]]), b = pos3(p.x[k[1]]), c = pos3(p.x[k[2]]);
    const Vec3f nf = unit_normal(a, b, c);
    // Clear of the plane: clear of the triangle (most candidates, most iterations).
    if (nf.isZero() || ct.side * (xi - a).dot(nf) >= ct.thickness) return std::nullopt;
    const Over o = over_triangle(xi, a, b, c, nf);
    if (o.lateral > beside) return std::nullopt;
    return Touch{nf, o};
}

// How far inside the thickness the candidate's particle lay when the substep began, over the
// triangle's plane then.
template <class Real>
float start_overlap(const ParticlesT<Real>& p, const Contact& ct, const std::array<uint32_t, 3>& k) {
    const Vec3f a0 = pos3(p.x_prev[k[0]]), n0 = unit_normal(a0, pos3(p.x_prev[k[1]]), pos3(p.x_prev[k[2]]));
    return n0.isZero() ? 0.0f : std::max(0.0f, ct.thickness - ct.side * (pos3(p.x_prev[ct.particle]) - a0).dot(n0));
}

} // namespace

template <class Real>
float ContactSolverT<Real>::project_rigid(ParticlesT<Real>& p, const ContactSettings& s, const Contact& ct,
                                          const std::array<uint32_t, 3>& k, Sides sd, Lift lift) {
    const std::optional<Touch> t = touch_of(p, ct, k, k_over * scale_.edge);
    if (!t) return 0.0f;
    const Over& o = t->over;
    const float C = ct.side * o.height - ct.thickness;
    if (C >= 0.0f) return 0.0f;
    separate(p, s, ct.particle, k, {o.wa, o.wb, o.wc}, sd, ct.side * t->normal, -C, std::min(start_overlap(p, ct, k), -C), lift);
    return -C;
}

template <class Real>
void ContactSolverT<Real>::project_soft(const SoftBodyT<Real>& body, const ContactSettings& s, const Contact& ct, const Corners& ck) {
    const ParticlesT<Real>& p = body.particles;
    const uint32_t i = ct.particle, ia = ck.ia, ib = ck.ib, ic = ck.ic;
    const Lift l = lift(body, i, ia);
    const Real up_w = Real(l.particle), down_w = Real(l.surface);
    const Real wp = up_w * p.w[i], wa = down_w * p.w[ia], wb = down_w * p.w[ib], wc = down_w * p.w[ic];
    const std::optional<Touch> t = touch_of(p, ct, {ia, ib, ic}, k_over * scale_.edge);
    if (!t) return;
    const Over& o = t->over;
    const Real C = Real(ct.side) * Real(o.height) - Real(ct.thickness);
    if (C >= Real(0)) return;
    const Real ua = Real(o.wa), ub = Real(o.wb), uc = Real(o.wc);
    const Real denom = wp + ua * ua * wa + ub * ub * wb + uc * uc * wc;
    if (!(denom > Real(0))) return;
    const Vec4<Real> n = Real(ct.side) * to4<Real>(t->normal);
    const Real depth = -C;
    note_push(body, i, {ia, ib, ic}, float(depth));
    // Friction on the particle's motion relative to the surface point since the substep began;
    // the push along n leaves its tangential part as it is.
    const Vec4<Real> rel = (p.x[i] - p.x_prev[i]) - ua * (p.x[ia] - p.x_prev[ia]) - ub * (p.x[ib] - p.x_prev[ib]) - uc * (p.x[ic] - p.x_prev[ic]);
    const Vec4<Real> tangential = rel - rel.dot(n) * n;
    const Vec4<Real> push = (depth / denom) * n;
    const Vec4<Real> d = push - (friction_share(s.friction, tangential.norm(), depth) / denom) * tangential;
    // Of the depth, what lay within the thickness when the substep began is taken out of the
    // start positions too, as separate() does for a stiff side and for the same reason: the two
    // sides of a cut begin inside each other's thickness, and pushed apart as motion they fly.
    const Vec4<Real> settle = Real(std::clamp(start_overlap(p, ct, {ia, ib, ic}) / float(depth), 0.0f, 1.0f)) * push;
    add_soft(i, wp * d, wp * settle);
    add_soft(ia, -(wa * ua) * d, -(wa * ua) * settle), add_soft(ib, -(wb * ub) * d, -(wb * ub) * settle);
    add_soft(ic, -(wc * uc) * d, -(wc * uc) * settle);
}

template <class Real>
void ContactSolverT<Real>::add_soft(uint32_t i, const Vec4<Real>& d, const Vec4<Real>& settle) {
    if (d.isZero()) return;
    if (soft_count_[i]++ == 0) soft_touched_.push_back(i), soft_delta_[i] = d, soft_settle_[i] = settle;
    else soft_delta_[i] += d, soft_settle_[i] += settle;
}

template <class Real>
void ContactSolverT<Real>::apply_soft(ParticlesT<Real>& p) {
    // Each particle's mean correction: every candidate it meets says where it should go, and a
    // sum would push it as far again for each (a corner under three particles thrice).
    for (const uint32_t i : soft_touched_) {
        const Real share = Real(1) / Real(soft_count_[i]);
        p.x[i] += share * soft_delta_[i], p.x_prev[i] += share * soft_settle_[i];
        soft_count_[i] = 0;
    }
    soft_touched_.clear();
}

template <class Real>
void ContactSolverT<Real>::project(SoftBodyT<Real>& body, const ContactSettings& s, bool stiff_bodies) {
    if (contacts_.empty() && seam_pairs_.empty()) return;
    ParticlesT<Real>& p = body.particles;
    const bool rigid = stiff_bodies && rigid_.any();
    if (rigid && !rigid_ready_) touch_clusters(body), rigid_.begin(body.shapes, p, touch_), rigid_ready_ = true;
    if (!heights_ready_) take_heights(body);
    if (soft_count_.size() != p.size()) soft_count_.assign(p.size(), 0), soft_delta_.resize(p.size()), soft_settle_.resize(p.size());
    update_faces(p);
    project_seams(body, s, rigid);
    for (const Contact& ct : contacts_) {
        const uint32_t i = ct.particle;
        const Corners ck = corners_of(body, ct.triangle);
        const uint32_t ia = ck.ia, ib = ck.ib, ic = ck.ic;
        if (rigid) {
            if (const Sides sd = pair_sides_[size_t(&ct - contacts_.data())]; sd.any()) {
                note_push(body, i, {ia, ib, ic}, project_rigid(p, s, ct, {ia, ib, ic}, sd, lift(body, i, ia)));
                continue;
            }
        }
        project_soft(body, s, ct, ck);
    }
    apply_soft(p);
    if (rigid) rigid_.finish(body.shapes, p);
}

template float mean_rest_edge<float>(const SoftBodyT<float>&);
template float mean_rest_edge<double>(const SoftBodyT<double>&);
template bool encloses_face<float>(const std::vector<uint32_t>&, const Vec4ArrayT<float>&, const std::vector<Vec3f>&);
template bool encloses_face<double>(const std::vector<uint32_t>&, const Vec4ArrayT<double>&, const std::vector<Vec3f>&);
template std::vector<std::array<uint32_t, 3>> face_triangles<float>(const std::vector<uint32_t>&, const Vec4ArrayT<float>&, std::span<const uint32_t>,
                                                                    std::vector<uint8_t>*);
template std::vector<std::array<uint32_t, 3>> face_triangles<double>(const std::vector<uint32_t>&, const Vec4ArrayT<double>&, std::span<const uint32_t>,
                                                                     std::vector<uint8_t>*);
template class ContactSolverT<float>;
template class ContactSolverT<double>;

} // namespace pbdsplat::sim
