#include "pbdsplat/report.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <fstream>

namespace pbdsplat::cli {
namespace {

std::string number_text(double v, int precision) {
    return precision < 0 ? format("%.*e", -precision, v) : format("%.*f", precision, v);
}

std::string cell_text(const nlohmann::json& cell, int precision) {
    if (cell.is_string()) return cell.get<std::string>();
    if (cell.is_number_integer() || cell.is_number_unsigned()) return cell.dump();
    if (cell.is_number()) return number_text(cell.get<double>(), precision);
    if (cell.is_boolean()) return cell.get<bool>() ? "yes" : "no";
    return cell.is_null() ? "-" : cell.dump();
}

std::string csv_cell(const nlohmann::json& cell) {
    if (!cell.is_string()) return cell.is_null() ? "" : cell.dump();
    const std::string s = cell.get<std::string>();
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string quoted = "\"";
    for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

// Writes DIR/NAME, creating DIR first; the error names the path that could not be written.
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

} // namespace

std::string format(const char* pattern, ...) {
    va_list args;
    va_start(args, pattern);
    va_list again;
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, pattern, args);
    va_end(args);
    std::string out(size_t(std::max(n, 0)), '\0');
    std::vsnprintf(out.data(), out.size() + 1, pattern, again);
    va_end(again);
    return out;
}

void Table::add(std::vector<nlohmann::json> cells) {
    PBDSPLAT_ASSERT(cells.size() == columns_.size(), "Table::add: give one cell per column, in column order");
    rows_.push_back(std::move(cells));
}

std::string Table::text(int indent) const {
    std::vector<size_t> shown;
    // A column with no value in any row (a measurement not asked for) is left out.
    for (size_t c = 0; c < columns_.size(); ++c)
        if (columns_[c].in_text && std::any_of(rows_.begin(), rows_.end(), [c](const auto& row) { return !row[c].is_null(); }))
            shown.push_back(c);
    std::vector<std::vector<std::string>> cells(rows_.size() + 1);
    for (size_t c : shown) cells[0].push_back(columns_[c].heading.value_or(columns_[c].name));
    for (size_t r = 0; r < rows_.size(); ++r)
        for (size_t c : shown) cells[r + 1].push_back(cell_text(rows_[r][c], columns_[c].precision));
    std::vector<size_t> width(shown.size(), 0);
    for (const auto& line : cells)
        for (size_t k = 0; k < line.size(); ++k) width[k] = std::max(width[k], line[k].size());
    // Text (the first column, or a column holding strings) reads left; numbers right.
    std::vector<bool> left(shown.size(), false);
    for (size_t k = 0; k < shown.size(); ++k)
        left[k] = k == 0 || std::any_of(rows_.begin(), rows_.end(), [c = shown[k]](const auto& row) { return row[c].is_string(); });
    std::string out;
    for (size_t r = 0; r < cells.size(); ++r) {
        std::string line(size_t(indent), ' ');
        for (size_t k = 0; k < shown.size(); ++k) {
            const std::string& s = cells[r][k];
            const std::string pad(width[k] - s.size(), ' ');
            line += (k ? "  " : "") + (left[k] ? s + pad : pad + s);
        }
        while (!line.empty() && line.back() == ' ') line.pop_back();
        out += line + "\n";
    }
    return out;
}

std::string Table::csv() const {
    std::string out;
    for (size_t c = 0; c < columns_.size(); ++c) out += (c ? "," : "") + columns_[c].name;
    out += "\n";
    for (const auto& row : rows_) {
        for (size_t c = 0; c < row.size(); ++c) out += (c ? "," : "") + csv_cell(row[c]);
        out += "\n";
    }
    return out;
}

nlohmann::json Table::json() const {
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& row : rows_) {
        nlohmann::json o = nlohmann::json::object();
        for (size_t c = 0; c < row.size(); ++c)
            if (!row[c].is_null()) o[columns_[c].name] = row[c];
        rows.push_back(std::move(o));
    }
    return rows;
}

Report::Report(std::string suite) : json_({{"suite", std::move(suite)}}) {}

void Report::line(std::string text) { text_ += text + "\n"; }

void Report::figures(std::string title, const std::vector<Figure>& figures) {
    if (!title.empty()) line(std::move(title));
    size_t width = 0;
    for (const Figure& f : figures) width = std::max(width, f.label.size());
    for (const Figure& f : figures) {
        const std::string value = number_text(f.value, f.precision);
        line("  " + f.label + std::string(width - f.label.size(), ' ') + "  " + std::string(value.size() < 9 ? 9 - value.size() : 0, ' ') +
             value + (f.unit.empty() ? "" : " " + f.unit));
    }
}

void Report::table(std::string title, const Table& table, int indent) {
    if (!title.empty()) line(std::move(title));
    text_ += table.text(indent);
}

void Report::csv(std::string file, const Table& table) { files_.emplace_back(std::move(file), table.csv()); }

void Report::plot(std::string file, const PlotSpec& plot) { files_.emplace_back(std::move(file), render_svg(plot)); }

std::string Report::text() const { return text_; }

core::Status Report::write_files(const std::filesystem::path& dir, std::vector<std::string>& written) const {
    for (const auto& [name, content] : files_) {
        PBDSPLAT_TRY(write_report_file(dir, name, content));
        written.push_back((dir / name).string());
    }
    return core::Status::success();
}

Option out_dir_option() {
    return text("out-dir", "DIR", "out/bench", "where the CSV and SVG files go (docs/bench holds the figures the docs show)");
}


} // namespace pbdsplat::cli
