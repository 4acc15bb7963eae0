#pragma once
// Recoverable errors come back as values. An Error carries where it happened (file and line of
// the user's input, when there is one) and what is wrong, ready to print as one line.
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "core/assert.h"

namespace pbdsplat::core {

struct Error {
    std::string message;   // what is wrong, and how to fix it when we know
    std::string file;      // input file, if any
    int line = 0;          // 1-based line in `file`, 0 when not applicable

    // "file:line: message", or just the message.
    std::string to_string() const;
};

inline Error make_error(std::string message) { return Error{std::move(message), {}, 0}; }
inline Error make_error(std::string file, int line, std::string message) {
    return Error{std::move(message), std::move(file), line};
}

template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::move(value)) {}
    Result(Error error) : v_(std::move(error)) {}

    bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & { PBDSPLAT_ASSERT(ok(), "Result::value() on an error: check ok() first"); return std::get<0>(v_); }
    T&& value() && { PBDSPLAT_ASSERT(ok(), "Result::value() on an error: check ok() first"); return std::get<0>(std::move(v_)); }
    const T& value() const& { PBDSPLAT_ASSERT(ok(), "Result::value() on an error: check ok() first"); return std::get<0>(v_); }
    const Error& error() const { PBDSPLAT_ASSERT(!ok(), "Result::error() on a value"); return std::get<1>(v_); }

    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }

private:
    std::variant<T, Error> v_;
};

// For operations that return nothing but can fail.
class [[nodiscard]] Status {
public:
    Status() = default;
    Status(Error error) : error_(std::move(error)) {}
    static Status success() { return {}; }
    bool ok() const { return !error_.has_value(); }
    explicit operator bool() const { return ok(); }
    const Error& error() const { PBDSPLAT_ASSERT(!ok(), "Status::error() on success"); return *error_; }

private:
    std::optional<Error> error_;
};

} // namespace pbdsplat::core

// Propagates an error from an expression returning Status or Result<T>.
#define PBDSPLAT_TRY(expr)                                   \
    do {                                                     \
        auto&& pbdsplat_try_ = (expr);                       \
        if (!pbdsplat_try_.ok()) return pbdsplat_try_.error(); \
    } while (0)
