#include "render/rgbd_renderer.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCubeSource.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTexture.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

namespace dslam {
namespace {

constexpr double kTextureRepeatM = 4.0;  // a static texture tile covers 4 m x 4 m

// Procedural texture rich in corners: random grey-level cells at two scales plus coloured discs.
vtkSmartPointer<vtkTexture> MakeTexture(uint32_t seed, bool mipmapped) {
  constexpr int kSize = 256;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> level(20, 235), coord(0, kSize - 1), radius(3, 14);
  std::vector<uint8_t> pixels(kSize * kSize * 3);
  const int coarse = 32, fine = 8;
  std::vector<int> coarse_cells((kSize / coarse) * (kSize / coarse)), fine_cells((kSize / fine) * (kSize / fine));
  for (int& c : coarse_cells) c = level(rng);
  for (int& c : fine_cells) c = level(rng);
  const int tint = seed % 3;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const int g = (coarse_cells[(y / coarse) * (kSize / coarse) + x / coarse] + fine_cells[(y / fine) * (kSize / fine) + x / fine]) / 2;
      for (int c = 0; c < 3; ++c) pixels[3 * (y * kSize + x) + c] = static_cast<uint8_t>(c == tint ? std::min(255, g + 20) : g);
    }
  for (int d = 0; d < 40; ++d) {
    const int cx = coord(rng), cy = coord(rng), r = radius(rng);
    const uint8_t col[3] = {static_cast<uint8_t>(level(rng)), static_cast<uint8_t>(level(rng)), static_cast<uint8_t>(level(rng))};
    for (int y = std::max(0, cy - r); y < std::min(kSize, cy + r); ++y)
      for (int x = std::max(0, cx - r); x < std::min(kSize, cx + r); ++x)
        if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r)
          for (int c = 0; c < 3; ++c) pixels[3 * (y * kSize + x) + c] = col[c];
  }
  vtkNew<vtkImageData> image;
  image->SetDimensions(kSize, kSize, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  std::copy(pixels.begin(), pixels.end(), static_cast<uint8_t*>(image->GetScalarPointer()));
  auto texture = vtkSmartPointer<vtkTexture>::New();
  texture->SetInputData(image);
  texture->RepeatOn();
  texture->InterpolateOn();
  // Mipmaps average the texture over each pixel's footprint, as a camera does. Without them the side of
  // a passing car, seen at a grazing angle, sparkles with aliasing that changes from frame to frame and
  // that optical flow follows. Only boxes get them: they cover little of the image, and mipmapping the
  // whole world would halve the software renderer's frame rate.
  texture->SetMipmap(mipmapped);
  return texture;
}

vtkSmartPointer<vtkPolyData> QuadPolyData(const RenderQuad& q) {
  vtkNew<vtkPoints> points;
  for (const auto& c : q.corners_world) points->InsertNextPoint(c.x(), c.y(), c.z());
  const double su = (q.corners_world[1] - q.corners_world[0]).norm() / kTextureRepeatM;
  const double sv = (q.corners_world[3] - q.corners_world[0]).norm() / kTextureRepeatM;
  vtkNew<vtkFloatArray> tcoords;
  tcoords->SetNumberOfComponents(2);
  const float uv[4][2] = {{0, 0}, {static_cast<float>(su), 0}, {static_cast<float>(su), static_cast<float>(sv)},
                          {0, static_cast<float>(sv)}};
  for (const auto& t : uv) tcoords->InsertNextTuple(t);
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[4] = {0, 1, 2, 3};
  polys->InsertNextCell(4, ids);
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(polys);
  poly->GetPointData()->SetTCoords(tcoords);
  return poly;
}

vtkSmartPointer<vtkActor> MakeActor(vtkPolyData* poly) {
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

// Flat, unlit colour that encodes an instance id exactly in the red and green bytes.
void MakeMaskMaterial(vtkActor* actor, int id) {
  actor->GetProperty()->SetLighting(false);
  actor->GetProperty()->SetColor((id & 0xff) / 255.0, ((id >> 8) & 0xff) / 255.0, 0.0);
  actor->SetTexture(nullptr);
}

vtkSmartPointer<vtkMatrix4x4> ToVtk(const SE3& T) {
  auto m = vtkSmartPointer<vtkMatrix4x4>::New();
  const Mat4 M = T.matrix();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m->SetElement(r, c, M(r, c));
  return m;
}
}  // namespace

struct RgbdRenderer::Impl {
  CameraIntrinsics camera;
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  std::vector<vtkSmartPointer<vtkActor>> static_colour, static_mask;
  std::map<std::pair<uint32_t, bool>, vtkSmartPointer<vtkTexture>> textures;

  vtkTexture* texture(uint32_t seed, bool mipmapped) {
    auto& t = textures[{seed, mipmapped}];
    if (!t) t = MakeTexture(seed, mipmapped);
    return t;
  }

