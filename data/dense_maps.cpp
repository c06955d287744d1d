#include "data/dense_maps.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <cstring>
#include <fstream>
#include <filesystem>
#include <stdexcept>

#include "data/text_parsing.h"

namespace dslam {

namespace {

// Opens a .flo file and checks its header against the file's size before anything is allocated for it;
// leaves `in` at the first flow value.
std::ifstream OpenFlo(const std::string& path, int32_t* width, int32_t* height) {
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
  const size_t expected_bytes = static_cast<size_t>(w) * static_cast<size_t>(h) * 2 * sizeof(float);
  in.seekg(0, std::ios::end);
  const auto file_bytes = static_cast<size_t>(std::max<std::streamoff>(0, in.tellg()));
  in.seekg(12, std::ios::beg);
  if (file_bytes < 12 + expected_bytes)
    throw std::runtime_error(path + ": truncated: its header says " + std::to_string(w) + "x" + std::to_string(h) +
                             ", " + std::to_string(expected_bytes) + " bytes of flow, but the file has " +
                             std::to_string(file_bytes > 12 ? file_bytes - 12 : 0) + " after the header");
  *width = w;
  *height = h;
  return in;
}

void ReadFloValues(std::ifstream& in, const std::string& path, float* uv, size_t count) {
  in.read(reinterpret_cast<char*>(uv), static_cast<std::streamsize>(count * sizeof(float)));
  if (in.gcount() != static_cast<std::streamsize>(count * sizeof(float)))
    throw std::runtime_error(path + ": truncated: expected " + std::to_string(count * sizeof(float)) +
                             " bytes of flow after the header");
}

}  // namespace

FlowField ReadFlo(const std::string& path) {
  FlowField flow;
  std::ifstream in = OpenFlo(path, &flow.width, &flow.height);
  flow.uv.resize(static_cast<size_t>(flow.width) * flow.height * 2);
  ReadFloValues(in, path, flow.uv.data(), flow.uv.size());
  return flow;
}

void ReadFloInto(const std::string& path, int width, int height, float* uv) {
  int32_t w = 0, h = 0;
  std::ifstream in = OpenFlo(path, &w, &h);
  if (w != width || h != height)
    throw std::runtime_error(path + ": flow is " + std::to_string(w) + "x" + std::to_string(h) + " but the image is " +
                             std::to_string(width) + "x" + std::to_string(height));
  ReadFloValues(in, path, uv, static_cast<size_t>(w) * h * 2);
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
  // A 1242x375 mask is ~1 MB of text: the file is read whole and its numbers parsed in place
  // (std::from_chars), which is ~10x faster than splitting each line into strings.
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw std::runtime_error("cannot read " + path);
  InstanceMask mask;
  const char* p = text.data();
  const char* const end = p + text.size();
  auto is_blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; };
  for (int line_no = 1; p < end; ++line_no) {
    const char* line_end = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
    if (!line_end) line_end = end;
    int fields = 0;
    while (true) {
      while (p < line_end && is_blank(*p)) ++p;
      if (p == line_end) break;
      const char* token = p;
      while (p < line_end && !is_blank(*p)) ++p;
      const char* digits = (*token == '+' && p - token > 1) ? token + 1 : token;
      int64_t id = 0;
      const auto [stop, error] = std::from_chars(digits, p, id);
      if (error != std::errc() || stop != p || id < INT32_MIN || id > INT32_MAX)
        throw std::runtime_error(AtLine(path, line_no, "instance id '" + std::string(token, p) + "' is not an integer"));
      mask.ids.push_back(static_cast<int32_t>(id));
      ++fields;
    }
    p = line_end + (line_end < end ? 1 : 0);
    if (fields == 0) continue;
    if (mask.width == 0) {
      mask.width = fields;
      mask.ids.reserve(static_cast<size_t>(fields) * static_cast<size_t>(std::count(line_end, end, '\n') + 1));
    }
    if (fields != mask.width)
      throw std::runtime_error(AtLine(path, line_no, "row has " + std::to_string(fields) + " values, expected " +
                                                         std::to_string(mask.width)));
    ++mask.height;
  }
  if (mask.height == 0) throw std::runtime_error(path + ": empty mask");
  return mask;
}

}  // namespace dslam
