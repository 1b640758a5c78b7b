#pragma once
// Errors and diagnostics. An InputError means the job or one of its inputs is invalid (exit code 2);
// any other exception escaping a stage is a stage failure (exit code 1).
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace olt {

/// One problem found in an input, printed as `FILE:LINE:COLUMN: message` (line/column 1-based;
/// 0 when the problem has no position, e.g. a missing file).
struct Diagnostic {
  std::string file;
  int line = 0;
  int column = 0;
  std::string message;

  std::string str() const;
};

class InputError : public std::runtime_error {
 public:
  explicit InputError(std::vector<Diagnostic> diagnostics);
  InputError(const std::string& file, const std::string& message);
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

 private:
  std::vector<Diagnostic> diagnostics_;
};

/// `olt merge` found work of the shards missing (a shard that did not finish, frames not in the
/// cache): nothing was published.
class ShardsIncomplete : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws InputError at the first byte of `text` (the content of `file`) that is not valid UTF-8,
/// with its line and column: text inputs are checked where they enter, so that no later JSON
/// serialisation of a name or message can fail on them.
void check_utf8(const std::string& file, std::string_view text);
/// "" where `text` is valid UTF-8, else where it is not ("byte 0xFF at 9").
std::string invalid_utf8(std::string_view text);

/// Exit codes of the `olt` binary, documented in the README.
enum ExitCode : int { kExitOk = 0, kExitStageFailed = 1, kExitInvalidInput = 2, kExitIncomplete = 3 };

}  // namespace olt
