#pragma once
// What went wrong, for the message of an assertion on a Result or Status:
//   REQUIRE_MESSAGE(r.ok(), test::why(r));
// doctest builds an assertion's message even when it passes if asked to report successes
// (`-s`), and error() on a success asserts: this reads it only on a failure.
#include <string>

namespace pbdsplat::test {

template <class R>
std::string why(const R& r) {
    return r.ok() ? std::string() : r.error().to_string();
}

} // namespace pbdsplat::test
