#pragma once
// Long texts (a manifest of 80,000 files, the records of 10,000 frames, a stage's publish list)
// made and written about a megabyte at a time rather than held whole: a string grown by doubling
// holds up to three times its size while it grows.
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>

namespace olt {

/// Where the pieces of a text go, in order.
using PieceSink = std::function<void(std::string_view)>;

/// A text made in a buffer that is handed to a sink each time it passes a piece's size.
class Pieces {
 public:
  explicit Pieces(const PieceSink& sink) : sink_(sink) { text_.reserve(2 * kPiece); }
  Pieces(const Pieces&) = delete;
  Pieces& operator=(const Pieces&) = delete;
  std::string& text() { return text_; }
  /// After each part (a file's entry, a unit's record): hands on what is there once it passes a
  /// piece's size.
  void next() {
    if (text_.size() >= kPiece) flush();
  }
  /// Hands on what is left (the text's end).
  void flush() {
    if (!text_.empty()) sink_(text_);
    text_.clear();
  }

 private:
  static constexpr size_t kPiece = 1 << 20;
  const PieceSink& sink_;
  std::string text_;
};

/// A text made a part at a time and read back in order, or any part by its offset, of which at most
/// `memory_bytes` is held in memory (a longer part too, until it is written out; the export holds
/// three such texts at once): the rest waits in an unnamed temporary file in $TMPDIR (or /tmp),
/// which the system removes when it is closed, even by a crash. Where no such file can be made or
/// written (no space), the text is held whole instead: no slower, only larger. A $TMPDIR on tmpfs
/// keeps the file in memory all the same (outside the process's resident set). Move-only.
class SpooledText {
 public:
  /// Where the text beyond memory_bytes waits: a file to write and read back, null for none.
  using FileMaker = std::FILE* (*)();
  /// An unnamed temporary file in $TMPDIR (or /tmp); null where none can be made.
  static std::FILE* temporary_file();

  explicit SpooledText(size_t memory_bytes = size_t{1} << 20, FileMaker make_file = temporary_file)
      : memory_bytes_(memory_bytes), make_file_(make_file) {}
  SpooledText(SpooledText&& other) noexcept;
  SpooledText& operator=(SpooledText&& other) noexcept;
  SpooledText(const SpooledText&) = delete;
  SpooledText& operator=(const SpooledText&) = delete;
  ~SpooledText();

  void append(std::string_view text);
  bool empty() const { return size_ == 0; }
  size_t size() const { return size_; }
  /// Whether part of the text waits in the temporary file.
  bool spilled() const { return file_ != nullptr; }
  /// Bytes of memory the text held in memory takes (its buffer's capacity).
  size_t held_bytes() const { return held_.capacity(); }
  /// Hands the text to `sink` in order, in pieces of about a megabyte (as often as asked; from one
  /// thread at a time with the appends).
  void for_each_piece(const PieceSink& sink) const;
  /// `bytes` of the text from `offset` (within size(), else std::out_of_range): from several
  /// threads at once while nothing is appended.
  std::string read(size_t offset, size_t bytes) const;

 private:
  size_t memory_bytes_;
  FileMaker make_file_;
  std::string held_;           ///< the text after what the file holds
  std::FILE* file_ = nullptr;  ///< the text's beginning, once it outgrew memory_bytes_
  size_t size_ = 0;

  void spill();
  void take_back();  ///< the file's text into memory, the file closed (it could not be written)
  void read_spilled(size_t offset, char* to, size_t bytes) const;
};

}  // namespace olt
