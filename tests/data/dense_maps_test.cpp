#include "data/dense_maps.h"

#include <gtest/gtest.h>

#include "support/temp_paths.h"

#include <cmath>
#include <filesystem>
#include <fstream>

namespace dslam {
namespace {

using test::TempDir;
using test::TempPath;

const std::string kSamples = std::string(DSLAM_SHARED_DATA_DIR) + "/kitti_tracking/samples";


TEST(ReadFlo, ReadsTheKittiSample) {
  const std::string path = kSamples + "/0000_flow_000000.flo";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data absent: " << path;
  const FlowField flow = ReadFlo(path);
  EXPECT_EQ(flow.width, 1242);
  EXPECT_EQ(flow.height, 375);
  double mean_abs_u = 0.0;
  bool finite = true;
  for (size_t i = 0; i < flow.uv.size(); i += 2) {
    finite &= std::isfinite(flow.uv[i]) && std::isfinite(flow.uv[i + 1]);
    mean_abs_u += std::abs(flow.uv[i]);
  }
  mean_abs_u /= flow.uv.size() / 2;
  EXPECT_TRUE(finite);
  // Forward driving between consecutive frames: a few pixels of flow on average, not zero, not wild.
  EXPECT_GT(mean_abs_u, 0.1);
  EXPECT_LT(mean_abs_u, 50.0);
}

TEST(ReadFlo, RoundTripAndBadFiles) {
  const std::string path = TempPath("a.flo");
  {
    std::ofstream out(path, std::ios::binary);
    const float magic = 202021.25f;
    const int32_t w = 2, h = 1;
    const float data[4] = {1.5f, -2.0f, 0.25f, 3.0f};
    out.write(reinterpret_cast<const char*>(&magic), 4);
    out.write(reinterpret_cast<const char*>(&w), 4);
    out.write(reinterpret_cast<const char*>(&h), 4);
    out.write(reinterpret_cast<const char*>(data), sizeof data);
  }
  const FlowField f = ReadFlo(path);
  EXPECT_EQ(f.u(1, 0), 0.25f);
  EXPECT_EQ(f.v(0, 0), -2.0f);
  float uv[4] = {};
  ReadFloInto(path, 2, 1, uv);  // straight into the caller's buffer
  EXPECT_EQ(uv[2], 0.25f);
  EXPECT_EQ(uv[1], -2.0f);
  try {
    ReadFloInto(path, 1, 2, uv);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": flow is 2x1 but the image is 1x2"), std::string::npos) << e.what();
  }
  std::filesystem::resize_file(path, 12 + 8);  // truncated data
  EXPECT_THROW(ReadFlo(path), std::runtime_error);
  {
    // A header claiming 100000x100000 (80 GB of flow) on a small file: an error naming it, before any
    // allocation (it was a bare std::bad_alloc).
    std::ofstream out(path, std::ios::binary);
    const float magic = 202021.25f;
    const int32_t huge = 100000;
    out.write(reinterpret_cast<const char*>(&magic), 4);
    out.write(reinterpret_cast<const char*>(&huge), 4);
    out.write(reinterpret_cast<const char*>(&huge), 4);
    out.write(reinterpret_cast<const char*>(&magic), 4);
  }
  try {
    ReadFlo(path);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": truncated: its header says 100000x100000"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "not a flow file at all";
  EXPECT_THROW(ReadFlo(path), std::runtime_error);
  std::filesystem::remove(path);
  EXPECT_THROW(ReadFlo(path), std::runtime_error);
}

TEST(WriteFlo, WritesWhatReadFloReadsWholeAndRefusesAFieldOfTheWrongSize) {
  const std::string path = TempPath("w.flo");
  FlowField f;
  f.width = 3, f.height = 2;
  f.uv = {1.5f, -2.0f, 0.25f, 3.0f, 1e10f, 1e10f, -7.0f, 0.5f, 0.0f, 0.0f, 4.0f, -4.0f};
  WriteFlo(path, f);
  const FlowField back = ReadFlo(path);
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.uv, f.uv);
  EXPECT_GT(back.u(2, 0), kUnknownFlow);  // unknown stays unknown
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  f.uv.pop_back();
  EXPECT_THROW(WriteFlo(path, f), std::invalid_argument);
  EXPECT_EQ(ReadFlo(path).uv.size(), 12u);  // the file written before is untouched
  EXPECT_THROW(WriteFlo(TempPath("no_such_dir") + "/x.flo", back), std::runtime_error);
}

TEST(ReadSemanticTxt, ReadsTheKittiSample) {
  const std::string path = kSamples + "/0000_semantic_000101.txt";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data absent: " << path;
  const InstanceMask mask = ReadSemanticTxt(path);
  EXPECT_EQ(mask.width, 1242);
  EXPECT_EQ(mask.height, 375);
  int background = 0, labelled = 0;
  for (int32_t id : mask.ids) (id == 0 ? background : labelled)++;
  EXPECT_GT(background, labelled);  // objects cover a minority of the image
  EXPECT_GT(labelled, 1000);
}

TEST(ReadSemanticTxt, RaggedRowsAndNonNumbersAreErrorsWithLine) {
  const std::string path = TempPath("mask.txt");
  std::ofstream(path) << "0 0 1\n0 1\n";
  try {
    ReadSemanticTxt(path);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":2"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "0 0 1\n0 x 1\n";
  EXPECT_THROW(ReadSemanticTxt(path), std::runtime_error);
  std::filesystem::remove(path);
}

TEST(ReadSemanticTxt, TabsCarriageReturnsSignsAndBlankLinesAreRead) {
  const std::string path = TempPath("mask_forms.txt");
  std::ofstream(path, std::ios::binary) << "\n0\t+3  -1\r\n\n  7 2147483647 0\r\n";
  const InstanceMask mask = ReadSemanticTxt(path);
  EXPECT_EQ(mask.width, 3);
  EXPECT_EQ(mask.height, 2);
  EXPECT_EQ(mask.ids, (std::vector<int32_t>{0, 3, -1, 7, 2147483647, 0}));
  std::ofstream(path, std::ios::binary) << "0 1\n0 2147483648\n";  // beyond 32 bits
  try {
    ReadSemanticTxt(path);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":2: instance id '2147483648'"), std::string::npos) << e.what();
  }
  std::ofstream(path, std::ios::binary) << "0 1\n0 1.5\n";
  EXPECT_THROW(ReadSemanticTxt(path), std::runtime_error);
  std::ofstream(path, std::ios::binary) << "\n \n";
  EXPECT_THROW(ReadSemanticTxt(path), std::runtime_error);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace dslam
