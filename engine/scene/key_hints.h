#pragma once
// Internal to the scene room: what an unknown key in a scene file was probably meant to be, said
// beside the error so a user fixes a typo or a misplaced key without reading the whole format.
#include <set>
#include <string>
#include <string_view>

namespace pbdsplat::scene {

// " (did you mean 'iterations'?)" where `key` is a near spelling of a key its table reads
// (`asked`: every key the reader looked up there); else " (a key of [simulation])" where another
// section reads a key of that name; else "". `path`: the table's own path ("" at the top).
std::string unknown_key_hint(std::string_view key, const std::set<std::string>& asked, std::string_view path);

} // namespace pbdsplat::scene
