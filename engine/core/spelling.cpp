#include "core/spelling.h"

#include <algorithm>
#include <cctype>
#include <vector>

namespace pbdsplat::core {
namespace {

std::string folded(std::string_view s) {
    std::string out(s);
    for (char& c : out) {
        c = char(std::tolower(static_cast<unsigned char>(c)));
        if (c == '-' || c == ' ') c = '_';
    }
    return out;
}

// Edits (insert, delete, substitute, swap two neighbours) from a to b.
size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
    for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (size_t i = 1; i <= a.size(); ++i)
        for (size_t j = 1; j <= b.size(); ++j) {
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[a.size()][b.size()];
}

} // namespace

std::optional<std::string> nearest_spelling(std::string_view word, std::span<const std::string> candidates) {
    const std::string w = folded(word);
    const size_t allowed = w.size() < 5 ? 1 : 2;
    std::optional<std::string> best;
    size_t best_distance = allowed + 1;
    for (const std::string& c : candidates) {
        const size_t d = edit_distance(w, folded(c));
        // A word of one or two letters one edit from another is no more like it than unlike ("x", "y").
        if (d < best_distance && 2 * d < w.size()) best_distance = d, best = c;
    }
    return best;
}

} // namespace pbdsplat::core
