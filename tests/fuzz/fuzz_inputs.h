#pragma once
// What the fuzz tests and the libFuzzer targets feed the parsers: the check that an input got
// a clean answer. A parser may accept or refuse anything; it may not crash, hang, accept
// garbage (non-finite positions, indices out of range) or refuse without naming the input.
#include <string>

namespace pbdsplat::fuzz {

// Empty when the parser's answer to `text` is clean; else what was wrong with it.
std::string check_obj(const std::string& text);
std::string check_scene(const std::string& text);

} // namespace pbdsplat::fuzz
