#include <charconv>

#include <nlohmann/json.hpp>

#include "core/timer.h"
#include "asset/mesh_spec.h"
#include "pbdsplat/bench_suites.h"
#include "pbdsplat/progress.h"
#include "pbdsplat/gpu_options.h"
#include "passes/coverage.h"
#include "sim/soft_body.h"
#include "splat/mapping.h"

namespace pbdsplat::cli {

namespace {

const CommandSpec& command_spec() {
    static const CommandSpec command{
        "bench surface", "",
        "Boundary particles on a mesh at rest: for each eta, the sampling time (median of R), the\n"
        "per-frame update time (median of 200 updates) and the same normalised to 10,000 boundary\n"
        "particles; with --coverage, also the hole ratio and silhouette IoU of the splats against\n"
        "a raster of the mesh (256x256), for each eta and for the vertices alone.\n",
        with_gpu({text("mesh", "SPEC", "teapot.obj", "a model from ../shared/models, an OBJ, or a procedural spec"),
                  text("eta", "LIST", "0.25,0.5,0.75,1", "comma-separated spacing factors, each 0.05 to 4"),
                  real("scale", "S", 0.7f, 0.01f, 10.0f, "splat std dev in units of h (0.7 is the scene default)"),
                  whole("repeat", "R", 5, 1, 1000, "sampling repetitions"),
                  flag("coverage", "measure coverage on the GPU"), json_option()})};
    return command;
}

Outcome measure(const Options& opt) {
    const uint32_t repeat = opt.whole("repeat");
    const float scale = opt.real("scale");
    std::vector<float> etas;
    for (const std::string& item : split_list(opt.text("eta"))) {
        float e = 0.0f;
        const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), e);
        if (ec != std::errc() || end != item.data() + item.size() || !(e >= 0.05f && e <= 4.0f))
            return Outcome::usage("--eta expects numbers from 0.05 to 4, comma-separated; got '" + opt.text("eta") + "'");
        etas.push_back(e);
    }
    if (etas.empty()) return Outcome::usage("--eta names no value");
    const std::string spec = opt.text("mesh");
    auto repaired = asset::load_mesh_spec(spec);
    if (!repaired.ok()) return repaired.error();
    auto made = sim::make_soft_body(repaired->mesh, {});
    if (!made.ok()) return made.error();
    const sim::SoftBody& body = made.value();
    const mesh::TriangleMesh rest{body.rest_positions, body.triangles, {}, {}, {}};
    const std::vector<std::array<uint32_t, 3>> tris(body.triangles.begin(), body.triangles.end());

    std::unique_ptr<gpu::Context> ctx;
    render::FrameInputs frame;
    if (opt.flag("coverage")) {
        auto c = open_context(opt);
        if (!c.ok()) return c.error();
        ctx = std::move(c).value();
        const mesh::Bounds b = mesh::bounds(rest);
        frame.camera.target = b.center();
        frame.camera.eye = b.center() + Vec3f(0.3f, 0.35f, 1.1f) * b.diagonal();
    }

    Table table({{"eta", 2},
                 {"h", 4},
                 {"boundary_particles", 0, true, "samples"},
                 {"sampling_ms", 2, true, "sampling ms"},
                 {"update_ms", 3, true, "update ms"},
                 {"update_ms_per_10k", 3, true, "per 10k ms"},
                 {"map_flat_ms", 3, true, "map flat ms"},
                 {"map_varying_ms", 3, true, "map varying ms"},
                 {"hole_ratio", 5, true, "holes"},
                 {"silhouette_iou", 3, true, "IoU"}});
    auto coverage = [&](const surface::BoundaryParticles* samples, float h, double& holes, double& iou) -> core::Status {
        splat::Appearance look;
        look.scale = scale * h;
        std::vector<splat::GaussianRecord> records;
        splat::map_body(body.particles.x, body.normals, {}, body.triangles, samples, look, nullptr, nullptr, records);
        auto c = passes::measure_coverage(*ctx, body.particles.x, tris, records, frame, 256, 256);
        if (!c.ok()) return c.error();
        holes = c->hole_ratio, iou = c->silhouette_iou;
        return core::Status::success();
    };
    Report report("surface");
    report.line(format("%s: %zu particles, %zu triangles; splats %.2f h", spec.c_str(), body.particle_count(), body.triangles.size(), scale));
    Progress progress("bench surface", uint32_t(etas.size()), "spacings");
    uint32_t done = 0;
    for (float eta : etas) {
        const float h = surface::spacing(rest, eta);
        std::vector<double> sample_ms;
        surface::BoundaryParticles samples;
        for (uint32_t r = 0; r < repeat; ++r) {
            const core::Stopwatch clock;
            samples = surface::sample_surface(rest, {h, 1});
            sample_ms.push_back(clock.elapsed_ms());
        }
        std::vector<double> update_ms;
        for (int r = 0; r < 200; ++r) {
            const core::Stopwatch clock;
            surface::update_boundary_particles(body.triangles, body.particles.x, body.normals, samples);
            update_ms.push_back(clock.elapsed_ms());
        }
        const double update = core::median(update_ms);
        const double per_10k = samples.size() ? update * 10000.0 / double(samples.size()) : 0.0;
        // The map stage's records for every particle and sample, with one normal per splat and
        // with the normal field (render.splat_normals): what the field costs per frame.
        std::vector<double> flat_ms, varying_ms;
        {
            splat::Appearance look;
            look.scale = scale * h;
            std::vector<splat::GaussianRecord> records;
            splat::NormalField field;
            for (int r = 0; r < 100; ++r) {
                const core::Stopwatch flat_clock;
                splat::map_body(body.particles.x, body.normals, {}, body.triangles, &samples, look, nullptr, nullptr, records);
                flat_ms.push_back(flat_clock.elapsed_ms());
                const core::Stopwatch varying_clock;
                field.update(body.particles.x, body.normals, body.triangles, true, splat::curvature_limit(look.scale));
                splat::map_body(body.particles.x, body.normals, {}, body.triangles, &samples, look, nullptr, &field, records);
                varying_ms.push_back(varying_clock.elapsed_ms());
            }
        }
        double holes = 0.0, iou = 0.0;
        if (ctx) PBDSPLAT_TRY(coverage(&samples, h, holes, iou));
        table.add({eta, h, samples.size(), core::median(sample_ms), update, per_10k, core::median(flat_ms), core::median(varying_ms), ctx ? nlohmann::json(holes) : nlohmann::json(),
                   ctx ? nlohmann::json(iou) : nlohmann::json()});
        progress.frame_done(++done);
    }
    report.json().update({{"mesh", spec}, {"particles", body.particle_count()}, {"splat_scale", scale}, {"rows", table.json()}});
    report.table("", table);
    if (ctx) {
        // The vertex-only baseline at the splat size of the first eta.
        const float h = surface::spacing(rest, etas.front());
        double holes = 0.0, iou = 0.0;
        PBDSPLAT_TRY(coverage(nullptr, h, holes, iou));
        report.json()["vertices_only"] = {{"splat_scale_h_of_eta", etas.front()}, {"hole_ratio", holes}, {"silhouette_iou", iou}};
        report.line(format("  vertices only, splats as for eta %.2f: holes %.5f, IoU %.3f", etas.front(), holes, iou));
        PBDSPLAT_TRY(check_validation(*ctx));
    }
    return report;
}

} // namespace

const BenchSuite k_bench_surface{"surface", "boundary particles: sampling and update time, coverage against eta", command_spec,
                                 measure};

} // namespace pbdsplat::cli
