#pragma once
// Asserts with a replaceable handler (tests install one that throws, tools one that prints).
// PBDSPLAT_ASSERT is for programming errors only: bad user input comes back as core::Error.
#include <string_view>

namespace pbdsplat::core {

using AssertHandler = void (*)(std::string_view condition, std::string_view message,
                               std::string_view file, int line);

// Installs a handler and returns the previous one. The default prints and aborts.
AssertHandler set_assert_handler(AssertHandler handler);
[[noreturn]] void assert_failed(std::string_view condition, std::string_view message,
                                std::string_view file, int line);

} // namespace pbdsplat::core

// Always on: these guard invariants whose violation would corrupt GPU memory or the solver.
#define PBDSPLAT_ASSERT(cond, msg)                                                       \
    do {                                                                                 \
        if (!(cond)) ::pbdsplat::core::assert_failed(#cond, (msg), __FILE__, __LINE__); \
    } while (0)

// Debug-only checks on hot paths.
#ifndef NDEBUG
#define PBDSPLAT_DEBUG_ASSERT(cond, msg) PBDSPLAT_ASSERT(cond, msg)
#else
#define PBDSPLAT_DEBUG_ASSERT(cond, msg) ((void)0)
#endif
