#include "olt/core/pieces.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdlib>
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
}

void SpooledText::take_back() {
  std::string text;
  text.resize(size_ - held_.size());
  std::rewind(file_);
  const size_t read = std::fread(text.data(), 1, text.size(), file_);
  std::fclose(file_);
  file_ = nullptr;
  if (read != text.size())
    throw std::runtime_error("a temporary file of " + std::to_string(text.size()) + " bytes read back short");
  held_ = text + held_;
  memory_bytes_ = static_cast<size_t>(-1);  // held from now on
}

void SpooledText::for_each_piece(const PieceSink& sink) const {
  if (file_) {
    std::string piece(size_t{1} << 20, '\0');
    std::rewind(file_);
    size_t left = size_ - held_.size();
    while (left > 0) {
      const size_t read = std::fread(piece.data(), 1, std::min(piece.size(), left), file_);
      if (read == 0)
        throw std::runtime_error("a temporary file of " + std::to_string(size_ - held_.size()) +
                                 " bytes read back short");
      sink(std::string_view(piece.data(), read));
      left -= read;
    }
    std::fseek(file_, 0, SEEK_END);  // where the next append writes
  }
  if (!held_.empty()) sink(held_);
}

}  // namespace olt
