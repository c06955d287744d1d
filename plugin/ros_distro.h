#pragma once
// What differs on the wire between ROS 2 distributions, for the parts of ROS 2 serve speaks beyond plain
// messages: the width of a GID in the graph topic (plugin/ros_graph.h). No Fast DDS here: the command line
// checks its options with it.

#include <stdexcept>
#include <string>

namespace dslam {

// The GID width (octets) of a ROS 2 distribution: 24 up to Humble ("foxy", "galactic", "humble"), 16 from
// Iron on ("iron", "jazzy", "kilted", "lyrical", "rolling"). Throws std::invalid_argument naming the known ones.
inline int RosGidWidth(const std::string& distro) {
  for (const char* d : {"foxy", "galactic", "humble"})
    if (distro == d) return 24;
  for (const char* d : {"iron", "jazzy", "kilted", "lyrical", "rolling"})
    if (distro == d) return 16;
  throw std::invalid_argument("unknown ROS 2 distribution '" + distro +
                              "': use humble (also foxy, galactic) or jazzy (also iron, kilted, lyrical, rolling)");
}

}  // namespace dslam
