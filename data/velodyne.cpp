#include "data/velodyne.h"

#include <fstream>
#include <stdexcept>

namespace dslam {

std::vector<Eigen::Vector4f> ReadVelodyneScan(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::runtime_error("cannot open LiDAR scan " + path);
  const std::streamsize bytes = in.tellg();
  if (bytes % 16 != 0)
    throw std::runtime_error(path + ": " + std::to_string(bytes) +
                             " bytes is not a whole number of 16-byte x y z reflectance records (truncated scan?)");
  std::vector<Eigen::Vector4f> points(static_cast<size_t>(bytes / 16));
  in.seekg(0);
  if (!points.empty() && !in.read(reinterpret_cast<char*>(points.data()), bytes))
    throw std::runtime_error("error while reading LiDAR scan " + path);
  return points;
}

}  // namespace dslam
