#pragma once
// Debian's VTK renders only through X. When DISPLAY is unset, this starts a private Xvfb on a free
// display number for the lifetime of the object (and stops it afterwards); when DISPLAY is set it
// does nothing. Without Xvfb it reports one clear line instead of letting VTK crash.

#include <optional>
#include <string>
#include <sys/types.h>

namespace dslam {

class HeadlessDisplay {
 public:
  // nullopt with `error` filled when no display can be had.
  static std::optional<HeadlessDisplay> Acquire(std::string* error);

  HeadlessDisplay(HeadlessDisplay&& other) noexcept;
  HeadlessDisplay& operator=(HeadlessDisplay&&) = delete;
  HeadlessDisplay(const HeadlessDisplay&) = delete;
  ~HeadlessDisplay();

  bool ownsServer() const { return pid_ > 0; }
  const std::string& display() const { return display_; }

 private:
  HeadlessDisplay(pid_t pid, std::string display) : pid_(pid), display_(std::move(display)) {}
  pid_t pid_ = -1;  // our Xvfb, or -1 when an existing display is used
  std::string display_;
};

// Full path of an executable found on PATH, or empty.
std::string FindOnPath(const std::string& program);

}  // namespace dslam
