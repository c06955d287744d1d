#include "output/whole_line_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>

namespace dslam {
namespace {
// Past this much pending text, whole lines go out even without a flush: memory stays bounded.
constexpr size_t kMaxPendingBytes = 1 << 20;
}  // namespace

WholeLineBuf::~WholeLineBuf() { close(); }

bool WholeLineBuf::open(const std::string& path) {
  close();
  failed_ = false;
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  return fd_ >= 0;
}

bool WholeLineBuf::close() {
  if (fd_ < 0) return !failed_;
  writeOut(pending_.size());
  pending_.clear();
  if (::close(fd_) != 0) failed_ = true;
  fd_ = -1;
  return !failed_;
}

bool WholeLineBuf::writeOut(size_t n) {
  size_t done = 0;
  while (done < n) {
    const ssize_t w = ::write(fd_, pending_.data() + done, n - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      failed_ = true;
      return false;
    }
    done += static_cast<size_t>(w);
  }
  pending_.erase(0, n);
  return true;
}

WholeLineBuf::int_type WholeLineBuf::overflow(int_type c) {
  if (fd_ < 0 || failed_) return traits_type::eof();
  if (!traits_type::eq_int_type(c, traits_type::eof())) {
    pending_.push_back(traits_type::to_char_type(c));
    if (pending_.size() > kMaxPendingBytes && sync() != 0) return traits_type::eof();
  }
  return traits_type::not_eof(c);
}

std::streamsize WholeLineBuf::xsputn(const char* s, std::streamsize n) {
  if (fd_ < 0 || failed_) return 0;
  pending_.append(s, static_cast<size_t>(n));
  if (pending_.size() > kMaxPendingBytes && sync() != 0) return 0;
  return n;
}

int WholeLineBuf::sync() {
  if (fd_ < 0) return failed_ ? -1 : 0;
  const size_t last_newline = pending_.rfind('\n');
  if (last_newline != std::string::npos && !writeOut(last_newline + 1)) return -1;
  return failed_ ? -1 : 0;
}

}  // namespace dslam
