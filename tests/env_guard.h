// EnvGuard: sets an environment variable for the lifetime of the guard, then unsets it
// (or restores its earlier value), so a synthetic topology (HWLOC_SYNTHETIC) or any
// other setting never leaks into other tests.
#pragma once

#include <cstdlib>
#include <optional>
#include <string>

namespace hrad {

class EnvGuard {
 public:
  EnvGuard(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value, 1);
  }
  ~EnvGuard() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }
  EnvGuard(const EnvGuard&) = delete;
  EnvGuard& operator=(const EnvGuard&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace hrad
