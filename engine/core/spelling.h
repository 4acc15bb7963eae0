#pragma once
// What a mistyped name was probably meant to be, for the "did you mean" of an error message.
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace pbdsplat::core {

// The candidate nearest `word`, if any is near: within one edit (a letter inserted, dropped,
// changed, or two neighbours swapped) for a word under five letters, two for a longer one, and
// fewer edits than half its letters (so no guess for "x"), after
// folding case and taking '-' and ' ' as '_' on both sides ("Splat-Scale" is splat_scale). The
// first of equally near candidates wins; the candidate is returned as written.
std::optional<std::string> nearest_spelling(std::string_view word, std::span<const std::string> candidates);

} // namespace pbdsplat::core
