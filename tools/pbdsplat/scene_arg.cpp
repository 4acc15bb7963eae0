#include "pbdsplat/scene_arg.h"

#include <filesystem>
#include <fstream>

#include "scene/default_scene.h"
#include "scene/model_scene.h"
#include "scene/scene_file.h"

namespace pbdsplat::cli {

Option save_scene_option() {
    return text("save-scene", "FILE.toml", "",
                "also write the scene used to FILE.toml: a model file's default scene (its path made relative\n"
                "to FILE's folder), or the scene as read, to edit and run again")
        .default_from("none");
}

core::Result<scene::Scene> load_scene_arg(const std::vector<std::string>& positionals) {
    if (positionals.size() > 1) return core::make_error("give one scene or model file (got " + std::to_string(positionals.size()) + ")");
    if (positionals.empty()) return scene::default_scene();
    return scene::load_scene_or_model(positionals[0]);
}

namespace {

core::Status save_scene(const std::string& out, const std::vector<std::string>& positionals, const scene::Scene& used) {
    const std::filesystem::path target(out);
    if (target.extension() != ".toml") return core::make_error("--save-scene " + out + ": name a .toml file");
    std::string text;
    auto kind = positionals.empty() ? core::Result<scene::InputKind>(scene::InputKind::scene) : scene::input_kind(positionals[0]);
    if (kind.ok() && kind.value() == scene::InputKind::model) {
        std::error_code ec;
        const std::filesystem::path model = std::filesystem::absolute(positionals[0], ec);
        const std::filesystem::path dir = std::filesystem::absolute(target, ec).parent_path();
        std::filesystem::path rel = model.lexically_relative(dir);
        auto t = scene::model_scene_text(positionals[0], (rel.empty() ? model : rel).generic_string());
        if (!t.ok()) return t.error();
        text = std::move(t).value();
    } else {
        text = scene::to_toml(used);
    }
    std::ofstream f(target, std::ios::binary);
    if (!f) return core::make_error(out, 0, "cannot write the scene (does its folder exist?)");
    f << text;
    if (!f) return core::make_error(out, 0, "write error");
    return core::Status::success();
}

} // namespace

core::Result<scene::Scene> load_scene_arg(const Options& options, const std::vector<std::string>& positionals) {
    auto scene = load_scene_arg(positionals);
    if (!scene.ok()) return scene;
    if (options.given("save-scene")) PBDSPLAT_TRY(save_scene(options.text("save-scene"), positionals, scene.value()));
    return scene;
}

core::Result<scene::Scene> load_scene_arg(const Options& options) { return load_scene_arg(options, options.operands()); }

} // namespace pbdsplat::cli
