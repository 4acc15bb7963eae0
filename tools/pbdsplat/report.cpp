#include "pbdsplat/report.h"

#include <fstream>

namespace pbdsplat::cli {

Option out_dir_option() {
    return text("out-dir", "DIR", "out/bench", "where the CSV and SVG files go (docs/bench holds the figures the docs show)");
}

core::Status write_report_file(const std::filesystem::path& dir, const std::string& name, const std::string& content) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) return core::make_error(dir.string() + ": cannot create the folder: " + ec.message());
    const std::filesystem::path path = dir / name;
    std::ofstream out(path, std::ios::binary);
    out << content;
    out.close();
    if (!out) return core::make_error(path.string() + ": cannot write");
    return core::Status::success();
}

} // namespace pbdsplat::cli
