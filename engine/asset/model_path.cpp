#include "asset/model_path.h"

#include <cstdlib>
#include <filesystem>

namespace pbdsplat::asset {

std::vector<std::string> model_search_path() {
    std::vector<std::string> dirs;
    if (const char* env = std::getenv("PBDSPLAT_MODELS")) {
        std::string s = env;
        size_t start = 0;
        while (start <= s.size()) {
            const size_t end = std::min(s.find(':', start), s.size());
            if (end > start) dirs.push_back(s.substr(start, end - start));
            start = end + 1;
        }
    }
    dirs.push_back("models");
    dirs.push_back("../shared/models");
#ifdef PBDSPLAT_SOURCE_DIR
    dirs.push_back(std::string(PBDSPLAT_SOURCE_DIR) + "/../shared/models");
#endif
    return dirs;
}

std::optional<std::string> find_model(const std::string& name) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(name, ec)) return name;
    for (const auto& dir : model_search_path()) {
        const std::filesystem::path p = std::filesystem::path(dir) / name;
        if (std::filesystem::is_regular_file(p, ec)) return p.lexically_normal().string();
    }
    return std::nullopt;
}

} // namespace pbdsplat::asset
