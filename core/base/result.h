// Result<T>: a value or an Error a user can act on, plus warnings that travel beside a success.
#pragma once

#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace cagewrap {

enum class ErrorCode {
  kFileNotFound,
  kFileUnreadable,
  kUnsupportedFormat,
  kParse,
  kEmpty,
  kNonFinite,
  kIndexOutOfRange,
  kTopologyMismatch,
  kNoValidElements,
  kInvalidArgument,
  kVersion,
  kCancelled,
  kWrite,
};

const char* error_code_name(ErrorCode code);

struct Error {
  ErrorCode code;
  std::string message;  // one sentence naming the file, element or vertex
};

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : data_(std::move(value)) {}
  Result(Error error) : data_(std::move(error)) {}

  bool ok() const { return data_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() & { return std::get<0>(data_); }
  const T& value() const& { return std::get<0>(data_); }
  T&& value() && { return std::get<0>(std::move(data_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const Error& error() const { return std::get<1>(data_); }

 private:
  std::variant<T, Error> data_;
};

struct Ok {};
using Status = Result<Ok>;

inline Error make_error(ErrorCode code, std::string message) { return Error{code, std::move(message)}; }

}  // namespace cagewrap
