#pragma once
// Unsets DISPLAY for a scope, as on a headless server, so that the project's own Xvfb handling runs.

#include <cstdlib>
#include <string>

namespace dslam::test {

class ScopedNoDisplay {
 public:
  ScopedNoDisplay() {
    const char* display = std::getenv("DISPLAY");
    saved_ = display ? display : "";
    ::unsetenv("DISPLAY");
  }
  ~ScopedNoDisplay() {
    if (!saved_.empty()) ::setenv("DISPLAY", saved_.c_str(), 1);
  }
  ScopedNoDisplay(const ScopedNoDisplay&) = delete;
  ScopedNoDisplay& operator=(const ScopedNoDisplay&) = delete;

 private:
  std::string saved_;
};

}  // namespace dslam::test
