// The render cache that ctest's test processes share (tests/support/rendered_city.h): a scene asked for at
// once by two callers is rendered once, and whole.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>
#include <thread>

#include "support/rendered_city.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

ino_t InodeOf(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? st.st_ino : 0;
}

TEST(RenderCache, TwoCallersAtOnceGetOneSceneRenderedOnceAndWhole) {
  const std::string cache = test::TempPath("render_cache");
  std::string dir_a, dir_b;
  ino_t inode_a = 0, inode_b = 0;
  // Each caller notes the scene's inode as soon as it has it: a second render would have replaced the
  // directory (a new inode) after the first caller returned.
  auto ask = [&](std::string* dir, ino_t* inode) {
    *dir = test::RenderedCityIn(cache, "tiny", 2, 1, false, 0.25);
    *inode = InodeOf(*dir + "/odometry.txt");
  };
  std::thread a(ask, &dir_a, &inode_a), b(ask, &dir_b, &inode_b);
  a.join();
  b.join();
  EXPECT_EQ(dir_a, dir_b);
  ASSERT_NE(inode_a, 0u);
  EXPECT_EQ(inode_a, inode_b);
  EXPECT_EQ(inode_a, InodeOf(dir_a + "/odometry.txt"));
  int images = 0, partial = 0;
  for (const auto& e : fs::directory_iterator(dir_a + "/image_0")) images += e.path().extension() == ".png";
  for (const auto& e : fs::directory_iterator(cache))
    partial += e.path().filename().string().find(".partial.") != std::string::npos;
  EXPECT_EQ(images, 2);
  EXPECT_EQ(partial, 0);
}

}  // namespace
}  // namespace dslam
