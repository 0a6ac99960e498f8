#include "bag_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

namespace semgraph::ros::detail {

BagFile::BagFile(BagFile&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      size_(other.size_),
      window_(std::move(other.window_)),
      window_offset_(other.window_offset_) {}

BagFile& BagFile::operator=(BagFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    size_ = other.size_;
    window_ = std::move(other.window_);
    window_offset_ = other.window_offset_;
  }
  return *this;
}

BagFile::~BagFile() {
  if (fd_ >= 0) ::close(fd_);
}

bool BagFile::Open(const std::string& path, std::string& error) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    error = std::string("cannot open: ") + std::strerror(errno);
    return false;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    error = S_ISDIR(st.st_mode) ? "is a folder, not a file" : "not a regular file";
    ::close(fd);
    return false;
  }
  fd_ = fd;
  size_ = static_cast<std::uint64_t>(st.st_size);
  window_.clear();
  return true;
}

bool BagFile::ReadInto(std::uint64_t offset, std::size_t n, std::uint8_t* dst, std::string& error) {
  if (offset > size_ || n > size_ - offset) {
    error = "reading " + std::to_string(n) + " bytes at byte " + std::to_string(offset) +
            " passes the end of the file (" + std::to_string(size_) + " bytes)";
    return false;
  }
  std::size_t done = 0;
  while (done < n) {
    const ssize_t got = ::pread(fd_, dst + done, n - done, static_cast<off_t>(offset + done));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      error = got < 0 ? std::string("read failed: ") + std::strerror(errno)
                      : "the file ended early (it shrank while being read)";
      return false;
    }
    done += static_cast<std::size_t>(got);
  }
  return true;
}

bool BagFile::Peek(std::uint64_t offset, std::size_t n, std::span<const std::uint8_t>& out,
                   std::string& error) {
  const bool inside = offset >= window_offset_ && offset - window_offset_ <= window_.size() &&
                      n <= window_.size() - (offset - window_offset_);
  if (!inside) {
    if (offset > size_ || n > size_ - offset) {
      error = "reading " + std::to_string(n) + " bytes at byte " + std::to_string(offset) +
              " passes the end of the file (" + std::to_string(size_) + " bytes)";
      return false;
    }
    const std::size_t fill =
        static_cast<std::size_t>(std::min<std::uint64_t>(size_ - offset, std::max(n, kPeekMax)));
    window_.resize(fill);
    window_offset_ = offset;
    if (!ReadInto(offset, fill, window_.data(), error)) {
      window_.clear();
      return false;
    }
  }
  out = std::span<const std::uint8_t>(window_).subspan(offset - window_offset_, n);
  return true;
}

bool BagFile::Read(std::uint64_t offset, std::size_t n, std::vector<std::uint8_t>& out,
                   std::string& error) {
  out.resize(n);
  return ReadInto(offset, n, out.data(), error);
}

}  // namespace semgraph::ros::detail
