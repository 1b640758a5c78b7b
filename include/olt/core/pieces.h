#pragma once
// Long texts (a manifest of 80,000 files, the records of 10,000 frames, a stage's publish list)
// made and written about a megabyte at a time rather than held whole: a string grown by doubling
// holds up to three times its size while it grows.
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

}  // namespace olt
