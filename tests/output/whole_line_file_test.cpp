#include "output/whole_line_file.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/temp_paths.h"

namespace dslam {
namespace {

std::string Contents(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(WholeLineFile, AFlushWritesTheWholeLinesAndKeepsTheUnfinishedOne) {
  const std::string path = test::TempPath("whole_line.csv");
  WholeLineFile f(path);
  ASSERT_TRUE(f);
  f << "a,b\n1,2\n3,";
  f.flush();
  EXPECT_EQ(Contents(path), "a,b\n1,2\n");
  f << "4\n5";
  f.flush();
  EXPECT_EQ(Contents(path), "a,b\n1,2\n3,4\n");
  f.close();  // what the program wrote, the unfinished last line too
  EXPECT_TRUE(f);
  EXPECT_EQ(Contents(path), "a,b\n1,2\n3,4\n5");
}

TEST(WholeLineFile, ManyRowsWithoutAFlushGoOutWholeAndMemoryStaysBounded) {
  const std::string path = test::TempPath("whole_line_big.csv");
  WholeLineFile f(path);
  const std::string row = "123456789,123456789,123456789,123456789\n";
  for (int i = 0; i < 60000; ++i) f << row.substr(0, 20) << row.substr(20);  // 2.4 MB, rows in two pieces
  const std::string on_disk = Contents(path);
  EXPECT_GT(on_disk.size(), 1000000u);  // written without a flush
  ASSERT_FALSE(on_disk.empty());
  EXPECT_EQ(on_disk.back(), '\n');
  EXPECT_EQ(on_disk.size() % row.size(), 0u);
}

TEST(WholeLineFile, AnUnwritablePathFailsTheStream) {
  WholeLineFile f(test::TempPath("no_such_dir") + "/x.csv");
  EXPECT_FALSE(f);
  EXPECT_FALSE(f.is_open());
}

// A writer killed at any moment (SIGKILL: nothing of its own runs) leaves whole rows, but for the cut at a
// page boundary that the kernel may make (below).
TEST(WholeLineFile, AProcessKilledWhileWritingLeavesWholeRows) {
  for (int trial = 0; trial < 5; ++trial) {
    const std::string path = test::TempPath("whole_line_killed_" + std::to_string(trial) + ".csv");
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      // At most ~1 GB whatever happens to the parent (a child left writing would fill the disk).
      WholeLineFile f(path);
      for (long i = 0; i < 20'000'000; ++i) {
        f << i << ',' << i * 7 << ',' << "some text to make a row long enough" << '\n';
        if (i % 97 == 0) f.flush();
      }
      _exit(0);
    }
    // Killed while it writes: once its first rows are out (on a loaded machine the child may take longer
    // than any fixed delay to start), then at a different moment in each trial.
    // (Its size, not its contents: reading a file that grows faster than it is read never ends.)
    std::error_code ec;
    for (int waited_ms = 0; waited_ms < 10000 && !(std::filesystem::file_size(path, ec) > 0 && !ec); waited_ms += 5)
      usleep(5000);
    usleep(5000 + 15000 * trial);
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
    const std::string text = Contents(path);
    ASSERT_FALSE(text.empty()) << trial;
    // Every line that ended is a whole, right row. The one exception no program can rule out: Linux stops a
    // write(2) at a page boundary of the file when SIGKILL arrives during it, so a row that straddles one
    // can be cut there (seen once in a CI run); anywhere else a cut would be ours.
    const size_t end_of_rows = text.rfind('\n') + 1;
    std::istringstream rows(text.substr(0, end_of_rows));
    long expected = 0;
    const auto row = [](long i) { return std::to_string(i) + ',' + std::to_string(i * 7) + ",some text to make a row long enough"; };
    for (std::string line; std::getline(rows, line); ++expected) ASSERT_EQ(line, row(expected)) << trial;
    if (end_of_rows < text.size()) {
      EXPECT_EQ(text.size() % 4096, 0u) << trial << ": a row cut at byte " << text.size() << ", not at a page boundary";
      EXPECT_EQ(row(expected).rfind(text.substr(end_of_rows), 0), 0u) << trial << ": the cut row is not a prefix of the next row";
    }
    std::filesystem::remove(path, ec);
  }
}

}  // namespace
}  // namespace dslam
