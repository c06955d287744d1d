#pragma once
// Resident set size of this process, MB (Linux; 0 elsewhere).
#include <cstdlib>
#include <fstream>
#include <string>

namespace dslam::bench {
inline double RssMb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
  return 0.0;
}
}  // namespace dslam::bench
