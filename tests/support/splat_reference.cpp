#include "support/splat_reference.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <Eigen/Eigenvalues>

#include "render/frame_uniforms.h"

namespace pbdsplat::test {

namespace {
struct Footprint2D {
    Vec3f centre;         // view space
    Eigen::Matrix2f inv;  // inverse projected covariance, view-plane units at the centre's depth
    Vec3f albedo;
    float alpha = 1.0f;
    Eigen::Matrix2f axes;  // columns: unit principal directions
    Vec2f lengths;         // standard deviations along them
    float s0 = 0.0f;       // the world standard deviation of a round splat
};

// `axes`: null for a round splat; `pixel`: a pixel's size in view-plane units at unit depth;
// `paper_kappa`: the disc's half-size in standard deviations, 0 for the Gaussian footprint.
Footprint2D project(const splat::GaussianRecord& r, const Mat4f& view, float scale_multiplier, const splat::GaussianShape* shape,
                    float pixel, float paper_kappa) {
    Footprint2D f;
    const Vec3f world(r.position[0], r.position[1], r.position[2]);
    f.centre = (view * world.homogeneous()).head<3>();
    const float s0 = splat::half_to_float(r.scale_half) * scale_multiplier;
    f.s0 = s0;
    // Eq. 14: the Gaussian's axes (s0 * e_k for a round one) seen in view space, each pushed
    // through the perspective Jacobian at the centre (a' = a.xy + p a.z).
    const Eigen::Matrix3f world_axes = shape ? Eigen::Matrix3f(splat::shape_axes(*shape)) : Eigen::Matrix3f(s0 * Eigen::Matrix3f::Identity());
    const Vec2f p = f.centre.head<2>() / -f.centre.z();
    Eigen::Matrix2f cov = Eigen::Matrix2f::Zero();
    const Eigen::Matrix3f rot = view.topLeftCorner<3, 3>();
    for (int k = 0; k < 3; ++k) {
        const Vec3f a = rot * world_axes.col(k);
        const Vec2f ap = a.head<2>() + p * a.z();
        cov += ap * ap.transpose();
    }
    const float px = pixel * -f.centre.z();  // a pixel, in view-plane units at the centre's depth
    // Gaussians: 3D Gaussian splatting's 0.3 pixel^2 low-pass. Discs: none, but a disc seen
    // edge-on is kept a line at least a pixel wide (half-size 0.5 px), never wider than long.
    if (shape && paper_kappa == 0.0f) cov += Eigen::Matrix2f::Identity() * 0.3f * px * px;
    // Principal axes, the longer first (the quad's r of eq. 19, along which sigma_x applies).
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2f> eig(cov);
    f.axes << eig.eigenvectors().col(1), eig.eigenvectors().col(0);
    f.lengths = Vec2f(eig.eigenvalues()(1), eig.eigenvalues()(0)).cwiseSqrt();
    if (shape && paper_kappa > 0.0f) f.lengths.y() = std::max(f.lengths.y(), std::min(f.lengths.x(), 0.5f * px / paper_kappa));
    f.inv = cov.inverse();
    f.albedo = Vec3f(r.color[0], r.color[1], r.color[2]) / 255.0f;
    const float fade = float(r.color[3]) / 255.0f;
    f.alpha = fade / (1.0f + std::exp(-splat::half_to_float(r.opacity_half)));
    return f;
}
} // namespace

namespace {
// The mesh's distance along the view axis where `ray` (view space, from the eye) first meets
// it, 0 where it misses; `edge` is set where the ray passes within `slack` (barycentric) of a
// triangle's rim without a clear answer: hit loosely but not strictly, or the reverse.
float mesh_depth(const std::vector<std::array<Vec3f, 3>>& tris, const Vec3f& ray, float slack, bool& edge) {
    float nearest = 0.0f;
    for (const auto& t : tris) {
        const Vec3f e1 = t[1] - t[0], e2 = t[2] - t[0];
        const Vec3f p = ray.cross(e2);
        const float det = e1.dot(p);
        if (std::abs(det) < 1e-12f) continue;
        const Vec3f s = -t[0];
        const float u = s.dot(p) / det;
        const Vec3f q = s.cross(e1);
        const float v = ray.dot(q) / det, along = e2.dot(q) / det;
        if (!(along > 0.0f)) continue;
        const float least = std::min({u, v, 1.0f - u - v});
        if (std::abs(least) < slack) edge = true;
        if (least < 0.0f) continue;
        const float depth = -(ray * along).z();
        if (nearest == 0.0f || depth < nearest) nearest = depth;
    }
    return nearest;
}

// Whether a fragment at view depth `depth` (along the axis) passes the occluders at a pixel
// whose mesh depth is `surface` (0: not seen there; `beside`: the mesh is seen next to it).
bool occluded_keeps(float depth, float surface, bool beside, float tolerance, float& margin) {
    if (surface <= 0.0f) return beside;
    const float off = depth - surface;  // > 0: behind the surface
    margin = std::min({margin, std::abs(off - tolerance) / tolerance, std::abs(off + 2.0f * tolerance) / tolerance});
    return off <= tolerance && off >= -2.0f * tolerance;
}

// What the occluders decide at one pixel: keep(depth) for a fragment there.
struct OccluderAt {
    bool on = false;
    float surface = 0.0f, tolerance = 0.0f;
    bool beside = false;
};

// The occluders' depth at every pixel, and where a pixel lies on the mesh's outline (not judged).
struct OccluderImage {
    uint32_t width = 0, height = 0;
    std::vector<float> surface;
    std::vector<uint8_t> outline;

