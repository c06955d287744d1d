#include "output/dir_lock.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <optional>

#include "support/temp_paths.h"

namespace dslam {
namespace {

TEST(DirLock, AFolderIsTakenByOneHolderAtATimeAndFreedWhenItGoes) {
  // Two serves with the same --out and vehicle used to interleave their files in one folder.
  const std::string dir = test::TempPath("dir_lock") + "/vehicle";
  std::optional<DirLock> first(dir);
  EXPECT_TRUE(std::filesystem::is_directory(dir));
  try {
    DirLock second(dir);
    ADD_FAILURE() << "the folder was taken twice";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("output folder " + dir + " is in use by another process (pid "),
              std::string::npos)
        << e.what();
  }
  first.reset();
  EXPECT_NO_THROW(DirLock again(dir));
}

}  // namespace
}  // namespace dslam
