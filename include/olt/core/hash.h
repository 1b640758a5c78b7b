#pragma once
// SHA-256 digests (OpenSSL) of bytes and files, as lowercase hex.
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace olt {

class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void update(std::string_view bytes);
  std::string hex();  ///< finishes the digest

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// A SHA-256 digest held as its 32 bytes rather than its 64 hex characters (a text that long takes
/// a heap block of 80 bytes besides the string: 100,000 files' digests at 10,000 frames); empty
/// until given one.
class Digest {
 public:
  Digest() = default;
  /// From 64 lowercase hex characters; nothing from any other text.
  static std::optional<Digest> from_hex(std::string_view hex);
  /// As from_hex, for texts OLT made itself (a hasher's): throws std::invalid_argument on another.
  explicit Digest(std::string_view hex);

  bool empty() const { return !set_; }
  std::string hex() const;  ///< "" when empty
  /// Appends hex() to `to` (without a string of its own: an artifact's metadata lists 70,000).
  void append_hex(std::string& to) const;
  friend bool operator==(const Digest& a, const Digest& b) { return a.set_ == b.set_ && a.bytes_ == b.bytes_; }
  friend bool operator!=(const Digest& a, const Digest& b) { return !(a == b); }
  /// Against a digest's text (what a file system or a manifest gives): equal where hex() would be,
  /// without making it (publishing compares 80,000).
  friend bool operator==(const Digest& a, std::string_view hex) {
    const std::optional<Digest> other = from_hex(hex);
    return other ? *other == a : a.empty() && hex.empty();
  }
  friend bool operator!=(const Digest& a, std::string_view hex) { return !(a == hex); }
  friend bool operator==(std::string_view hex, const Digest& a) { return a == hex; }
  friend bool operator!=(std::string_view hex, const Digest& a) { return !(a == hex); }

 private:
  std::array<uint8_t, 32> bytes_{};
  bool set_ = false;
};

std::string sha256_hex(std::string_view bytes);
/// Throws InputError naming the file when it cannot be read.
std::string sha256_file(const std::filesystem::path& file);

}  // namespace olt
