// SceneRuntime's interaction between steps: the camera, drags and cuts from the mouse, the
// toggles of the windowed demo (pause, sort, view, readback). Those that change which passes
// run rebuild the frame graph.
#include "scene/scene_runtime.h"

#include <algorithm>
#include <cmath>

#include "passes/mesh_image.h"
#include "sim/drag.h"

namespace pbdsplat::scene {

const char* display_view_name(DisplayView v) {
    switch (v) {
    case DisplayView::splats: return "splats";
    case DisplayView::mesh: return "mesh";
    case DisplayView::points: return "points";
    case DisplayView::side_by_side: return "splats | mesh";
    }
    return "?";
}

namespace {
// The unit view ray through a pixel (window coordinates, y down).
Vec3f pixel_ray(const render::Camera& c, const Vec2f& pixel, const Vec2f& size) {
    const Vec3f forward = (c.target - c.eye).normalized();
    const Vec3f right = forward.cross(c.up).normalized();
    const Vec3f up = right.cross(forward);
    const float tan_half = std::tan(math::radians(c.fov_y_degrees) * 0.5f);
    const float nx = 2.0f * pixel.x() / size.x() - 1.0f, ny = 2.0f * pixel.y() / size.y() - 1.0f;
    return (forward + nx * tan_half * (size.x() / size.y()) * right - ny * tan_half * up).normalized();
}
} // namespace

void SceneRuntime::set_camera(const render::Camera& camera) {
    frame_input_.frame.camera = camera;
    control_.camera_override = true;
}

bool SceneRuntime::begin_drag(const Vec2f& pixel, const Vec2f& view_size) {
    const render::Camera& c = frame_input_.frame.camera;
    const Vec3f ray = pixel_ray(c, pixel, view_size);
    // Within a few sampling spacings of the ray: the splats' size, roughly.
    const auto picked = sim::pick_particle(body_.particles, c.eye, ray, 3.0f * h_);
    if (!picked) return false;
    const Vec3f forward = (c.target - c.eye).normalized();
    drag_depth_ = (sim::xyz(body_.particles.x[*picked]) - c.eye).dot(forward);
    control_.user_drag = sim::grab_region(body_, *picked, sim::default_grab_radius(body_), DragEvent{}.stiffness);
    return true;
}

void SceneRuntime::move_drag(const Vec2f& pixel, const Vec2f& view_size) {
    if (!control_.user_drag.active) return;
    const render::Camera& c = frame_input_.frame.camera;
    const Vec3f ray = pixel_ray(c, pixel, view_size);
    const float along = ray.dot((c.target - c.eye).normalized());
    if (along > 1e-4f) control_.user_drag.target = c.eye + ray * (drag_depth_ / along);
}

void SceneRuntime::end_drag() {
    control_.user_drag.active = false;
    drag_.active = false;
}

void SceneRuntime::queue_cut(const Vec2f& a, const Vec2f& b, const Vec2f& view_size) {
    if ((b - a).norm() < 2.0f) {
        note_ = "cut stroke too short";
        return;
    }
    CutEvent c;
    c.segment = std::array<Vec2f, 2>{a, b};
    c.screen = view_size;
    queue_->push(Event{control_.time, c}, true);  // due at the next frame
}

void SceneRuntime::scale_pressure(float factor) {
    for (sim::VolumeConstraint& v : body_.volumes)
        if (v.leak == 0.0f) v.pressure = std::clamp(v.pressure * factor, 0.0f, 100.0f);
}

float SceneRuntime::pressure() const { return body_.volumes.empty() ? 0.0f : body_.volumes.front().pressure; }

core::Status SceneRuntime::set_readback(bool readback) {
    if (readback == readback_) return core::Status::success();
    readback_ = readback;
    return build_graph();
}

core::Status SceneRuntime::set_paused(bool paused) {
    if (paused == paused_) return core::Status::success();
    paused_ = paused;
    return build_graph();
}

core::Status SceneRuntime::set_sorted(bool sorted) {
    const bool blend_over = scene_.render.frame.style.blend == render::Blend::over;
    render::SplatOrder order = sorted && blend_over ? sorted_order_ : render::SplatOrder::unsorted;
    if (order == render::SplatOrder::gpu && !(renderer_ && renderer_->has_gpu_sort())) order = render::SplatOrder::cpu;
    if (order == order_) return core::Status::success();
    order_ = order;
    frame_input_.frame.style.order = order;
    return build_graph();
}

core::Status SceneRuntime::ensure_mesh_raster() {
    if (mesh_raster_ || !renderer_ || !options_.gpu) return core::Status::success();
    render::MeshRasterOptions mo;
    mo.width = renderer_->width();
    mo.height = renderer_->height();
    mo.max_vertices = renderer_->max_splats();  // room for what cuts add, as for the splats
    mo.max_triangles = 4 * body_.triangles.size() + 1024;
    mo.environment_map = scene_.render.environment_map;
    mo.sky_sun = scene_.render.frame.lighting.direction;
    mo.slots = renderer_->frames_in_flight();
    auto raster = render::MeshRaster::create(*options_.gpu, mo);
    if (!raster.ok()) return raster.error();
    mesh_raster_ = std::move(raster).value();
    mesh_color_.image = mesh_raster_->color_image();
    mesh_depth_.image = mesh_raster_->depth_image();
    return core::Status::success();
}

core::Result<core::ImageRgba8> SceneRuntime::mesh_image() {
    if (!renderer_) return core::make_error("mesh_image: this scene runtime has no renderer (created without a GPU context)");
    PBDSPLAT_TRY(ensure_mesh_raster());
    options_.gpu->device().wait_idle();  // no frame in flight uses the raster's buffers now
    PBDSPLAT_TRY(mesh_raster_->set_mesh(body_.particles.x, body_.triangles, body_.normals, 0, body_.colors));
    const Vec3f albedo = body_.colors.empty() ? appearance_.albedo : Vec3f::Ones();
    auto image = passes::render_mesh_image(*options_.gpu, *mesh_raster_, frame_input_.frame, render::MeshView::shaded, albedo);
    if (!image.ok()) return image.error();
    return std::move(image->image);
}

core::Status SceneRuntime::set_view(DisplayView view) {
    if (view == view_) return core::Status::success();
    if (view == DisplayView::mesh || view == DisplayView::side_by_side) PBDSPLAT_TRY(ensure_mesh_raster());
    view_ = view;
    // Particles as points: the same splats, a fraction of their size.
    frame_input_.frame.style.scale_multiplier = base_scale_multiplier_ * (view == DisplayView::points ? 0.3f : 1.0f);
    return build_graph();
}

} // namespace pbdsplat::scene
