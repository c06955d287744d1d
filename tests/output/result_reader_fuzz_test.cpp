// Every reader of our own result files, fed damaged copies of real results: each one is read or rejected
// with an error naming the file, never a crash. (dslam figures segfaulted on a CSV with fewer columns.)
#include "output/result_reader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "output/run_report.h"
#include "pipeline/run_sequence.h"
#include "simulation/scenarios.h"
#include "support/child_process.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

const std::string& GoodResults() {
  static const std::string dir = [] {
    ScenarioOptions opt;
    opt.num_frames = 12;
    const Sequence seq = MakeScenario("paper", opt);
    RunConfig config;
    config.backend.default_mode = MotionMode::kConstant;
    RunSequenceOptions run;
    run.methods = {Method::kOurs};
    const std::string out = test::TempPath("fuzz_good");
    WriteRunOutputs(out, seq, RunSequence(seq, config, run), {{"command", "test"}});
    return out;
  }();
  return dir;
}

const char* kFiles[] = {"metrics.json", "camera_gt.tum", "camera_ours.tum", "object_speeds.csv",
                        "object_motions.csv", "object_centroids_gt.csv", "map_points.csv", "objects.csv"};

// Reads `dir`; fails the test on anything but success or a std::runtime_error that names the file.
void ExpectReadOrNamedError(const std::string& dir, const std::string& file, const std::string& what) {
  try {
    ReadRunResults(dir);
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << what << ": " << e.what();
  }
}

TEST(ResultReaderFuzz, FewerColumnsIsANamedError) {
  for (const char* file : {"object_speeds.csv", "object_motions.csv", "map_points.csv", "object_centroids_gt.csv"}) {
    const std::string dir = test::TempPath(std::string("fuzz_cols_") + file);
    fs::remove_all(dir);
    fs::copy(GoodResults(), dir);
    std::ofstream(dir + "/" + file) << "frame,object_id\n1,1\n";
    try {
      ReadRunResults(dir);
      ADD_FAILURE() << file << " with two columns was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("expected the columns"), std::string::npos) << e.what();
    }
  }
}

TEST(ResultReaderFuzz, DamagedFilesAreReadOrRejectedNeverACrash) {
  std::mt19937 rng(7);
  const std::string dir = test::TempPath("fuzz_damaged");
  for (const char* file : kFiles) {
    const std::string good = test::ReadFile(GoodResults() + "/" + file);
    ASSERT_FALSE(good.empty()) << file;
    for (int trial = 0; trial < 40; ++trial) {
      std::string bad = good;
      const size_t at = std::uniform_int_distribution<size_t>(0, bad.size() - 1)(rng);
      switch (trial % 5) {
        case 0: bad.resize(at); break;                                      // truncated anywhere
        case 1: bad[at] = static_cast<char>(rng() % 256); break;            // one byte changed
        case 2: bad.insert(at, ",,"); break;                                // extra fields
        case 3: bad.erase(at, std::min<size_t>(8, bad.size() - at)); break;  // bytes lost
        case 4: bad.insert(at, "\n1e999,nan,-,\n"); break;                  // a bogus line
      }
      fs::remove_all(dir);
      fs::copy(GoodResults(), dir);
      std::ofstream(dir + "/" + file, std::ios::binary) << bad;
      ExpectReadOrNamedError(dir, file, std::string(file) + " trial " + std::to_string(trial));
    }
  }
}

}  // namespace
}  // namespace dslam
