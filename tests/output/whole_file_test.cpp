#include "output/whole_file.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "support/child_process.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

TEST(WholeFile, ReplacesTheFileOnlyWhenCommitted) {
  const std::string path = test::TempPath("whole.csv");
  {
    WholeFile f(path);
    f << "a,b\n1,2\n";
    f.commit();
  }
  EXPECT_EQ(test::ReadFile(path), "a,b\n1,2\n");
  {
    WholeFile f(path);
    f << "a,b\n3,";  // interrupted before commit: the previous file stays, no partial file is left
    EXPECT_EQ(test::ReadFile(path), "a,b\n1,2\n");
  }
  EXPECT_EQ(test::ReadFile(path), "a,b\n1,2\n");
  EXPECT_FALSE(fs::exists(path + ".partial"));
  EXPECT_THROW(WholeFile("/proc/dslam_cannot_write/x.csv"), std::runtime_error);
}

}  // namespace
}  // namespace dslam
