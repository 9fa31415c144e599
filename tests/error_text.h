// Small helpers for tests that check what an error says: whether a text contains a
// part, and the message of the exception a call throws.
#pragma once

#include <stdexcept>
#include <string>

namespace hrad::test {

inline bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

/// The message of the E that f() throws; "" when it throws nothing (an exception of
/// another type passes through, and fails the test).
template <class E = std::invalid_argument, class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

}  // namespace hrad::test
