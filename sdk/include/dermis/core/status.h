// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Status: the error type of every Dermis call that can fail on bad input.
///
/// Dermis never throws. Calls that can fail on user data return a Status; a non-ok Status
/// carries a human-readable message that names the file, line or element at fault.
#pragma once

#include <string>
#include <utility>

namespace dermis {

/// What kind of failure a Status reports.
enum class StatusCode {
  kOk = 0,
  kInvalidInput,  ///< The data is malformed (bad index, NaN, non-manifold, ...).
  kIoError,       ///< A file could not be opened, read or written.
  kUnsupported,   ///< Valid data that this version cannot handle.
  kInternal,      ///< A numerical or internal failure that should not happen.
};

/// Result of a fallible operation: a code plus a message (empty when ok).
class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status Ok() { return Status(); }
  static Status InvalidInput(std::string m) { return {StatusCode::kInvalidInput, std::move(m)}; }
  static Status IoError(std::string m) { return {StatusCode::kIoError, std::move(m)}; }
  static Status Unsupported(std::string m) { return {StatusCode::kUnsupported, std::move(m)}; }
  static Status Internal(std::string m) { return {StatusCode::kInternal, std::move(m)}; }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }

  /// Returns a copy whose message is prefixed with `context + ": "`.
  Status WithContext(const std::string& context) const {
    if (ok()) return *this;
    return Status(code_, context + ": " + message_);
  }

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

}  // namespace dermis
