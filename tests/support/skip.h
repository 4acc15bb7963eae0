#pragma once
// A test (or part of one) that cannot run on this machine says why and is counted. Under ctest
// the suite then exits with SKIP_RETURN_CODE (see test_main.cpp and tests/CMakeLists.txt), so
// the summary lists it as skipped instead of passed; run by hand, the binary still exits 0.
#include <doctest/doctest.h>

#include <atomic>
#include <string>

namespace pbdsplat::test {

inline std::atomic<int>& skip_count() {
    static std::atomic<int> n{0};
    return n;
}

inline void skip(const std::string& why) {
    ++skip_count();
    MESSAGE("SKIPPED: " << why);
}

} // namespace pbdsplat::test
