// doctest entry point shared by the suites. Asserts throw instead of aborting, so a failed
// PBDSPLAT_ASSERT fails the test that triggered it and the rest still run.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <stdexcept>
#include <string>

#include "core/assert.h"

namespace {
void throwing_handler(std::string_view cond, std::string_view msg, std::string_view file, int line) {
    throw std::logic_error(std::string(file) + ":" + std::to_string(line) + ": " + std::string(cond) + ": " +
                           std::string(msg));
}
} // namespace

int main(int argc, char** argv) {
    pbdsplat::core::set_assert_handler(throwing_handler);
    doctest::Context context(argc, argv);
    return context.run();
}
