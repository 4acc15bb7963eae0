#include "sim/soft_body.h"

#include <algorithm>
#include <cmath>

#include "mesh/reorder.h"
#include "mesh/topology.h"
#include "sim/constraint_order.h"
#include "sim/enclosure.h"
#include "sim/integrate.h"
#include "sim/volume.h"

namespace pbdsplat::sim {

namespace {

// Openings (the vector areas of its boundary loops) over the surface area of the piece, above
// which a part is a shell: a hemisphere has 0.5, the teapot's lid 0.79, Suzanne's eyes 0.61,
// while the teapot's body (0.16, open at the lid's rim) and the bunny's scan holes (0.018) are
// closed enough to hold air under their caps.
constexpr double k_shell_opening_ratio = 0.4;

double opening_ratio(const mesh::TriangleMesh& m, std::span<const uint32_t> piece_of_particle, const VolumeConstraint& v) {
    if (v.cap_loops.empty()) return 0.0;
    const auto position = [&](uint32_t i) -> Vec3d { return m.positions[i].cast<double>(); };
    double openings = 0.0, area = 0.0;
    for (const auto& loop : v.cap_loops) openings += loop_area(loop, position);
    for (const mesh::Triangle& t : m.triangles)
        if (piece_of_particle[t[0]] == v.piece)
            area += 0.5 * (m.positions[t[1]] - m.positions[t[0]]).cast<double>().cross((m.positions[t[2]] - m.positions[t[0]]).cast<double>()).norm();
    return area > 0.0 ? openings / area : 0.0;
}

} // namespace

uint32_t label_pieces(std::span<const mesh::Triangle> triangles, size_t particle_count, std::vector<uint32_t>& piece_of_particle) {
    std::vector<uint32_t> comp;
    const uint32_t count = mesh::vertex_components(triangles, particle_count, comp);
    piece_of_particle.assign(particle_count, k_no_piece);
    for (size_t f = 0; f < triangles.size(); ++f)
        for (uint32_t v : triangles[f]) piece_of_particle[v] = comp[f];
    return count;
}

std::vector<size_t> piece_triangle_counts(std::span<const mesh::Triangle> triangles, std::span<const uint32_t> piece_of_particle,
                                          size_t pieces) {
    std::vector<size_t> count(pieces, 0);
    for (const mesh::Triangle& t : triangles)
        if (const uint32_t p = piece_of_particle[t[0]]; p < pieces) ++count[p];
    return count;
}

template <class Real>
void rebuild_derived(SoftBodyT<Real>& b) {
    const size_t n = b.particle_count();
    b.distance_groups = make_distance_groups(b.distance, n);
    b.distance_lambda.assign(b.distance.size(), Real(0));
    b.rings = build_vertex_rings(b.triangles, n);
    if (b.rest_positions.size() == n) set_rest_ring_areas(b.rings, b.rest_positions);
    // A volume constraint follows its piece to the piece's new label, found through one of its
    // particles (labels that do not fit the body are taken as already fresh).
    std::vector<uint32_t> particle_of_volume(b.volumes.size(), UINT32_MAX);
    if (b.piece_of_particle.size() == n) {
        std::vector<uint32_t> first(b.pieces, UINT32_MAX);
        for (uint32_t i = 0; i < n; ++i)
            if (const uint32_t p = b.piece_of_particle[i]; p < first.size() && first[p] == UINT32_MAX) first[p] = i;
        for (size_t k = 0; k < b.volumes.size(); ++k)
            if (b.volumes[k].piece < first.size()) particle_of_volume[k] = first[b.volumes[k].piece];
    }
    b.pieces = label_pieces(b.triangles, n, b.piece_of_particle);
    for (size_t k = 0; k < b.volumes.size(); ++k)
        if (particle_of_volume[k] != UINT32_MAX) b.volumes[k].piece = b.piece_of_particle[particle_of_volume[k]];
    // Kept in piece order: a cut finds a reached piece's constraint by bisection.
    std::stable_sort(b.volumes.begin(), b.volumes.end(), [](const VolumeConstraint& x, const VolumeConstraint& y) { return x.piece < y.piece; });
    b.normals.resize(n, Vec3f(0.0f, 1.0f, 0.0f));
    rebuild_shape_clusters(b);
}

template <class Real>
void rebuild_shape_clusters(SoftBodyT<Real>& b) {
    b.shapes.clear();
    if (!b.shape_matching) return;
    std::vector<float> w(b.particles.w.size());
    for (size_t i = 0; i < w.size(); ++i) w[i] = float(b.particles.w[i]);
    std::vector<std::pair<uint32_t, uint32_t>> welds;
    welds.reserve(b.welds.size());
    for (const DistanceConstraint& c : b.welds)
        if (c.alive()) welds.emplace_back(c.i, c.j);
    b.shapes = build_shape_clusters(b.triangles, b.rest_positions, w, welds);
    const std::vector<float>& own = b.model_shape_stiffness;
    if (own.empty() || b.model_of_particle.size() != w.size()) return;
    // A cluster never spans two models: they share no triangle, and welds join parts of one.
    for (ShapeCluster& c : b.shapes) {
        const uint32_t m = c.particles.empty() ? 0u : b.model_of_particle[c.particles.front()];
        c.own_stiffness = m < own.size() ? own[m] : -1.0f;
    }
}
template void rebuild_shape_clusters<float>(SoftBodyT<float>&);
template void rebuild_shape_clusters<double>(SoftBodyT<double>&);
template void rebuild_derived<float>(SoftBodyT<float>&);
template void rebuild_derived<double>(SoftBodyT<double>&);

bool reserve_headroom(SoftBody& b, float fraction) {
    const size_t n = b.particle_count(), t = b.triangles.size(), e = b.distance.size();
    const auto room = [fraction](size_t size) { return size + size_t(float(size) * fraction) + 64; };
    // Grown only when less than half the asked-for room is left: no churn on every edit.
    const auto low = [fraction](size_t size, size_t capacity) { return capacity < size + size_t(float(size) * fraction * 0.5f) + 32; };
    bool grew = false;
    auto reserve = [&](auto& v, size_t size) {
        if (low(size, v.capacity())) v.reserve(room(size)), grew = true;
    };
    reserve(b.particles.x, n), reserve(b.particles.x_prev, n), reserve(b.particles.v, n), reserve(b.particles.w, n);
    reserve(b.rest_positions, n), reserve(b.normals, n), reserve(b.piece_of_particle, n);
    if (!b.colors.empty()) reserve(b.colors, n);
    if (!b.texcoords.empty()) reserve(b.texcoords, n);
    reserve(b.triangles, t);
    reserve(b.distance, e), reserve(b.distance_lambda, e), reserve(b.distance_groups.colour, e);
    reserve(b.volumes, b.volumes.size());  // a piece cut off adds its constraint at the end
    auto reserve_lists = [&](auto& lists) {
        if (low(n, lists.key_capacity()) || low(lists.pool_size(), lists.pool_capacity()))
            lists.reserve(room(n), room(lists.pool_size())), grew = true;
    };
    reserve_lists(b.distance_groups.of_particle), reserve_lists(b.rings.ring), reserve_lists(b.rings.triangles);
    return grew;
}

SoftBodyT<double> to_double(const SoftBody& b) {
    SoftBodyT<double> d;
    const size_t n = b.particle_count();
    d.particles.resize(n);
    for (size_t i = 0; i < n; ++i) {
        d.particles.x[i] = b.particles.x[i].cast<double>();
        d.particles.x_prev[i] = b.particles.x_prev[i].cast<double>();
        d.particles.v[i] = b.particles.v[i].cast<double>();
        d.particles.w[i] = double(b.particles.w[i]);
    }
    d.normals = b.normals;
    d.triangles = b.triangles;
    d.rings = b.rings;
    d.distance = b.distance;
    d.distance_groups = b.distance_groups;
    d.distance_lambda.assign(b.distance_lambda.size(), 0.0);
    d.sleep = b.sleep;  // the held masses go with the zeros they stand for
    d.welds = b.welds;
    d.volumes = b.volumes;
    d.piece_of_particle = b.piece_of_particle;
    d.pieces = b.pieces;
    d.shape_matching = b.shape_matching;
    d.shapes = b.shapes;
    d.rest_positions = b.rest_positions;
    d.colors = b.colors;
    d.texcoords = b.texcoords;
    d.model_of_particle = b.model_of_particle;
    d.model_shape_stiffness = b.model_shape_stiffness;
    d.model_damping = b.model_damping;
    d.model_deform_damping = b.model_deform_damping;
    d.model_stretch_stiffness = b.model_stretch_stiffness;
    d.part_of_particle = b.part_of_particle;
    d.enclosed_parts = b.enclosed_parts;
    return d;
}

namespace {
// Masses: lumped from a third of each incident triangle's area, or uniform; into inverse masses.
core::Status set_masses(const mesh::TriangleMesh& m, const SoftBodyDesc& desc, SoftBody& b) {
    const size_t n = m.positions.size();
    std::vector<double> mass(n, 0.0);
    if (desc.mass_mode == MassMode::area) {
        for (const auto& t : m.triangles) {
            const double area = 0.5 * double((m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).norm());
            for (uint32_t v : t) mass[v] += area / 3.0;
        }
    } else {
        std::fill(mass.begin(), mass.end(), 1.0);
    }
    double total = 0.0;
    for (double x : mass) total += x;
    if (!(total > 0.0)) return core::make_error("the mesh has no area to spread the mass over");
    for (size_t i = 0; i < n; ++i) {
        // A vertex with (almost) no area still gets a sane mass: at least 1 % of the average.
        const double mi = std::max(mass[i], 0.01 * total / double(n)) * double(desc.total_mass) / total;
        b.particles.w[i] = float(1.0 / mi);
    }
    return core::Status::success();
}

// One volume constraint per closed (or virtually capped) piece, its loops capped at load.
void add_volume_constraints(const mesh::TriangleMesh& m, const SoftBodyDesc& desc, SoftBody& b) {
    const std::vector<size_t> triangle_count = piece_triangle_counts(b.triangles, b.piece_of_particle, b.pieces);
    b.volumes.resize(b.pieces);
    for (uint32_t c = 0; c < b.pieces; ++c) b.volumes[c].piece = c, b.volumes[c].triangle_count = triangle_count[c];
    for (auto& loop : mesh::boundary_loops(m)) b.volumes[b.piece_of_particle[loop[0]]].cap_loops.push_back(std::move(loop));
    for (size_t k = 0; k < b.volumes.size(); ++k) {
        VolumeConstraint& v = b.volumes[k];
        v.pressure = desc.pressure;
        v.compliance = desc.volume_compliance;
        v.sealed_below = uint32_t(m.positions.size());
        v.rest_volume = b.volume(k);
    }
    // A flat or inside-out component has no volume to keep: it gets no constraint.
    std::erase_if(b.volumes, [](const VolumeConstraint& v) { return !(v.rest_volume > 0.0); });
    // An open part whose openings are a large share of its surface (a dish, a lid, a
    // hemispherical eye) is a shell, not a balloon: its virtual caps would span the openings
    // and hold air the part cannot hold.
    std::erase_if(b.volumes, [&](const VolumeConstraint& v) { return opening_ratio(m, b.piece_of_particle, v) > k_shell_opening_ratio; });
}
} // namespace

core::Result<SoftBody> make_soft_body(mesh::TriangleMesh m, const SoftBodyDesc& desc) {
    if (m.triangles.empty()) return core::make_error("a soft body needs at least one triangle");
    if (!(desc.total_mass > 0.0f) || !std::isfinite(desc.total_mass)) return core::make_error("total mass must be positive");
    if (!(desc.pressure > 0.0f) || !std::isfinite(desc.pressure)) return core::make_error("pressure factor must be positive");
    if (desc.reorder) mesh::reorder_for_locality(m);

    SoftBody b;
    const size_t n = m.positions.size();
    b.particles.resize(n);
    for (size_t i = 0; i < n; ++i) b.particles.x[i] = b.particles.x_prev[i] = to4(m.positions[i]);
    b.rest_positions = m.positions;
    b.colors = m.colors;
    b.triangles = m.triangles;
    b.shape_matching = desc.shape_matching;

    PBDSPLAT_TRY(set_masses(m, desc, b));
    for (const mesh::Edge& e : mesh::unique_edges(m)) {
        const float rest = (m.positions[e.a] - m.positions[e.b]).norm();
        b.distance.push_back({e.a, e.b, rest, desc.stretch_compliance});
    }


    b.pieces = label_pieces(b.triangles, n, b.piece_of_particle);
    if (desc.volume) add_volume_constraints(m, desc, b);
    rebuild_derived(b);
    update_normals(b.rings, b.particles.x, b.normals, 0, n);
    b.part_of_particle = b.piece_of_particle;
    b.model_of_particle.assign(n, 0);  // one mesh, one model
    b.enclosed_parts = find_enclosed_parts(b);
    return b;
}

} // namespace pbdsplat::sim
