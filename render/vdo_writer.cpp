#include "render/vdo_writer.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <map>
#include <stdexcept>
#include <vector>

namespace dslam {
namespace {
std::string Name(int k, const char* ext) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%06d.%s", k, ext);
  return buf;
}

// Writes rows top-down from `pixel(u, v, channel)`; VTK images start at the bottom row.
template <typename T, typename F>
void WritePng(const std::string& path, int width, int height, int channels, int vtk_type, F pixel) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(width, height, 1);
  image->AllocateScalars(vtk_type, channels);
  for (int v = 0; v < height; ++v) {
    auto* row = static_cast<T*>(image->GetScalarPointer(0, height - 1 - v, 0));
    for (int u = 0; u < width; ++u)
      for (int c = 0; c < channels; ++c) row[u * channels + c] = pixel(u, v, c);
  }
  vtkNew<vtkPNGWriter> writer;
  writer->SetCompressionLevel(1);  // zlib's fastest: a tenth off rendering time, files about as small (lossless)
  writer->SetFileName(path.c_str());
  writer->SetInputData(image);
  writer->Write();
  if (writer->GetErrorCode() != 0) throw std::runtime_error("cannot write " + path);
}

std::ofstream Open(const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << std::setprecision(9);
  return out;
}
}  // namespace

VdoWriter::VdoWriter(const std::string& dir, const Scene& scene, const CameraIntrinsics& camera,
                     double stereo_baseline_m)
    : dir_(dir), scene_(scene), camera_(camera), stereo_baseline_m_(stereo_baseline_m) {
  std::vector<std::string> subs = {"image_0", "depth", "mask", "semantic"};  // flow/: by the first writeFlow()
  if (stereo_baseline_m > 0.0) subs.push_back("image_1");
  for (const std::string& sub : subs) {
    std::error_code ec;
    std::filesystem::create_directories(dir + "/" + sub, ec);
    if (ec) throw std::runtime_error("cannot create " + dir + "/" + sub + ": " + ec.message());
  }
  poses_ = Open(dir + "/pose_gt.txt");
  objects_ = Open(dir + "/object_pose.txt");
  times_ = Open(dir + "/times.txt");
  std::ofstream categories = Open(dir + "/object_category.txt");
  for (const auto& o : scene.objects) categories << o.object_id << ' ' << o.category << '\n';
  std::ofstream calib = Open(dir + "/calib.txt");
  // Rectified cameras of one intrinsics: P0..P2 the left one; P3 the right one, -fx * baseline in its first row
  // (KITTI's convention), the left one again without stereo.
  for (int i = 0; i < 4; ++i)
    calib << 'P' << i << ": " << camera.fx << " 0 " << camera.cx << ' ' << (i == 3 ? -camera.fx * stereo_baseline_m : 0.0)
          << " 0 " << camera.fy << ' ' << camera.cy << " 0 0 0 1 0\n";
  calib << "R0_rect: 1 0 0 0 1 0 0 0 1\n";
}

void VdoWriter::writeFlow(int k, const FlowField& flow) {
  std::error_code ec;
  std::filesystem::create_directories(dir_ + "/flow", ec);
  if (ec) throw std::runtime_error("cannot create " + dir_ + "/flow: " + ec.message());
  WriteFlo(dir_ + "/flow/" + Name(k, "flo"), flow);
}

void VdoWriter::write(int k, const RgbdFrame& f, const RgbdFrame* right) {
  const int w = f.width, h = f.height;
  WritePng<uint8_t>(dir_ + "/image_0/" + Name(k, "png"), w, h, 3, VTK_UNSIGNED_CHAR,
                    [&](int u, int v, int c) { return f.rgb[3 * (static_cast<size_t>(v) * w + u) + c]; });
  if (stereo_baseline_m_ > 0.0) {
    if (!right || right->width != w || right->height != h)
      throw std::invalid_argument("frame " + std::to_string(k) + ": a stereo scene needs the right image, of the left's size");
    WritePng<uint8_t>(dir_ + "/image_1/" + Name(k, "png"), w, h, 3, VTK_UNSIGNED_CHAR,
                      [&](int u, int v, int c) { return right->rgb[3 * (static_cast<size_t>(v) * w + u) + c]; });
  }
  WritePng<uint16_t>(dir_ + "/depth/" + Name(k, "png"), w, h, 1, VTK_UNSIGNED_SHORT, [&](int u, int v, int) {
    const double mm = std::round(f.depth(u, v) * 1000.0);
    return static_cast<uint16_t>(std::clamp(mm, 0.0, 65535.0));
  });
  WritePng<uint16_t>(dir_ + "/mask/" + Name(k, "png"), w, h, 1, VTK_UNSIGNED_SHORT,
                     [&](int u, int v, int) { return f.id(u, v); });
  {
    // Formatted by hand: a KITTI-sized mask is half a million numbers.
    std::string text;
    text.reserve(static_cast<size_t>(w) * h * 3);
    char buf[8];
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const auto end = std::to_chars(buf, buf + sizeof buf, f.id(u, v)).ptr;
        text.append(buf, end);
        text.push_back(u + 1 < w ? ' ' : '\n');
      }
    std::ofstream sem = Open(dir_ + "/semantic/" + Name(k, "txt"));
    sem << text;
    if (!sem) throw std::runtime_error("error while writing " + dir_ + "/semantic/" + Name(k, "txt"));
  }

  const SE3& T = scene_.T_world_camera[k];
  const Mat4 M = T.matrix();
  poses_ << k;
  for (int i = 0; i < 16; ++i) poses_ << ' ' << M(i / 4, i % 4);
  poses_ << '\n';
  times_ << std::fixed << std::setprecision(6) << k / scene_.frame_rate_hz << '\n' << std::defaultfloat;

  // 2D boxes from the mask; poses in the current camera frame (bottom centre, rotation about y).
  struct Box2d {
    int x1 = 1 << 30, y1 = 1 << 30, x2 = -1, y2 = -1;
  };
  std::map<int, Box2d> boxes;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const int id = f.id(u, v);
      if (id == 0) continue;
      Box2d& b = boxes[id];
      b.x1 = std::min(b.x1, u), b.y1 = std::min(b.y1, v), b.x2 = std::max(b.x2, u), b.y2 = std::max(b.y2, v);
    }
  for (const auto& o : scene_.objects) {
    const auto pose = o.L_world_object.find(k);
    const auto box = boxes.find(o.object_id);
    if (pose == o.L_world_object.end() || box == boxes.end()) continue;
    const SE3 T_camera_object = T.inverse() * pose->second;
    const Mat3 R = T_camera_object.rotationMatrix();
    const Vec3& p = T_camera_object.translation();
    objects_ << k << '\t' << o.object_id << '\t' << box->second.x1 << '\t' << box->second.y1 << '\t' << box->second.x2
             << '\t' << box->second.y2 << '\t' << p.x() << '\t' << p.y() << '\t' << p.z() << '\t'
             << std::atan2(R(0, 2), R(0, 0)) << '\n';
  }
  poses_.flush();
  objects_.flush();
  times_.flush();
  if (!poses_ || !objects_ || !times_) throw std::runtime_error("error while writing the ground truth in " + dir_);
}

}  // namespace dslam
