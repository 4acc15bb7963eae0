// doctest entry point shared by the suites. Asserts throw instead of aborting, so a failed
// PBDSPLAT_ASSERT fails the test that triggered it and the rest still run.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "core/assert.h"
#include "support/skip.h"

namespace {
void throwing_handler(std::string_view cond, std::string_view msg, std::string_view file, int line) {
    throw std::logic_error(std::string(file) + ":" + std::to_string(line) + ": " + std::string(cond) + ": " +
                           std::string(msg));
}
} // namespace

int main(int argc, char** argv) {
    pbdsplat::core::set_assert_handler(throwing_handler);
    doctest::Context context(argc, argv);
    const int result = context.run();
    const int skipped = pbdsplat::test::skip_count().load();
    // ctest passes the code it treats as "skipped"; everything else passed, but not everything ran.
    if (const char* code = std::getenv("PBDSPLAT_SKIP_EXIT_CODE"); code && result == 0 && skipped > 0) {
        std::printf("SKIPPED: %d part(s) of this suite could not run on this machine (see the SKIPPED messages above)\n", skipped);
        return std::atoi(code);
    }
    return result;
}
