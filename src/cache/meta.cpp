#include "meta.h"

#include <string.h>

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>

namespace olt {
namespace {

// nlohmann's parser events for {"digest": s, "files": [{"as", "in", "path", "sha256", "size"}...],
// "key": s, ...}: members this version does not know are skipped; a known one of another type, a
// file entry that is no object or lacks path, sha256 or size, or no digest or files, is a damaged
// entry.
class MetaReader : public nlohmann::json_sax<nlohmann::json> {
 public:
  explicit MetaReader(Meta& meta) : meta_(meta) {}

  bool null() override { return unknown(); }
  bool boolean(bool) override { return unknown(); }
  bool number_integer(number_integer_t v) override { return v >= 0 ? size(static_cast<uint64_t>(v)) : unknown(); }
  bool number_unsigned(number_unsigned_t v) override { return size(v); }
  bool number_float(number_float_t, const string_t&) override { return unknown(); }
  bool binary(binary_t&) override { return unknown(); }
  bool string(string_t& v) override {
    std::string* field = nullptr;
    if (at_top()) {
      field = key_ == "digest" ? &meta_.digest : key_ == "key" ? &meta_.key : nullptr;
      seen_top_ |= key_ == "digest" ? 1 : 0;
    } else if (in_file()) {
      ArtifactFile& f = file_;
      if (key_ == "sha256") {  // 64 hex characters, or a damaged entry
        const std::optional<Digest> digest = Digest::from_hex(v);
        if (!digest) return false;
        f.sha256 = *digest;
        seen_file_ |= 2;
        return true;
      }
      if (key_ == "in") {
        f.in = std::move(v);
        return true;
      }
      field = key_ == "path" ? &f.path : key_ == "as" ? &f.as : nullptr;
      seen_file_ |= key_ == "path" ? 1 : 0;
    }
    if (!field) return unknown();
    // A copy of its own size: the parser's buffer, taken, would bring the capacity it grew to for the
    // longest text it held (120 bytes, doubling up to a digest's 64), in each of 70,000 files' names
    // at 10,000 frames.
    *field = std::string(v);
    return true;
  }
  bool start_object(std::size_t) override {
    if (skip_ > 0 || (depth_ > 0 && !in_files_list())) return enter_unknown();
    if (in_files_list()) {
      file_ = ArtifactFile();
      seen_file_ = 0;
    }
    ++depth_;
    return true;
  }
  bool key(string_t& k) override {
    key_ = std::move(k);
    return true;
  }
  bool end_object() override {
    if (skip_ > 0) return --skip_, true;
    if (in_file() && seen_file_ != 7) return false;  // a file without its path, sha256 or size
    if (in_file()) meta_.files.add(file_);
    --depth_;
    return depth_ > 0 || seen_top_ == 3;  // the document: with its digest and files
  }
  bool start_array(std::size_t) override {
    if (at_top() && key_ == "files") {
      if (seen_top_ & 2) return false;  // given twice: not what OLT writes
      seen_top_ |= 2;
      in_files_ = true;
      ++depth_;
      return true;
    }
    return enter_unknown();
  }
  bool end_array() override {
    if (skip_ > 0) return --skip_, true;
    in_files_ = false;
    --depth_;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  ArtifactFile file_;  ///< the file entry being read

  bool at_top() const { return skip_ == 0 && depth_ == 1; }
  bool in_files_list() const { return skip_ == 0 && depth_ == 2 && in_files_; }
  bool in_file() const { return skip_ == 0 && depth_ == 3 && in_files_; }
  // Whether the member being read is one this reader knows (and so must be of its own type).
  bool known() const {
    if (at_top()) return key_ == "digest" || key_ == "key" || key_ == "files";
    if (in_file()) return key_ == "path" || key_ == "sha256" || key_ == "size" || key_ == "in" || key_ == "as";
    return in_files_list() || (skip_ == 0 && depth_ == 0);  // a file entry, the document itself
  }
  // A value this reader does not take: skipped where unknown, the end of the parse where known.
  bool unknown() const { return skip_ > 0 || !known(); }
  bool enter_unknown() {
    if (!unknown()) return false;
    ++skip_;
    return true;
  }
  bool size(uint64_t v) {
    if (!in_file() || key_ != "size") return unknown();
    file_.size = v;
    seen_file_ |= 4;
    return true;
  }

  Meta& meta_;
  int depth_ = 0, skip_ = 0, seen_top_ = 0, seen_file_ = 0;
  bool in_files_ = false;
  std::string key_;
};

// How often `pattern` occurs in what `in` holds, read a piece at a time (memmem: the text is mostly
// quotes, which a search for the pattern's first character would stop at).
size_t occurrences(std::istream& in, const std::string& pattern) {
  size_t count = 0, kept = 0;  // kept: the end of the last piece, where a match may begin
  std::vector<char> window(pattern.size() - 1 + (1 << 16));
  while (in.read(window.data() + kept, static_cast<std::streamsize>(window.size() - kept)) || in.gcount() > 0) {
    const size_t size = kept + static_cast<size_t>(in.gcount());
    const char* at = window.data();
    const char* end = window.data() + size;
    while (const void* found = ::memmem(at, static_cast<size_t>(end - at), pattern.data(), pattern.size())) {
      ++count;
      at = static_cast<const char*>(found) + pattern.size();
    }
    // What may begin a match: the last bytes, short of one, that no match counted already covers.
    kept = std::min(std::min(size, pattern.size() - 1), static_cast<size_t>(end - at));
    std::memmove(window.data(), end - kept, kept);
  }
  return count;
}

// The metadata, its file list made of its size, `files` (the count of "sha256" in the text): the
// labeling stage's 70,000 files, grown by doubling, were held up to three times their 9 MB.
std::optional<Meta> parse_meta(std::istream& text, size_t files) {
  Meta meta;
  meta.files.reserve(files);
  MetaReader reader(meta);
  if (!nlohmann::json::sax_parse(text, &reader)) return std::nullopt;
  meta.files.sort();  // as written: only checked
  return meta;
}

}  // namespace

std::optional<Meta> read_meta(const std::string& text) {
  std::istringstream count(text), parse(text);
  return parse_meta(parse, occurrences(count, "\"sha256\""));
}

std::optional<Meta> read_meta_file(const FileSystem& files, const fs::path& file) {
  const size_t count = occurrences(*files.read_stream(file), "\"sha256\"");
  return parse_meta(*files.read_stream(file), count);
}

}  // namespace olt
