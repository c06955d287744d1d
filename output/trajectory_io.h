#pragma once
// Trajectory files that evo and other tools read: TUM ("t tx ty tz qx qy qz qw") and KITTI
// (12 numbers of the 3x4 matrix, row-major). Throws std::runtime_error naming the file on failure.

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "geometry/se3.h"

namespace dslam {

// One line of each format (the stream's number format as the caller set it: fixed, 9 digits).
void PutTumLine(std::ostream& out, int64_t t_ns, const SE3& pose);
void PutKittiLine(std::ostream& out, const SE3& pose);

void WriteTumTrajectory(const std::string& path, const std::vector<int64_t>& t_ns, const std::vector<SE3>& poses);
void WriteKittiTrajectory(const std::string& path, const std::vector<SE3>& poses);
// Reads a TUM file; throws std::runtime_error with file and line on a malformed line.
std::vector<SE3> ReadTumTrajectory(const std::string& path, std::vector<int64_t>* t_ns = nullptr);

}  // namespace dslam
