// errorOf: the message of the std::invalid_argument a call throws, for the node's unit tests.
#pragma once

#include <stdexcept>
#include <string>

namespace cloth_sim::test {

/// The message @p f throws as std::invalid_argument, or "" when it does not throw.
template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace cloth_sim::test
