#include "demo/app.h"

#include <algorithm>
#include <cstdio>
#include <deque>
#include <thread>

#include "core/timer.h"
#include "demo/camera_control.h"
#include "demo/hud.h"
#include "demo/presenter.h"
#include "demo/script.h"
#include "demo/window.h"
#include "demo/window_session.h"
#include "splat/ply.h"

namespace pbdsplat::demo {

namespace {

const char* const k_help[] = {
    "left-drag on the body   pull it (drag constraint)",
    "left-drag elsewhere     orbit    shift/middle-drag  pan    wheel  zoom",
    "right-drag              draw a cut line (applied on release)",
    "space  pause / resume    N  single step    R  reset",
    "+ / -  raise / lower the pressure    S  sort far to near on / off",
    "B  boundary particles on / off    E  environment lookup mode",
    "V  view: splats, mesh, particles, splats | mesh side by side",
    "P  save a screenshot (PNG)    L  save the Gaussians (.ply)",
    "H / F1  this help    Esc / Q  quit",
};

double median_of(std::vector<double> v) { return v.empty() ? 0.0 : core::median(v); }

// The window's objects, and the scene drawn into it (freed first).
struct Session : WindowSession {
    std::unique_ptr<scene::SceneRuntime> runtime;
    ~Session() override {
        if (ctx) (void)vkDeviceWaitIdle(ctx->vk());
        runtime.reset();
    }
};

class Demo {
public:
    Demo(const DemoOptions& o, Session& s) : options_(o), s_(s), control_(s.runtime->camera()) {}
    core::Result<DemoReport> run(const InputScript* script);

private:
    core::Status handle(const InputEvent& e);
    core::Status key(int k);
    Vec2f to_image(Vec2f window_pixel) const;
    Vec2f image_size() const { return {float(options_.scene.render.width), float(options_.scene.render.height)}; }
    void draw_overlay();
    core::Status save_screenshot(const std::string& path);
    core::Status reset();

