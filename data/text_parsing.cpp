#include "data/text_parsing.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace dslam {

std::string AtLine(const std::string& path, int line_no, const std::string& message) {
  return path + ":" + std::to_string(line_no) + ": " + message;
}

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  std::string f;
  while (in >> f) fields.push_back(f);
  return fields;
}

double ParseDouble(const std::string& field, const std::string& path, int line_no, const std::string& what) {
  const char* begin = field.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0' || errno == ERANGE || !std::isfinite(v))
    throw std::runtime_error(AtLine(path, line_no, what + " '" + field + "' is not a finite number"));
  return v;
}

int ParseInt(const std::string& field, const std::string& path, int line_no, const std::string& what) {
  const char* begin = field.c_str();
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(begin, &end, 10);
  if (end == begin || *end != '\0' || errno == ERANGE || v < INT32_MIN || v > INT32_MAX)
    throw std::runtime_error(AtLine(path, line_no, what + " '" + field + "' is not an integer"));
  return static_cast<int>(v);
}

std::ifstream OpenText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  return in;
}

}  // namespace dslam
