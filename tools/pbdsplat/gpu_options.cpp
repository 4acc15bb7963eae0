#include "pbdsplat/gpu_options.h"

namespace pbdsplat::cli {

core::Result<std::unique_ptr<gpu::Context>> open_context(const Options& options) {
    gpu::ContextOptions o;
    o.instance.validation = options.flag("validation");
    o.instance.best_practices = o.instance.validation;
    o.device.name_filter = options.text("device");
    return gpu::Context::create(o);
}

core::Status check_validation(const gpu::Context& ctx) {
    if (const size_t n = ctx.validation_messages(); n > 0)
        return core::make_error("the validation layer reported " + std::to_string(n) + " message(s) (printed above)");
    return core::Status::success();
}

} // namespace pbdsplat::cli