    // What the occluders decide at pixel (x, y): off when there are none.
    OccluderAt at(uint32_t x, uint32_t y, float tolerance, float& margin) const {
        OccluderAt occ;
        if (surface.empty()) return occ;
        occ.on = true;
        occ.surface = surface[size_t(y) * width + x];
        occ.tolerance = tolerance;
        const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
        bool unsure = outline[size_t(y) * width + x] != 0;
        for (int k = 0; k < 4; ++k) {
            const int nx = std::clamp(int(x) + dx[k], 0, int(width) - 1), ny = std::clamp(int(y) + dy[k], 0, int(height) - 1);
            occ.beside |= surface[size_t(ny) * width + size_t(nx)] > 0.0f;
            unsure |= outline[size_t(ny) * width + size_t(nx)] != 0;
        }
        if (unsure) margin = 0.0f;
        return occ;
    }
};

template <class RayAt>
OccluderImage occluder_depths(const OccluderMesh& mesh, const Mat4f& view, uint32_t width, uint32_t height, const RayAt& ray_at) {
    std::vector<std::array<Vec3f, 3>> tris;
    for (const auto& t : mesh.triangles) {
        std::array<Vec3f, 3> v;
        for (int k = 0; k < 3; ++k) v[k] = (view * Vec4f(mesh.x[t[k]].head<3>().homogeneous())).head<3>();
        tris.push_back(v);
    }
    OccluderImage img{width, height, std::vector<float>(size_t(width) * height), std::vector<uint8_t>(size_t(width) * height)};
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            bool edge = false;
            img.surface[size_t(y) * width + x] = mesh_depth(tris, ray_at(int(x), int(y)), 0.02f, edge);
            img.outline[size_t(y) * width + x] = edge;
        }
    return img;
}

// Normalised blending at one pixel, from its definition (render/frame_inputs.h, "Blend"): a
// splat counts where its Gaussian reaches at least 1/255 and, when kappa > 0, within kappa
// standard deviations of its centre; of those, the front surface: no farther than the nearest
// opaque core (alpha >= depth_min_alpha) pushed back by depth_push of its own standard
// deviations. Each adds w = -ln(1 - alpha) of its colour; the mean shows over the background
// with coverage 1 - exp(-4 sum w). Round splats facing the eye only (no inside layer).
Vec3f normalised_pixel(const std::vector<Footprint2D>& splats, const Vec3f& ray, const render::SplatStyle& style,
                       const Vec3f& background, const OccluderAt& occ, float& margin) {
    // The accumulation stage's alpha: the Gaussian inside its carrier, down to 1/255.
    const auto alpha_at = [&](const Footprint2D& f) {
        const Vec3f hit = ray * (f.centre.z() / ray.z());
        const Vec2f d = (hit - f.centre).head<2>();
        const float a = std::min(f.alpha * std::exp(-0.5f * d.dot(f.inv * d)), 1.0f);
        if (!(a >= 1.0f / 255.0f)) return 0.0f;
        // Within kappa standard deviations (a disc; the sharpness only scales the falloff).
        const Vec2f q = f.axes.transpose() * d;
        if (style.kappa > 0.0f && Vec2f(q.x() / f.lengths.x(), q.y() / f.lengths.y()).squaredNorm() > style.kappa * style.kappa)
            return 0.0f;
        return a;
    };
    float front = -1e30f;  // view z of the visibility pass's depth (the camera looks down -z)
    for (const Footprint2D& f : splats) {
        if (occ.on) break;  // the mesh is the visibility, not the splats' cores
        const float pushed = f.centre.z() - style.depth_push * f.s0;
        const Vec3f hit = ray * (pushed / ray.z());
        const Vec2f d = (hit - Vec3f(f.centre.x(), f.centre.y(), pushed)).head<2>();
        const float a = f.alpha * std::exp(-0.5f * d.dot(f.inv * d));
        // How near the core's edge: where the test could go either way, the pixel is not judged.
        margin = std::min(margin, std::abs(a - style.depth_min_alpha) / style.depth_min_alpha);
        if (a >= style.depth_min_alpha) front = std::max(front, pushed);
    }
    Vec3f sum = Vec3f::Zero();
    float weight = 0.0f;
    for (const Footprint2D& f : splats) {
        if (f.centre.z() < front) continue;  // behind the front surface
        if (occ.on && !occluded_keeps(-f.centre.z(), occ.surface, occ.beside, occ.tolerance, margin)) continue;
        const float a = alpha_at(f);
        if (a == 0.0f) continue;
        const float w = -std::log(1.0f - std::min(a, 0.996f));
        sum += w * f.albedo;
        weight += w;
    }
    if (!(weight > 1e-4f)) return background;
    const float coverage = 1.0f - std::exp(-4.0f * weight);
    return sum / weight * coverage + background * (1.0f - coverage);
}
} // namespace

