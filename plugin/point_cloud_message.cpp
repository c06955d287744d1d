#include "plugin/point_cloud_message.h"

#include <cmath>
#include <cstring>

#include "plugin/image_message.h"

namespace dslam {
namespace {

constexpr uint8_t kFloat32 = 7;  // sensor_msgs/PointField FLOAT32

// The offset of float32 field `name` when the point holds it whole; -1 otherwise (with the reason).
int64_t FloatField(const sensor_msgs::msg::PointCloud2& msg, const std::string& name, std::string* problem) {
  for (const auto& f : msg.fields()) {
    if (f.name() != name) continue;
    if (f.datatype() != kFloat32 || f.count() != 1) {
      *problem = "field '" + name + "' is not one float32";
      return -1;
    }
    if (static_cast<uint64_t>(f.offset()) + 4 > msg.point_step()) {
      *problem = "field '" + name + "' at offset " + std::to_string(f.offset()) + " lies outside the " +
                 std::to_string(msg.point_step()) + "-byte point";
      return -1;
    }
    return f.offset();
  }
  *problem = "no field '" + name + "'";
  return -1;
}

}  // namespace

DecodedPointCloud DecodePointCloud(const sensor_msgs::msg::PointCloud2& msg) {
  DecodedPointCloud out;
  const std::string what = "LiDAR scan at " + std::to_string(StampToNs(msg.header().stamp())) + " ns";
  const uint64_t count = static_cast<uint64_t>(msg.width()) * msg.height();
  if (count > kMaxPointCloudPoints) {
    out.error = what + ": " + std::to_string(count) + " points, more than the " + std::to_string(kMaxPointCloudPoints) +
                " a scan may have";
    return out;
  }
  if (msg.is_bigendian()) {
    out.error = what + ": big-endian data is not supported";
    return out;
  }
  std::string problem;
  const int64_t x = FloatField(msg, "x", &problem), y = x < 0 ? -1 : FloatField(msg, "y", &problem),
                z = y < 0 ? -1 : FloatField(msg, "z", &problem);
  if (z < 0) {
    out.error = what + ": " + problem;
    return out;
  }
  std::string no_intensity;
  const int64_t intensity = FloatField(msg, "intensity", &no_intensity);  // optional
  if (static_cast<uint64_t>(msg.row_step()) < static_cast<uint64_t>(msg.width()) * msg.point_step()) {
    out.error = what + ": row_step " + std::to_string(msg.row_step()) + " is smaller than width x point_step";
    return out;
  }
  if (msg.data().size() != static_cast<uint64_t>(msg.row_step()) * msg.height()) {
    out.error = what + ": " + std::to_string(msg.data().size()) + " bytes of data for row_step " +
                std::to_string(msg.row_step()) + " x height " + std::to_string(msg.height());
    return out;
  }
  out.points.reserve(count);
  auto read = [](const uint8_t* p) {
    float v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  for (uint32_t row = 0; row < msg.height(); ++row) {
    const uint8_t* base = msg.data().data() + static_cast<size_t>(row) * msg.row_step();
    for (uint32_t i = 0; i < msg.width(); ++i) {
      const uint8_t* p = base + static_cast<size_t>(i) * msg.point_step();
      const Eigen::Vector4f point(read(p + x), read(p + y), read(p + z), intensity >= 0 ? read(p + intensity) : 0.0f);
      if (point.head<3>().allFinite()) out.points.push_back(point);  // a driver's "no return"
    }
  }
  return out;
}

sensor_msgs::msg::PointCloud2 EncodePointCloud(const std::vector<Eigen::Vector4f>& points, int64_t t_ns,
                                               const std::string& frame_id) {
  sensor_msgs::msg::PointCloud2 msg;
  msg.header().stamp(NsToStamp(t_ns));
  msg.header().frame_id(frame_id);
  msg.height(1);
  msg.width(static_cast<uint32_t>(points.size()));
  const char* names[] = {"x", "y", "z", "intensity"};
  for (uint32_t i = 0; i < 4; ++i) {
    sensor_msgs::msg::PointField f;
    f.name(names[i]);
    f.offset(4 * i);
    f.datatype(kFloat32);
    f.count(1);
    msg.fields().push_back(f);
  }
  msg.is_bigendian(false);
  msg.point_step(16);
  msg.row_step(static_cast<uint32_t>(16 * points.size()));
  msg.data().resize(16 * points.size());
  for (size_t i = 0; i < points.size(); ++i) std::memcpy(msg.data().data() + 16 * i, points[i].data(), 16);
  msg.is_dense(true);
  return msg;
}

}  // namespace dslam
