#include "olt/core/pieces.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <utility>

namespace olt {

std::FILE* SpooledText::temporary_file() {
  const char* dir = std::getenv("TMPDIR");
  const int fd = ::open(dir && *dir ? dir : "/tmp", O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd < 0) return std::tmpfile();
  std::FILE* file = ::fdopen(fd, "w+");
  if (!file) ::close(fd);
  return file;
}

SpooledText::SpooledText(SpooledText&& other) noexcept
    : memory_bytes_(other.memory_bytes_),
      make_file_(other.make_file_),
      held_(std::move(other.held_)),
      file_(std::exchange(other.file_, nullptr)),
      size_(std::exchange(other.size_, 0)) {}

SpooledText& SpooledText::operator=(SpooledText&& other) noexcept {
  if (this != &other) {
    if (file_) std::fclose(file_);
    memory_bytes_ = other.memory_bytes_;
    make_file_ = other.make_file_;
    held_ = std::move(other.held_);
    file_ = std::exchange(other.file_, nullptr);
    size_ = std::exchange(other.size_, 0);
  }
  return *this;
}

SpooledText::~SpooledText() {
  if (file_) std::fclose(file_);
}

void SpooledText::append(std::string_view text) {
  // What is held is written out before it grows past memory_bytes_, and its buffer grows by doubling
  // but not past that (unless a part alone is longer). A new buffer: std::string::reserve doubles too.
  if (!held_.empty() && held_.size() + text.size() > memory_bytes_) spill();
  const size_t needed = held_.size() + text.size();
  if (needed > held_.capacity()) {
    std::string grown;
    grown.reserve(std::max(needed, std::min(memory_bytes_, 2 * held_.capacity())));
    grown += held_;
    held_.swap(grown);
  }
  held_ += text;
  size_ += text.size();
  if (held_.size() > memory_bytes_) spill();
}

void SpooledText::spill() {
  if (!file_ && !(file_ = make_file_())) {  // held whole
    memory_bytes_ = static_cast<size_t>(-1);
    return;
  }
  if (std::fwrite(held_.data(), 1, held_.size(), file_) != held_.size() || std::fflush(file_) != 0) {
    take_back();
    return;
  }
  held_.clear();
  if (held_.capacity() > memory_bytes_) std::string().swap(held_);  // a longer part's buffer
}

void SpooledText::take_back() {
  std::string text(size_ - held_.size(), '\0');
  read_spilled(0, text.data(), text.size());
  std::fclose(file_);
  file_ = nullptr;
  held_ = text + held_;
  memory_bytes_ = static_cast<size_t>(-1);  // held from now on
}

void SpooledText::read_spilled(size_t offset, char* to, size_t bytes) const {
  // The stream is put back at its end whatever happens: the next spill writes there (and C streams
  // must be positioned between a read and a write).
  const bool read =
      std::fseek(file_, static_cast<long>(offset), SEEK_SET) == 0 && std::fread(to, 1, bytes, file_) == bytes;
  std::fseek(file_, 0, SEEK_END);
  if (!read)
    throw std::runtime_error("a temporary file of " + std::to_string(size_ - held_.size()) + " bytes read back short");
}

std::string SpooledText::read(size_t offset, size_t bytes) const {
  if (offset > size_ || bytes > size_ - offset) throw std::out_of_range("a spooled text read past its end");
  std::string text(bytes, '\0');
  const size_t spilled = size_ - held_.size();
  const size_t from_file = offset < spilled ? std::min(bytes, spilled - offset) : 0;
  const int fd = from_file ? ::fileno(file_) : -1;
  if (from_file && fd < 0) {  // a file without a descriptor (in memory): its stream's position is shared
    static std::mutex one_at_a_time;
    const std::lock_guard<std::mutex> lock(one_at_a_time);
    read_spilled(offset, text.data(), from_file);
  }
  size_t done = fd < 0 ? from_file : 0;
  while (done < from_file) {  // pread: no shared file position between the threads reading
    const ssize_t n = ::pread(fd, text.data() + done, from_file - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw std::runtime_error("a temporary file of " + std::to_string(spilled) + " bytes read back short");
    done += static_cast<size_t>(n);
  }
  if (from_file < bytes) held_.copy(text.data() + from_file, bytes - from_file, offset + from_file - spilled);
  return text;
}

void SpooledText::for_each_piece(const PieceSink& sink) const {
  const size_t spilled = size_ - held_.size();
  if (spilled > 0) {
    std::string piece(std::min(spilled, size_t{1} << 20), '\0');
    for (size_t at = 0; at < spilled; at += piece.size()) {
      const size_t bytes = std::min(piece.size(), spilled - at);
      read_spilled(at, piece.data(), bytes);
      sink(std::string_view(piece.data(), bytes));
    }
  }
  if (!held_.empty()) sink(held_);
}

}  // namespace olt
