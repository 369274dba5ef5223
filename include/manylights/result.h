// Result<T>: the return type of fallible setup and loading. Either a value or a one-line message that
// names what failed (a path, a position, a reason). No exceptions cross the module boundary.
#pragma once
#include <optional>
#include <string>
#include <utility>

namespace ml {

struct Error {
    std::string message;
};

template <class T> class Result {
  public:
    Result(T value) : value_(std::move(value)) {}
    Result(Error error) : error_(std::move(error.message)) {}
    explicit operator bool() const { return value_.has_value(); }
    bool ok() const { return value_.has_value(); }
    T& value() { return *value_; }
    const T& value() const { return *value_; }
    T& operator*() { return *value_; }
    T* operator->() { return &*value_; }
    const std::string& error() const { return error_; }

  private:
    std::optional<T> value_;
    std::string error_;
};

template <> class Result<void> {
  public:
    Result() = default;
    Result(Error error) : error_(std::move(error.message)), ok_(false) {}
    explicit operator bool() const { return ok_; }
    bool ok() const { return ok_; }
    const std::string& error() const { return error_; }

  private:
    std::string error_;
    bool ok_ = true;
};

inline Error fail(std::string message) {
    return Error{std::move(message)};
}

} // namespace ml
