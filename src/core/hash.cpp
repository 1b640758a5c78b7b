#include "olt/core/hash.h"

#include <openssl/evp.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "olt/core/error.h"
#include "olt/core/fs.h"

namespace olt {

struct Sha256::State {
  EVP_MD_CTX* ctx = EVP_MD_CTX_new();
  ~State() { EVP_MD_CTX_free(ctx); }
};

Sha256::Sha256() : state_(std::make_unique<State>()) { EVP_DigestInit_ex(state_->ctx, EVP_sha256(), nullptr); }

Sha256::~Sha256() = default;

void Sha256::update(std::string_view bytes) { EVP_DigestUpdate(state_->ctx, bytes.data(), bytes.size()); }

std::string Sha256::hex() {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  EVP_DigestFinal_ex(state_->ctx, digest.data(), &length);
  std::string text(2 * length, '0');
  static const char* kHex = "0123456789abcdef";
  for (unsigned int i = 0; i < length; ++i) {
    text[2 * i] = kHex[digest[i] >> 4];
    text[2 * i + 1] = kHex[digest[i] & 15];
  }
  return text;
}

std::optional<Digest> Digest::from_hex(std::string_view hex) {
  if (hex.size() != 64) return std::nullopt;
  Digest d;
  for (size_t i = 0; i < 64; ++i) {
    const char c = hex[i];
    const int v = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
    if (v < 0) return std::nullopt;
    d.bytes_[i / 2] = static_cast<uint8_t>(i % 2 ? d.bytes_[i / 2] | v : v << 4);
  }
  d.set_ = true;
  return d;
}

Digest::Digest(std::string_view hex) {
  const std::optional<Digest> d = from_hex(hex);
  if (!d) throw std::invalid_argument("not a SHA-256 digest: '" + std::string(hex.substr(0, 80)) + "'");
  *this = *d;
}

std::string Digest::hex() const {
  std::string text;
  append_hex(text);
  return text;
}

void Digest::append_hex(std::string& to) const {
  static const char* digits = "0123456789abcdef";
  if (!set_) return;
  const size_t at = to.size();
  to.resize(at + 64);
  for (size_t i = 0; i < 32; ++i) {
    to[at + 2 * i] = digits[bytes_[i] >> 4];
    to[at + 2 * i + 1] = digits[bytes_[i] & 15];
  }
}

std::string sha256_hex(std::string_view bytes) {
  Sha256 hash;
  hash.update(bytes);
  return hash.hex();
}

std::string sha256_file(const std::filesystem::path& file) {
  uint64_t size = 0;
  const int fd = open_regular_file(file, &size);
  Sha256 hash;
  std::array<char, 1 << 16> buffer{};
  for (;;) {
    const ssize_t n = ::read(fd, buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      ::close(fd);
      throw InputError(file.string(), "read error");
    }
    if (n == 0) break;
    hash.update(std::string_view(buffer.data(), static_cast<size_t>(n)));
  }
  ::close(fd);
  return hash.hex();
}

}  // namespace olt
