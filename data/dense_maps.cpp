#include "data/dense_maps.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <filesystem>
#include <stdexcept>

#include "data/text_parsing.h"

namespace dslam {

FlowField ReadFlo(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  float magic = 0.0f;
  int32_t w = 0, h = 0;
  in.read(reinterpret_cast<char*>(&magic), 4);
  in.read(reinterpret_cast<char*>(&w), 4);
  in.read(reinterpret_cast<char*>(&h), 4);
  if (!in) throw std::runtime_error(path + ": truncated .flo header");
  if (magic != 202021.25f) throw std::runtime_error(path + ": not a .flo file (bad magic number)");
  if (w <= 0 || h <= 0 || w > 100000 || h > 100000)
    throw std::runtime_error(path + ": implausible size " + std::to_string(w) + "x" + std::to_string(h));
  // The header's size must match the file's before anything is allocated for it.
  const size_t expected_bytes = static_cast<size_t>(w) * static_cast<size_t>(h) * 2 * sizeof(float);
  in.seekg(0, std::ios::end);
  const auto file_bytes = static_cast<size_t>(std::max<std::streamoff>(0, in.tellg()));
  in.seekg(12, std::ios::beg);
  if (file_bytes < 12 + expected_bytes)
    throw std::runtime_error(path + ": truncated: its header says " + std::to_string(w) + "x" + std::to_string(h) +
                             ", " + std::to_string(expected_bytes) + " bytes of flow, but the file has " +
                             std::to_string(file_bytes > 12 ? file_bytes - 12 : 0) + " after the header");
  FlowField flow;
  flow.width = w;
  flow.height = h;
  flow.uv.resize(static_cast<size_t>(w) * h * 2);
  in.read(reinterpret_cast<char*>(flow.uv.data()), static_cast<std::streamsize>(flow.uv.size() * sizeof(float)));
  if (in.gcount() != static_cast<std::streamsize>(flow.uv.size() * sizeof(float)))
    throw std::runtime_error(path + ": truncated: expected " + std::to_string(flow.uv.size() * sizeof(float)) +
                             " bytes of flow after the header");
  return flow;
}

void WriteFlo(const std::string& path, const FlowField& flow) {
  if (flow.width <= 0 || flow.height <= 0 || flow.uv.size() != static_cast<size_t>(flow.width) * flow.height * 2)
    throw std::invalid_argument(path + ": flow field of " + std::to_string(flow.uv.size()) + " values is not " +
                                std::to_string(flow.width) + "x" + std::to_string(flow.height) + "x2");
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    const float magic = 202021.25f;
    const int32_t w = flow.width, h = flow.height;
    out.write(reinterpret_cast<const char*>(&magic), 4);
    out.write(reinterpret_cast<const char*>(&w), 4);
    out.write(reinterpret_cast<const char*>(&h), 4);
    out.write(reinterpret_cast<const char*>(flow.uv.data()), static_cast<std::streamsize>(flow.uv.size() * sizeof(float)));
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("cannot rename " + tmp + " to " + path + ": " + ec.message());
}

InstanceMask ReadSemanticTxt(const std::string& path) {
  std::ifstream in = OpenText(path);
  InstanceMask mask;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const auto fields = SplitFields(line);
    if (fields.empty()) continue;
    if (mask.width == 0) mask.width = static_cast<int>(fields.size());
    if (static_cast<int>(fields.size()) != mask.width)
      throw std::runtime_error(AtLine(path, line_no, "row has " + std::to_string(fields.size()) + " values, expected " +
                                                         std::to_string(mask.width)));
    for (const auto& f : fields) mask.ids.push_back(ParseInt(f, path, line_no, "instance id"));
    ++mask.height;
  }
  if (mask.height == 0) throw std::runtime_error(path + ": empty mask");
  return mask;
}

}  // namespace dslam
