#pragma once
// DDS could not start: the profiles could not be loaded, or a participant, topic, reader or writer could not
// be created. The commands exit with status 4 on it (bad options and bad data are 2).

#include <stdexcept>

namespace dslam {

class DdsStartError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace dslam