std::vector<ReferencePixel> render_reference(const std::vector<splat::GaussianRecord>& records,
                                             const render::FrameInputs& frame, uint32_t width, uint32_t height,
                                             const std::vector<splat::GaussianShape>& shapes, const OccluderMesh* occluders) {
    const auto u = render::make_frame_uniforms(frame, width, height);
    Mat4f view, proj;
    std::memcpy(view.data(), u.view.m, sizeof(u.view.m));
    std::memcpy(proj.data(), u.proj.m, sizeof(u.proj.m));
    const Mat4f unproject = proj.inverse();
    const render::SplatStyle& style = frame.style;
    std::vector<Footprint2D> splats;
    const float pixel = 2.0f * std::tan(math::radians(frame.camera.fov_y_degrees) * 0.5f) / float(height);
    const float kappa = render::paper_kappa(style);
    const bool paper = style.footprint == render::Footprint::paper;
    for (size_t i = 0; i < records.size(); ++i)
        splats.push_back(project(records[i], view, style.scale_multiplier, shapes.empty() ? nullptr : &shapes[i], pixel, paper ? kappa : 0.0f));
    const Vec2f sharp = style.sharpness;
    const auto ray_at = [&](int x, int y) {
        const Vec2f ndc((float(x) + 0.5f) / float(width) * 2.0f - 1.0f, (float(y) + 0.5f) / float(height) * 2.0f - 1.0f);
        const Vec4f v = unproject * Vec4f(ndc.x(), ndc.y(), 0.5f, 1.0f);
        return Vec3f(v.head<3>() / v.w());  // from the eye at the origin
    };
    const OccluderImage occluder_image =
        occluders && style.mesh_occluders ? occluder_depths(*occluders, view, width, height, ray_at) : OccluderImage{};
    std::vector<ReferencePixel> out(size_t(width) * height);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const Vec3f ray = ray_at(int(x), int(y));
            ReferencePixel& px = out[size_t(y) * width + x];
            const OccluderAt occ = occluder_image.at(x, y, style.occluder_tolerance, px.rim_margin);
            Vec3f c = frame.background.head<3>();
            float nearest = -1e30f;
            if (style.footprint == render::Footprint::paper) {
                // Eqs. 19-23: quad coordinates over the half-sizes kappa * l, divided by sigma;
                // the nearest covering disc wins (depth test and write).
                std::vector<float> radius(splats.size());
                for (size_t i = 0; i < splats.size(); ++i) {
                    const Footprint2D& f = splats[i];
                    // Where the ray meets the quad's plane (constant view depth), from the centre.
                    const Vec3f hit = ray * (f.centre.z() / ray.z());
                    const Vec2f q = f.axes.transpose() * (hit - f.centre).head<2>();
                    radius[i] = Vec2f(q.x() / (kappa * f.lengths.x()) / sharp.x(), q.y() / (kappa * f.lengths.y()) / sharp.y()).norm();
                    if (occ.on && !occluded_keeps(-f.centre.z(), occ.surface, occ.beside, occ.tolerance, px.rim_margin)) continue;
                    if (radius[i] <= 1.0f && f.centre.z() > nearest) {
                        nearest = f.centre.z();
                        c = f.albedo;
                    }
                }
                for (size_t i = 0; i < splats.size(); ++i)
                    if (splats[i].centre.z() >= nearest) px.rim_margin = std::min(px.rim_margin, std::abs(radius[i] - 1.0f));
            } else if (style.blend == render::Blend::normalised) {
                c = normalised_pixel(splats, ray, style, c, occ, px.rim_margin);
            } else {
                for (const Footprint2D& f : splats) {
                    const Vec3f hit = ray * (f.centre.z() / ray.z());
                    const Vec2f d = (hit - f.centre).head<2>();
                    const float m2 = d.dot(f.inv * d);  // squared Mahalanobis distance, in sigmas
                    const float a = std::min(f.alpha * std::exp(-0.5f * m2), 1.0f);
                    if (a < 1.0f / 255.0f) continue;  // the cut-off
                    if (style.blend == render::Blend::additive) c += a * f.albedo;
                    else c = a * f.albedo + (1.0f - a) * c;
                }
            }
            px.color = c.cwiseMin(1.0f).cwiseMax(0.0f);
        }
    return out;
}

} // namespace pbdsplat::test