  // Reads the current frame buffer (colour, or depth) into top-down rows.
  void grab(bool depth, std::vector<uint8_t>* rgb, std::vector<float>* z) {
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(window);
    grab->ReadFrontBufferOff();
    if (depth) grab->SetInputBufferTypeToZBuffer();
    grab->Update();
    vtkImageData* image = grab->GetOutput();
    const int w = camera.width, h = camera.height;
    const int channels = image->GetNumberOfScalarComponents();
    for (int y = 0; y < h; ++y) {
      const size_t v = static_cast<size_t>(h - 1 - y);  // VTK rows start at the bottom
      if (depth) {
        const auto* row = static_cast<const float*>(image->GetScalarPointer(0, y, 0));
        std::copy(row, row + w, z->begin() + v * w);
      } else {
        const auto* row = static_cast<const uint8_t*>(image->GetScalarPointer(0, y, 0));
        for (int u = 0; u < w; ++u)
          for (int c = 0; c < 3; ++c) (*rgb)[3 * (v * w + u) + c] = row[channels * u + c];
      }
    }
  }
};

RgbdRenderer::RgbdRenderer(const CameraIntrinsics& camera, const std::vector<RenderQuad>& static_world)
    : impl_(std::make_unique<Impl>()) {
  if (camera.width < 16 || camera.height < 16 || !(camera.fx > 0.0) || !(camera.fy > 0.0) ||
      !(camera.near_m > 0.0 && camera.far_m > camera.near_m))
    throw std::invalid_argument("camera intrinsics out of range");
  impl_->camera = camera;
  impl_->window->SetOffScreenRendering(1);
  impl_->window->SetMultiSamples(0);
  impl_->window->SetSize(camera.width, camera.height);
  impl_->window->AddRenderer(impl_->renderer);
  impl_->renderer->SetBackground(0.0, 0.0, 0.0);
  for (const auto& quad : static_world) {
    auto poly = QuadPolyData(quad);
    auto colour = MakeActor(poly);
    colour->SetTexture(impl_->texture(quad.texture_seed, false));
    colour->GetProperty()->SetAmbient(0.6);
    colour->GetProperty()->SetDiffuse(0.4);
    auto mask = MakeActor(poly);
    MakeMaskMaterial(mask, 0);
    impl_->static_colour.push_back(colour);
    impl_->static_mask.push_back(mask);
  }
}

RgbdRenderer::~RgbdRenderer() = default;

RgbdFrame RgbdRenderer::render(const SE3& T_world_camera, const std::vector<RenderBox>& objects) {
  Impl& s = *impl_;
  const CameraIntrinsics& K = s.camera;
  // Pinhole camera: x right, y down, z forward; vertical view angle from fy; principal point by
  // shifting the window centre (VTK's view is centred on the optical axis otherwise).
  vtkCamera* cam = s.renderer->GetActiveCamera();
  const Vec3 centre = T_world_camera.translation();
  const Mat3 R = T_world_camera.rotationMatrix();
  const Vec3 focal = centre + R.col(2), up = -R.col(1);
  cam->SetPosition(centre.data());
  cam->SetFocalPoint(focal.data());
  cam->SetViewUp(up.data());
  cam->SetViewAngle(2.0 * std::atan(0.5 * K.height / K.fy) * kRadToDeg);
  // OpenCV pixel centres are integers, OpenGL's are at +0.5: hence the half pixel.
  cam->SetWindowCenter(-(K.cx + 0.5 - 0.5 * K.width) / (0.5 * K.width), (K.cy + 0.5 - 0.5 * K.height) / (0.5 * K.height));
  cam->SetClippingRange(K.near_m, K.far_m);

  std::vector<vtkSmartPointer<vtkActor>> box_colour, box_mask;
  for (const auto& box : objects) {
    if (box.object_id < 1 || box.object_id > 0xffff) throw std::invalid_argument("object id out of 1..65535");
    vtkNew<vtkCubeSource> cube;
    cube->SetXLength(box.l);
    cube->SetYLength(box.h);
    cube->SetZLength(box.w);
    cube->SetCenter(0.0, -box.h / 2.0, 0.0);
    cube->Update();
    auto colour = MakeActor(cube->GetOutput());
    colour->SetUserMatrix(ToVtk(box.L_world_object));
    colour->SetTexture(s.texture(box.texture_seed, true));
    colour->GetProperty()->SetAmbient(0.6);
    colour->GetProperty()->SetDiffuse(0.4);
    auto mask = MakeActor(cube->GetOutput());
    mask->SetUserMatrix(ToVtk(box.L_world_object));
    MakeMaskMaterial(mask, box.object_id);
    box_colour.push_back(colour);
    box_mask.push_back(mask);
  }

  RgbdFrame frame;
  frame.width = K.width;
  frame.height = K.height;
  const size_t n = static_cast<size_t>(K.width) * K.height;
  frame.rgb.resize(3 * n);
  frame.depth_m.resize(n);
  frame.instance.resize(n);

  // Pass 1: textured colour and the depth buffer.
  s.renderer->RemoveAllViewProps();
  for (auto& a : s.static_colour) s.renderer->AddActor(a);
  for (auto& a : box_colour) s.renderer->AddActor(a);
  s.window->Render();
  s.grab(false, &frame.rgb, nullptr);
  s.grab(true, nullptr, &frame.depth_m);
  const double n_m = K.near_m, f_m = K.far_m;
  for (float& z : frame.depth_m)  // OpenGL depth in [0, 1] -> metric z; the far plane means no hit
    z = z >= 1.0f ? 0.0f : static_cast<float>(n_m * f_m / (f_m - z * (f_m - n_m)));

  // Pass 2: flat colours that encode the instance ids.
  s.renderer->RemoveAllViewProps();
  for (auto& a : s.static_mask) s.renderer->AddActor(a);
  for (auto& a : box_mask) s.renderer->AddActor(a);
  s.window->Render();
  std::vector<uint8_t> ids(3 * n);
  s.grab(false, &ids, nullptr);
  for (size_t i = 0; i < n; ++i) frame.instance[i] = static_cast<uint16_t>(ids[3 * i] | (ids[3 * i + 1] << 8));
  s.renderer->RemoveAllViewProps();
  return frame;
}

}  // namespace dslam
