#pragma once
// Status and Result<T>: expected outcomes (a missing file, a malformed line, the end of the data)
// are returned, never thrown, so that callers must look at them. Messages name the file and the
// problem, e.g. "velodyne/0000000003.bin: size 1000 bytes is not a multiple of 16".

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

namespace artemis {

enum class StatusCode {
  kOk,
  kNotFound,         // a file or folder that should exist does not
  kInvalidArgument,  // a bad option, a frame range out of bounds
  kParseError,       // a file exists but its content is malformed
  kIoError,          // reading or writing failed
  kEndOfData,        // sequential reading reached the end
};

const char* toString(StatusCode code);

class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status ok() { return {}; }

  [[nodiscard]] bool isOk() const { return code_ == StatusCode::kOk; }
  [[nodiscard]] StatusCode code() const { return code_; }
  [[nodiscard]] const std::string& message() const { return message_; }
  // "parse error: calib.txt line 3: expected 12 numbers after 'Tr:', found 11"
  [[nodiscard]] std::string toString() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

inline Status notFound(std::string message) {
  return {StatusCode::kNotFound, std::move(message)};
}
inline Status invalidArgument(std::string message) {
  return {StatusCode::kInvalidArgument, std::move(message)};
}
inline Status parseError(std::string message) {
  return {StatusCode::kParseError, std::move(message)};
}
inline Status ioError(std::string message) {
  return {StatusCode::kIoError, std::move(message)};
}

// Thrown by Result::value() on an error result: a broken contract of the caller.
class StatusError : public std::runtime_error {
 public:
  explicit StatusError(const Status& status) : std::runtime_error(status.toString()), status_(status) {}
  [[nodiscard]] const Status& status() const { return status_; }

 private:
  Status status_;
};

// A value or the Status saying why there is none.
template <typename T>
class Result {
 public:
  Result(T value) : state_(std::move(value)) {}        // NOLINT(google-explicit-constructor)
  Result(Status status) : state_(std::move(status)) {  // NOLINT(google-explicit-constructor)
    if (std::get<Status>(state_).isOk()) {
      throw std::logic_error("Result constructed from an ok Status without a value");
    }
  }

  [[nodiscard]] bool isOk() const { return std::holds_alternative<T>(state_); }
  explicit operator bool() const { return isOk(); }

  [[nodiscard]] const Status& status() const {
    static const Status kOkStatus;
    return isOk() ? kOkStatus : std::get<Status>(state_);
  }

  T& value() & {
    check();
    return std::get<T>(state_);
  }
  const T& value() const& {
    check();
    return std::get<T>(state_);
  }
  T&& value() && {
    check();
    return std::get<T>(std::move(state_));
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  void check() const {
    if (!isOk()) throw StatusError(std::get<Status>(state_));
  }
  std::variant<T, Status> state_;
};

}  // namespace artemis
