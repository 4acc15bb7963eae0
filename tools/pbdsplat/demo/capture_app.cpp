#include "demo/capture_app.h"

#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>

#include "core/timer.h"
#include "demo/camera_control.h"
#include "demo/hud.h"
#include "demo/window_session.h"
#include "passes/offscreen_renderer.h"
#include "scene/ply_view.h"

namespace pbdsplat::demo {

namespace {

const char* const k_capture_help[] = {
    "left-drag  orbit    shift/middle-drag  pan    wheel  zoom",
    "space  turn on its own / hold still    P  save a screenshot (PNG)",
    "H / F1  this help    Esc / Q  quit",
};

struct CaptureSession : WindowSession {
    std::unique_ptr<passes::OffscreenRenderer> renderer;
    ~CaptureSession() override {
        if (ctx) (void)vkDeviceWaitIdle(ctx->vk());
        renderer.reset();
    }
};

class CaptureView {
public:
    CaptureView(const CaptureOptions& o, CaptureSession& s, splat::PlyGaussians& file, bool gpu_sort)
        : options_(o), s_(s), file_(file), gpu_sort_(gpu_sort), start_(scene::ply_view(file.records)), control_(start_.camera) {}
    core::Result<DemoReport> run();

private:
    void handle(const InputEvent& e);
    void draw_overlay(double mean_ms);

