#pragma once
// A text file that is on disk only in whole lines: what is written goes to the file up to its last
// newline, in one write(2) per flush, and a line still being written stays in memory until it ends. A
// process ended by a signal while it streams results leaves each file ending on a whole row. SIGKILL
// leaves whole rows too, with one exception no program can rule out: when it arrives during a write(2),
// Linux stops the write at the next page boundary of the file, so a row straddling one can be cut there
// (seen once in a CI run of tests/output/whole_line_file_test.cpp, at byte 6749 x 4096). Used as any
// std::ostream.

#include <ostream>
#include <streambuf>
#include <string>

namespace dslam {

class WholeLineBuf : public std::streambuf {
 public:
  ~WholeLineBuf() override;
  // Truncates or creates `path`; false (errno set) when it cannot.
  bool open(const std::string& path);
  bool isOpen() const { return fd_ >= 0; }
  // Writes what is pending, the unfinished last line too, and closes; false on a write error.
  bool close();

 protected:
  int_type overflow(int_type c) override;
  std::streamsize xsputn(const char* s, std::streamsize n) override;
  int sync() override;  // writes the whole lines pending

 private:
  bool writeOut(size_t n);  // the first n pending bytes, in one write(2) (looping on short writes)

  int fd_ = -1;
  std::string pending_;
  bool failed_ = false;
};

class WholeLineFile : public std::ostream {
 public:
  WholeLineFile() : std::ostream(&buf_) {}
  explicit WholeLineFile(const std::string& path) : WholeLineFile() { open(path); }
  // Sets failbit when the file cannot be created.
  void open(const std::string& path) {
    clear();
    if (!buf_.open(path)) setstate(std::ios::failbit);
  }
  bool is_open() const { return buf_.isOpen(); }
  void close() {
    if (!buf_.close()) setstate(std::ios::badbit);
  }

 private:
  WholeLineBuf buf_;
};

}  // namespace dslam
