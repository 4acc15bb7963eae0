#pragma once
// What benches write beside their printed figures: files in --out-dir (a CSV table, SVG plots).
#include <filesystem>
#include <string>

#include "core/result.h"
#include "pbdsplat/options.h"

namespace pbdsplat::cli {

// --out-dir, shared by every bench that writes files.
Option out_dir_option();

// Writes DIR/NAME, creating DIR first; the error names the path that could not be written.
core::Status write_report_file(const std::filesystem::path& dir, const std::string& name, const std::string& content);

} // namespace pbdsplat::cli
