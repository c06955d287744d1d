#pragma once
// A result file written whole or not at all: the text goes to PATH.partial, and commit() renames it over
// PATH. A run interrupted while writing (Ctrl-C, a full disk) leaves the previous PATH as it was, never a
// file cut mid-row. Without commit() the partial file is removed.

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

namespace dslam {

class WholeFile : public std::ofstream {
 public:
  explicit WholeFile(const std::string& path) : std::ofstream(path + ".partial", std::ios::trunc), path_(path) {
    if (!*this) throw std::runtime_error("cannot write " + path);
  }
  WholeFile(WholeFile&& other) noexcept
      : std::ofstream(std::move(other)), path_(std::move(other.path_)), committed_(other.committed_) {
    other.committed_ = true;  // the moved-from object owns nothing
  }
  WholeFile& operator=(WholeFile&&) = delete;
  ~WholeFile() override {
    if (committed_) return;
    close();
    std::remove((path_ + ".partial").c_str());
  }

  // Throws std::runtime_error naming the file when anything failed to be written.
  void commit() {
    close();
    if (fail()) throw std::runtime_error("error while writing " + path_);
    if (std::rename((path_ + ".partial").c_str(), path_.c_str()) != 0)
      throw std::runtime_error("cannot replace " + path_);
    committed_ = true;
  }

 private:
  std::string path_;
  bool committed_ = false;
};

}  // namespace dslam
