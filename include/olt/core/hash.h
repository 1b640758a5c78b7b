#pragma once
// SHA-256 digests (OpenSSL) of bytes and files, as lowercase hex.
#include <filesystem>
#include <memory>
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

std::string sha256_hex(std::string_view bytes);
/// Throws InputError naming the file when it cannot be read.
std::string sha256_file(const std::filesystem::path& file);

}  // namespace olt
