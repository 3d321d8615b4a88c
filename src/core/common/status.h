// Expected failures are values with a reason ("registration rejected: 7 inliers < 20"), not
// exceptions. Exceptions are kept for load/API boundaries (see ConfigError).
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace icgm {

class Status {
 public:
  static Status Ok() { return Status(); }
  static Status Error(std::string reason) { return Status(std::move(reason)); }
  bool ok() const { return reason_.empty(); }
  explicit operator bool() const { return ok(); }
  const std::string& reason() const { return reason_; }

 private:
  Status() = default;
  explicit Status(std::string reason)
      : reason_(reason.empty() ? std::string("unspecified error") : std::move(reason)) {}
  std::string reason_;
};

// Thrown only at load boundaries: unreadable/invalid configuration, dataset or map files.
class LoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace icgm