    const CaptureOptions& options_;
    CaptureSession& s_;
    splat::PlyGaussians& file_;
    const bool gpu_sort_;
    const render::FrameInputs start_;
    CameraControl control_;
    enum class Mode { none, orbit, pan } mode_ = Mode::none;
    Vec2f last_{0, 0};
    bool turning_ = true, show_help_ = false, quit_ = false;
    std::string pending_screenshot_, note_;
    core::ImageRgba8 overlay_image_;
    uint64_t frame_ = 0;
};

void CaptureView::handle(const InputEvent& e) {
    switch (e.kind) {
    case InputEvent::Kind::press:
        last_ = e.position;
        mode_ = e.button == 2 || e.shift ? Mode::pan : Mode::orbit;
        turning_ = false;  // the user has the camera now
        break;
    case InputEvent::Kind::move:
        if (mode_ == Mode::orbit) control_.orbit(e.position - last_);
        if (mode_ == Mode::pan) control_.pan(e.position - last_, float(options_.height));
        last_ = e.position;
        break;
    case InputEvent::Kind::release: mode_ = Mode::none; break;
    case InputEvent::Kind::scroll: control_.zoom(e.scroll); break;
    case InputEvent::Kind::key:
        if (e.key == key_space) turning_ = !turning_;
        if (e.key == 'P') pending_screenshot_ = "pbdsplat-capture-" + std::to_string(frame_) + ".png";
        if (e.key == 'H' || e.key == key_f1) show_help_ = !show_help_;
        if (e.key == 'Q' || e.key == key_escape) quit_ = true;
        break;
    }
}

void CaptureView::draw_overlay(double mean_ms) {
    core::ImageRgba8& img = overlay_image_;
    clear(img);
    if (!options_.hud) return;
    const render::GpuTimings t = s_.renderer->timings();
    char buf[512];
    std::vector<std::string> lines;
    std::snprintf(buf, sizeof(buf), "pbdsplat  %s    %s", std::filesystem::path(options_.path).filename().c_str(), s_.ctx->caps().name.c_str());
    lines.emplace_back(buf);
    std::snprintf(buf, sizeof(buf), "FPS %.1f (%.1f ms)   %zu %s Gaussians, colour of degree %u", mean_ms > 0 ? 1000.0 / mean_ms : 0.0,
                  mean_ms, file_.records.size(), file_.shapes.empty() ? "round" : "anisotropic", file_.sh.empty() ? 0u : file_.sh_degree);
    lines.emplace_back(buf);
    std::snprintf(buf, sizeof(buf), "GPU ms  upload %.2f  sort %.2f  draw %.2f    sorted on the %s", t.upload_ms, t.sort_ms, t.draw_ms,
                  gpu_sort_ ? "GPU" : "CPU");
    lines.emplace_back(buf);
    lines.push_back(note_.empty() ? "H: help" : note_ + "    H: help");
    draw_panel(img, 8, 8, lines, {0.95f, 0.95f, 0.9f, 1.0f}, 1);
    if (show_help_) draw_panel(img, 8, 80, std::vector<std::string>(std::begin(k_capture_help), std::end(k_capture_help)), {1.0f, 0.95f, 0.6f, 1.0f}, 1);
}

core::Result<DemoReport> CaptureView::run() {
    DemoReport report;
    report.device = s_.ctx->caps().name;
    report.gaussians = file_.records.size();
    std::vector<double> all_ms;
    std::deque<double> recent_ms;
    overlay_image_ = core::ImageRgba8(s_.overlay->width(), s_.overlay->height());
    const core::Stopwatch clock;
    double last_s = 0.0;
    while (!s_.window->should_close() && !quit_) {
        if (options_.frames && frame_ >= options_.frames) break;
        for (const InputEvent& e : s_.window->poll()) handle(e);
        auto visible = s_.follow_window_size();
        if (!visible.ok()) return visible.error();
        if (!visible.value()) {
            s_.window->wait();
            continue;
        }
        const double now_s = clock.elapsed_ms() / 1000.0;
        // Turned by wall time, so a slow device turns as far per second, in fewer frames.
        if (turning_) {
            const double radians = (now_s - last_s) * options_.orbit_degrees_per_second * M_PI / 180.0;
            control_.orbit(Vec2f(float(radians / k_orbit_radians_per_pixel), 0.0f));
        }
        last_s = now_s;
        double mean = 0.0;
        for (double ms : recent_ms) mean += ms / double(recent_ms.size());
        draw_overlay(mean);
        s_.overlay->set(overlay_image_);

        const core::Stopwatch frame_clock;
        render::FrameInputs frame = start_;
        frame.camera = control_.camera();
        scene::order_ply(file_, frame, gpu_sort_);
        const bool shoot = (options_.screenshot_at && *options_.screenshot_at == frame_) || !pending_screenshot_.empty();
        if (shoot) PBDSPLAT_TRY(s_.renderer->set_readback(true));  // only this frame is copied out
        PBDSPLAT_TRY(s_.renderer->render(file_.records, frame, {}, file_.shapes, file_.sh));
        PBDSPLAT_TRY(s_.present());
        if (shoot) {
            const std::string path = pending_screenshot_.empty() ? options_.screenshot_path : pending_screenshot_;
            auto img = s_.renderer->finish();
            if (!img.ok()) return img.error();
            PBDSPLAT_TRY(core::write_png(path, img.value()));
            PBDSPLAT_TRY(s_.renderer->set_readback(false));
            if (pending_screenshot_.empty()) report.screenshot = path;
            note_ = "saved " + path;
            pending_screenshot_.clear();
        }
        const double ms = frame_clock.elapsed_ms();
        recent_ms.push_back(ms);
        if (recent_ms.size() > 30) recent_ms.pop_front();
        all_ms.push_back(ms);
        ++frame_;
    }
    PBDSPLAT_VK_TRY(vkDeviceWaitIdle(s_.ctx->vk()));
    report.frames = frame_;
    report.median_frame_ms = all_ms.empty() ? 0.0 : core::median(all_ms);
    report.fps = report.median_frame_ms > 0 ? 1000.0 / report.median_frame_ms : 0.0;
    report.fps_before_cut = report.fps;
    report.validation_messages = s_.ctx->validation_messages();
    return report;
}

} // namespace

core::Result<DemoReport> run_capture(const CaptureOptions& options) {
    auto file = splat::read_ply_gaussians(options.path, options.up, splat::MissingNormals::leave);
    if (!file.ok()) return file.error();
    if (file->records.empty()) return core::make_error(options.path + ": holds no Gaussians");
    auto session = std::make_unique<CaptureSession>();
    CaptureSession& s = *session;
    PBDSPLAT_TRY(s.open("pbdsplat - " + std::filesystem::path(options.path).filename().string(), options.width, options.height,
                        options.vsync, options.validation, options.device));
    const bool gpu_sort = options.gpu_sort.value_or(scene::ply_sort_on_gpu(s.ctx->caps().type));
    render::RendererOptions ro = scene::ply_renderer_options(file.value(), options.width, options.height, gpu_sort);
    ro.frames_in_flight = k_window_frames_in_flight;
    auto renderer = passes::OffscreenRenderer::create(*s.ctx, ro, s.presenter.get());
    if (!renderer.ok()) return renderer.error();
    s.renderer = std::move(renderer).value();
    const auto log = s.ctx->instance().shared_validation_log();
    core::Result<DemoReport> report = [&] {
        CaptureView view(options, s, file.value(), gpu_sort);
        return view.run();
    }();
    session.reset();
    if (report.ok()) report->validation_messages = log->count();
    return report;
}

} // namespace pbdsplat::demo
