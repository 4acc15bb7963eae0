#pragma once
// What a bench found, written once and shown four ways. The JSON object is the record (what
// --json prints and scripts read); the text is built from titled figure lists and tables; a
// table also becomes a CSV file at full precision; plots become SVG files. A bench fills a
// Report and bench_runner.h prints it and writes its files, so no bench formats its own output.
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "pbdsplat/options.h"
#include "pbdsplat/svg_plot.h"

namespace pbdsplat::cli {

// printf into a std::string (GCC 12 has no std::format).
std::string format(const char* pattern, ...) __attribute__((format(printf, 1, 2)));

// One column: its name (CSV header and JSON key), how the text table shows it.
struct Column {
    std::string name;
    int precision = 3;      // digits after the point in the text table (negative: -p digits, exponent form);
                            // CSV keeps every digit
    bool in_text = true;    // false: CSV and JSON only
    std::optional<std::string> heading;  // text table heading; none: the name
};

// Rows of cells, each a number, a string, or null (not measured: left out of the JSON, and a
// column of nulls out of the text).
class Table {
public:
    explicit Table(std::vector<Column> columns) : columns_(std::move(columns)) {}
    // One cell per column, in column order.
    void add(std::vector<nlohmann::json> cells);

    // Aligned columns under their headings, each line indented by `indent` spaces.
    std::string text(int indent = 2) const;
    // Header line of names, then the rows; strings with a comma or quote are quoted.
    std::string csv() const;
    // An array of objects keyed by column name, without the null cells.
    nlohmann::json json() const;
    size_t size() const { return rows_.size(); }

private:
    std::vector<Column> columns_;
    std::vector<std::vector<nlohmann::json>> rows_;
};

// A named value in a figure list: "  label   12.345 ms".
struct Figure {
    std::string label;
    double value = 0.0;
    std::string unit;
    int precision = 3;
};

class Report {
public:
    explicit Report(std::string suite);

    // The record: {"suite": ...} and whatever the bench puts in.
    nlohmann::json& json() { return json_; }
    const nlohmann::json& json() const { return json_; }

    // A line of the text view (a headline, a note).
    void line(std::string text);
    // A titled list of figures, labels aligned.
    void figures(std::string title, const std::vector<Figure>& figures);
    // A titled table in the text view.
    void table(std::string title, const Table& table, int indent = 2);
    // A file to write into --out-dir: a table as CSV, a plot as SVG.
    void csv(std::string file, const Table& table);
    void plot(std::string file, const PlotSpec& plot);

    std::string text() const;
    // Writes every file into `dir`; `written` gets their paths.
    core::Status write_files(const std::filesystem::path& dir, std::vector<std::string>& written) const;
    bool has_files() const { return !files_.empty(); }

private:
    nlohmann::json json_;
    std::string text_;
    std::vector<std::pair<std::string, std::string>> files_;  // name, content
};

// --out-dir, shared by every bench that writes files.
Option out_dir_option();

} // namespace pbdsplat::cli