    const DemoOptions& options_;
    Session& s_;
    CameraControl control_;
    enum class Mode { none, drag_body, orbit, pan, cut } mode_ = Mode::none;
    Vec2f last_{0, 0}, stroke_start_{0, 0};
    bool show_help_ = false, step_once_ = false, quit_ = false;
    std::string pending_screenshot_;
    std::deque<double> recent_ms_;
    core::ImageRgba8 overlay_image_;
    uint64_t frame_ = 0;
    std::string note_;
};

Vec2f Demo::to_image(Vec2f p) const {
    const Letterbox box = fit(options_.scene.render.width, options_.scene.render.height, s_.swapchain.extent());
    if (box.width == 0) return p;
    return {(p.x() - float(box.x)) * float(options_.scene.render.width) / float(box.width),
            (p.y() - float(box.y)) * float(options_.scene.render.height) / float(box.height)};
}

core::Status Demo::handle(const InputEvent& e) {
    scene::SceneRuntime& rt = *s_.runtime;
    switch (e.kind) {
    case InputEvent::Kind::press:
        last_ = e.position;
        if (e.button == 1) {
            mode_ = Mode::cut;
            stroke_start_ = e.position;
        } else if (e.button == 2 || e.shift) {
            mode_ = Mode::pan;
        } else {
            mode_ = rt.begin_drag(to_image(e.position), image_size()) ? Mode::drag_body : Mode::orbit;
        }
        break;
    case InputEvent::Kind::move:
        if (mode_ == Mode::drag_body) rt.move_drag(to_image(e.position), image_size());
        if (mode_ == Mode::orbit) control_.orbit(e.position - last_), rt.set_camera(control_.camera());
        if (mode_ == Mode::pan) control_.pan(e.position - last_, image_size().y()), rt.set_camera(control_.camera());
        last_ = e.position;
        break;
    case InputEvent::Kind::release:
        if (mode_ == Mode::drag_body) rt.end_drag();
        if (mode_ == Mode::cut) rt.queue_cut(to_image(stroke_start_), to_image(e.position), image_size());
        last_ = e.position;
        mode_ = Mode::none;
        break;
    case InputEvent::Kind::scroll:
        control_.zoom(e.scroll);
        rt.set_camera(control_.camera());
        break;
    case InputEvent::Kind::key: return key(e.key);
    }
    return core::Status::success();
}

core::Status Demo::key(int k) {
    scene::SceneRuntime& rt = *s_.runtime;
    switch (k) {
    case key_space: return rt.set_paused(!rt.paused());
    case 'N':
        step_once_ = true;
        return rt.set_paused(false);
    case 'R': return reset();
    case key_plus: case key_up: rt.scale_pressure(1.1f); break;
    case key_minus: case key_down: rt.scale_pressure(1.0f / 1.1f); break;
    case 'S': return rt.set_sorted(rt.order() == render::SplatOrder::unsorted);
    case 'B': rt.set_boundary_visible(!rt.boundary_visible()); break;
    case 'E': {
        const render::EnvSampling next[] = {render::EnvSampling::normal, render::EnvSampling::hybrid, render::EnvSampling::off,
                                            render::EnvSampling::position};
        rt.set_environment_sampling(next[int(rt.environment_sampling())]);
        break;
    }
    case 'V': {
        const scene::DisplayView next = scene::DisplayView((int(rt.view()) + 1) % 4);
        s_.presenter->set_view(next);
        return rt.set_view(next);
    }
    case 'P': pending_screenshot_ = "pbdsplat-frame-" + std::to_string(frame_) + ".png"; break;
    case 'L': {
        const std::string path = "pbdsplat-frame-" + std::to_string(frame_) + ".ply";
        const core::Status st = splat::write_ply(path, rt.records());
        note_ = st.ok() ? "saved " + path : st.error().to_string();
        break;
    }
    case 'H': case key_f1: show_help_ = !show_help_; break;
    case 'Q': case key_escape: quit_ = true; break;
    default: break;
    }
    return core::Status::success();
}

core::Status Demo::reset() {
    scene::RuntimeOptions ro;
    ro.threads = options_.threads;
    ro.gpu = s_.ctx.get();
    ro.readback = false;
    ro.interactive = true;
    ro.presenter = s_.presenter.get();
    PBDSPLAT_VK_TRY(vkDeviceWaitIdle(s_.ctx->vk()));
    s_.runtime.reset();
    auto rt = scene::SceneRuntime::create(options_.scene, ro);
    if (!rt.ok()) return rt.error();
    s_.runtime = std::move(rt).value();
    s_.presenter->set_view(scene::DisplayView::splats);
    control_ = CameraControl(s_.runtime->camera());
    note_ = "reset";
    return core::Status::success();
}

void Demo::draw_overlay() {
    const VkExtent2D ext = s_.swapchain.extent();
    core::ImageRgba8& img = overlay_image_;
    clear(img);
    if (mode_ == Mode::cut) draw_line(img, stroke_start_, last_, 3.0f, {1.0f, 0.9f, 0.2f, 0.9f});
    if (!options_.hud) return;
    const scene::SceneRuntime& rt = *s_.runtime;
    const scene::FrameStats& st = rt.stats();
    double sum = 0.0;
    for (double ms : recent_ms_) sum += ms;
    const double mean = recent_ms_.empty() ? 0.0 : sum / double(recent_ms_.size());
    char buf[512];
    std::vector<std::string> lines;
    std::snprintf(buf, sizeof(buf), "pbdsplat  %s    %ux%u    %s", options_.scene.name.c_str(), ext.width, ext.height,
                  s_.ctx->caps().name.c_str());
    lines.emplace_back(buf);
    std::snprintf(buf, sizeof(buf), "FPS %.1f (%.1f ms)   frame %llu   t %.2f s%s", mean > 0 ? 1000.0 / mean : 0.0, mean,
                  static_cast<unsigned long long>(frame_), double(rt.time()), rt.paused() ? "   PAUSED" : "");
    lines.emplace_back(buf);
    std::snprintf(buf, sizeof(buf), "particles %zu   boundary %zu   Gaussians %zu   cuts %zu   tears %zu", st.particles,
                  st.boundary_particles, st.gaussians, st.cuts, st.tears);
    lines.emplace_back(buf);
    std::string cpu = "CPU ms";
    for (const auto& n : scene::k_pass_groups) {
        std::snprintf(buf, sizeof(buf), "  %s %.2f", n.brief, st.groups[n.group]);
        cpu += buf;
    }
    lines.push_back(std::move(cpu));
    std::snprintf(buf, sizeof(buf), "GPU ms  upload %.2f  sort %.2f  splat %.2f  (GPU scene %.2f)", st.gpu.upload_ms, st.gpu.sort_ms,
                  st.gpu.draw_ms, st.gpu_scene_ms());
    lines.emplace_back(buf);
    std::snprintf(buf, sizeof(buf), "view %s   environment %s   sort %s   pressure %.2f   boundary %s",
                  scene::display_view_name(rt.view()), render::env_sampling_name(rt.environment_sampling()),
                  render::splat_order_name(rt.order()), double(rt.pressure()), rt.boundary_visible() ? "on" : "off");
    lines.emplace_back(buf);
    const std::string& note = note_.empty() ? rt.interaction_note() : note_;
    lines.push_back(note.empty() ? "H: help" : note + "    H: help");
    draw_panel(img, 8, 8, lines, {0.95f, 0.95f, 0.9f, 1.0f}, 1);
    if (show_help_) draw_panel(img, 8, 110, std::vector<std::string>(std::begin(k_help), std::end(k_help)), {1.0f, 0.95f, 0.6f, 1.0f}, 1);
}

core::Status Demo::save_screenshot(const std::string& path) {
    auto img = s_.runtime->finish();
    if (!img.ok()) return img.error();
    PBDSPLAT_TRY(core::write_png(path, img.value()));
    return s_.runtime->set_readback(false);
}

core::Result<DemoReport> Demo::run(const InputScript* script) {
    DemoReport report;
    report.device = s_.ctx->caps().name;
    std::vector<double> all_ms, before_cut_ms, after_cut_ms;
    overlay_image_ = core::ImageRgba8(s_.overlay->width(), s_.overlay->height());
    while (!s_.window->should_close() && !quit_) {
        if (options_.frames && frame_ >= options_.frames) break;
        std::vector<InputEvent> events = s_.window->poll();
        if (script) {
            const auto scripted = script->events_at(frame_);
            events.insert(events.end(), scripted.begin(), scripted.end());
        }
        for (const InputEvent& e : events) PBDSPLAT_TRY(handle(e));
        auto visible = s_.follow_window_size();
        if (!visible.ok()) return visible.error();
        if (!visible.value()) {  // minimised: nothing to draw into
            s_.window->wait();
            continue;
        }
        const bool shoot = (options_.screenshot_at && *options_.screenshot_at == frame_) || !pending_screenshot_.empty();
        if (shoot) PBDSPLAT_TRY(s_.runtime->set_readback(true));
        draw_overlay();
        s_.overlay->set(overlay_image_);

        const core::Stopwatch clock;
        PBDSPLAT_TRY(s_.runtime->step());
        PBDSPLAT_TRY(s_.present());
        const double ms = clock.elapsed_ms();

        if (shoot) {
            const std::string path = pending_screenshot_.empty() ? options_.screenshot_path : pending_screenshot_;
            PBDSPLAT_TRY(save_screenshot(path));
            if (pending_screenshot_.empty()) report.screenshot = path;
            note_ = "saved " + path;
            pending_screenshot_.clear();
        }
        if (step_once_) {
            step_once_ = false;
            PBDSPLAT_TRY(s_.runtime->set_paused(true));
        }
        recent_ms_.push_back(ms);
        if (recent_ms_.size() > 30) recent_ms_.pop_front();
        all_ms.push_back(ms);
        (s_.runtime->stats().cuts == 0 ? before_cut_ms : after_cut_ms).push_back(ms);
        ++frame_;
    }
    PBDSPLAT_VK_TRY(vkDeviceWaitIdle(s_.ctx->vk()));
    const scene::FrameStats& st = s_.runtime->stats();
    report.frames = frame_;
    report.median_frame_ms = median_of(all_ms);
    report.fps = report.median_frame_ms > 0 ? 1000.0 / report.median_frame_ms : 0.0;
    report.fps_before_cut = before_cut_ms.empty() ? 0.0 : 1000.0 / median_of(before_cut_ms);
    report.fps_after_cut = after_cut_ms.empty() ? 0.0 : 1000.0 / median_of(after_cut_ms);
    report.cuts = st.cuts;
    report.tears = st.tears;
    report.particles = st.particles;
    report.gaussians = st.gaussians;
    report.pieces = s_.runtime->pieces();
    report.validation_messages = s_.ctx->validation_messages();
    return report;
}

} // namespace

unsigned default_simulation_threads() { return std::clamp(std::thread::hardware_concurrency() / 2, 1u, 8u); }

core::Result<DemoReport> run_demo(const DemoOptions& options) {
    std::optional<InputScript> script;
    if (!options.script_path.empty()) {
        auto loaded = InputScript::load(options.script_path);
        if (!loaded.ok()) return loaded.error();
        script = std::move(loaded).value();
    }
    // Held by pointer so it can be torn down before the validation count is read: messages sent
    // while the device and instance are destroyed (leaked objects) count too.
    auto session = std::make_unique<Session>();
    Session& s = *session;
    PBDSPLAT_TRY(s.open("pbdsplat - " + options.scene.name, options.scene.render.width, options.scene.render.height, options.vsync,
                        options.validation, options.device));

    scene::RuntimeOptions ro;
    ro.threads = options.threads;
    ro.gpu = s.ctx.get();
    ro.readback = false;
    ro.interactive = true;
    ro.presenter = s.presenter.get();
    ro.frames_in_flight = k_window_frames_in_flight;
    auto rt = scene::SceneRuntime::create(options.scene, ro);
    if (!rt.ok()) return rt.error();
    s.runtime = std::move(rt).value();
    const auto log = s.ctx->instance().shared_validation_log();
    core::Result<DemoReport> report = [&] {
        Demo demo(options, s);
        return demo.run(script ? &*script : nullptr);
    }();
    session.reset();
    if (report.ok()) report->validation_messages = log->count();
    return report;
}

} // namespace pbdsplat::demo
