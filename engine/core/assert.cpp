#include "core/assert.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace pbdsplat::core {
namespace {
void default_handler(std::string_view cond, std::string_view msg, std::string_view file, int line) {
    std::fprintf(stderr, "%.*s:%d: assertion failed: %.*s\n  %.*s\n", int(file.size()), file.data(), line,
                 int(cond.size()), cond.data(), int(msg.size()), msg.data());
}
std::atomic<AssertHandler> g_handler{&default_handler};
} // namespace

AssertHandler set_assert_handler(AssertHandler handler) {
    return g_handler.exchange(handler ? handler : &default_handler);
}

void assert_failed(std::string_view condition, std::string_view message, std::string_view file, int line) {
    g_handler.load()(condition, message, file, line);
    // A handler may throw (tests do); if it returns, stopping is the only safe choice.
    std::abort();
}
} // namespace pbdsplat::core
