#include "pbdsplat/gpu_options.h"

namespace pbdsplat::cli {

core::Result<std::unique_ptr<gpu::Context>> open_context(const Options& options) {
    gpu::ContextOptions o;
    o.instance.validation = options.flag("validation");
    o.instance.best_practices = o.instance.validation;
    o.device.name_filter = options.text("device");
    return gpu::Context::create(o);
}

namespace {
core::Status counted(size_t n, const char* when) {
    if (n > 0) return core::make_error("the validation layer reported " + std::to_string(n) + " message(s)" + when + " (printed above)");
    return core::Status::success();
}
} // namespace

core::Status check_validation(const gpu::Context& ctx) { return counted(ctx.validation_messages(), ""); }

core::Status close_and_check_validation(std::unique_ptr<gpu::Context> ctx) {
    if (!ctx) return core::Status::success();
    const std::shared_ptr<const gpu::ValidationLog> log = ctx->instance().shared_validation_log();
    ctx.reset();
    return counted(log->count(), ", teardown included");
}

} // namespace pbdsplat::cli
