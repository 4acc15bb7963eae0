#include "scene/ply_view.h"

#include <algorithm>
#include <cmath>

#include "render/cpu_shading.h"
#include "splat/sort.h"

namespace pbdsplat::scene {

render::FrameInputs ply_view(std::span<const splat::GaussianRecord> records, bool lit) {
    Vec3f lo = Vec3f::Constant(1e30f), hi = Vec3f::Constant(-1e30f);
    for (const auto& r : records) {
        // Each Gaussian's own reach counts: a file of one splat still has a size to frame.
        const Vec3f p(r.position[0], r.position[1], r.position[2]);
        const float reach = 3.0f * std::abs(splat::half_to_float(r.scale_half));
        const Vec3f pad = Vec3f::Constant(std::isfinite(reach) ? reach : 0.0f);
        lo = lo.cwiseMin(p - pad), hi = hi.cwiseMax(p + pad);
    }
    if (records.empty()) lo = hi = Vec3f::Zero();
    render::FrameInputs frame;
    const Vec3f centre = 0.5f * (lo + hi);
    const float diag = std::max((hi - lo).norm(), 1e-6f);
    frame.camera.target = centre;
    frame.camera.eye = centre + Vec3f(0.0f, 0.25f, 1.2f) * diag;
    frame.camera.z_near = 0.01f * diag;
    frame.camera.z_far = 10.0f * diag;
    frame.style.footprint = render::Footprint::gaussian;
    frame.style.order = render::SplatOrder::cpu;
    render::Lighting& l = frame.lighting;
    l.environment.center = centre;
    if (lit) return frame;
    l.intensity = 0.0f;
    l.specular = 0.0f;
    l.ambient = Vec3f::Ones();
    l.environment.sampling = render::EnvSampling::off;
    l.lights.clear();
    return frame;
}

bool ply_sort_on_gpu(const std::string& device_type) { return device_type != "cpu"; }

render::RendererOptions ply_renderer_options(const splat::PlyGaussians& file, uint32_t width, uint32_t height, bool gpu_sort) {
    render::RendererOptions o;
    o.width = width;
    o.height = height;
    o.max_splats = uint32_t(std::max<size_t>(1, file.records.size()));
    o.frames_in_flight = 1;
    o.anisotropic = !file.shapes.empty();
    o.sh_degree = file.sh.empty() ? 0 : file.sh_degree;
    o.gpu_sort = gpu_sort;
    return o;
}

void sort_ply(splat::PlyGaussians& file, const render::FrameInputs& frame) {
    splat::SortScratch scratch;
    const render::Camera& c = frame.camera;
    splat::sort_far_to_near(file.records, file.shapes, math::look_at(c.eye, c.target, c.up), scratch);
    splat::reorder_like_last_sort(scratch, file.sh);
}

void order_ply(splat::PlyGaussians& file, render::FrameInputs& frame, bool gpu_sort) {
    if (gpu_sort) frame.style.order = render::SplatOrder::gpu;
    else sort_ply(file, frame);
}

void bake_shading(const render::FrameInputs& frame, const render::EnvironmentMap& map, std::span<splat::GaussianRecord> records) {
    render::CpuShading shading;
    shading.lighting = &frame.lighting;
    shading.map = &map;
    shading.sh = render::irradiance_sh(map);
    shading.eye = frame.camera.eye;
    shading.opaque_discs = frame.style.footprint == render::Footprint::paper;
    for (splat::GaussianRecord& r : records) {
        const Vec3f albedo = Vec3f(r.color[0], r.color[1], r.color[2]) / 255.0f;
        const Vec3f lit = render::shade_cpu(shading, albedo, splat::decode_octahedral(r.normal_oct),
                                            Vec3f(r.position[0], r.position[1], r.position[2]), splat::record_model(r));
        for (int c = 0; c < 3; ++c) r.color[c] = uint8_t(std::lround(std::clamp(lit[c], 0.0f, 1.0f) * 255.0f));
    }
}

} // namespace pbdsplat::scene
