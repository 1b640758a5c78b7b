#include "manifest.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "olt/core/hash.h"
#include "olt/core/json_text.h"
#include "olt/core/pieces.h"

namespace olt {
namespace {

// The listing's first line: its format, as ninja's log names its version.
const std::string kListingFormat = "# olt listing 1\n";

}  // namespace

const Entry* find_entry(const Entries& entries, const std::string& path) {
  auto it = std::lower_bound(entries.begin(), entries.end(), path,
                             [](const Entry& e, const std::string& p) { return e.published.path < p; });
  return it != entries.end() && it->published.path == path ? &*it : nullptr;
}

const std::string* find_listed(const Listed& listed, const std::string& path) {
  auto it = std::lower_bound(listed.begin(), listed.end(), path,
                             [](const auto& entry, const std::string& p) { return entry.first < p; });
  return it != listed.end() && it->first == path ? &it->second : nullptr;
}

Listed previous_manifest(const FileSystem& files, const fs::path& manifest_file) {
  Listed previous;
  if (!files.stat(manifest_file, true).is_file()) return previous;
  try {
    for_each_at(files.read(manifest_file), 2, [&](const nlohmann::json& f) {
      if (f.is_object() && f.contains("path") && f.contains("sha256") && f["path"].is_string() &&
          f["sha256"].is_string())
        previous.emplace_back(f["path"], f["sha256"]);
    });
  } catch (const nlohmann::json::exception&) {
    return {};  // not a manifest OLT can read: nothing in the output is taken for ours
  }
  std::sort(previous.begin(), previous.end());
  return previous;
}

std::string manifest_digest(const FileSystem& files, const fs::path& manifest_file) {
  if (!files.stat(manifest_file).is_file()) return "";
  try {
    return files.sha256(manifest_file);  // not read whole: 31 MB at 80,000 files
  } catch (const std::exception&) {
    return "";
  }
}

// Assembled without the document (keys in nlohmann's sorted order, strings and numbers written by
// it): as JSON values, 80,000 entries took 0.2-0.5 s to build and dump, and ~1 KB each.
void manifest_pieces(const Entries& entries, const PieceSink& sink) {
  Pieces pieces(sink);
  std::string& text = pieces.text();
  text = entries.empty() ? "{\n \"files\": []\n}\n" : "{\n \"files\": [\n";
  for (size_t i = 0; i < entries.size(); ++i) {
    const Entry& e = entries[i];
    const Published& p = e.published;
    text += i ? ",\n  {\n" : "  {\n";
    text += "   \"kind\": " + json_string(p.kind) + ",\n";
    if (!p.observation.empty())
      text += "   \"observation\": {\n    \"id\": " + json_string(p.observation) +
              ",\n    \"timestamp\": " + nlohmann::json(p.timestamp).dump() + "\n   },\n";
    text += "   \"path\": " + json_string(p.path) + ",\n";
    if (!p.sensor.empty()) text += "   \"sensor\": " + json_string(p.sensor) + ",\n";
    text += "   \"sha256\": " + json_string(e.file->sha256) + ",\n";
    text += "   \"stage\": " + json_string(e.stage) + "\n  }";
    pieces.next();
  }
  if (!entries.empty()) text += "\n ]\n}\n";
  pieces.flush();
}

std::string manifest_digest(const Entries& entries) {
  Sha256 hash;
  manifest_pieces(entries, [&](std::string_view piece) { hash.update(piece); });
  return hash.hex();
}

// Read instead of the manifest (31 MB of JSON at 80,000 files, 0.3 s to parse) when it copies the
// manifest there.
void listing_pieces(const std::string& digest, const Entries& entries, const PieceSink& sink) {
  Pieces pieces(sink);
  std::string& text = pieces.text();
  text = kListingFormat + digest + "\n";
  for (const Entry& e : entries) {
    text += e.file->sha256 + " " + std::to_string(e.published.path.size()) + " " + e.published.path + "\n";
    pieces.next();
  }
  pieces.flush();
}

std::optional<Listed> read_listing(const FileSystem& files, const fs::path& file, const std::string& manifest_digest) {
  if (file.empty() || manifest_digest.empty() || !files.stat(file).is_file()) return std::nullopt;
  try {
    const std::string text = files.read(file);
    const std::string head = kListingFormat + manifest_digest + "\n";  // another format's is a miss
    if (text.compare(0, head.size(), head) != 0) return std::nullopt;
    Listed listed;
    for (size_t at = head.size(); at < text.size();) {
      const size_t space = text.find(' ', at);
      const size_t second = space == std::string::npos ? space : text.find(' ', space + 1);
      if (second == std::string::npos || second == space + 1) return std::nullopt;
      const std::string digits = text.substr(space + 1, second - space - 1);
      if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
      const size_t length = std::stoul(digits), end = second + 1 + length;
      if (end >= text.size() || text[end] != '\n') return std::nullopt;
      std::string path = text.substr(second + 1, length);
      if (!listed.empty() && !(listed.back().first < path)) return std::nullopt;  // sorted, as written
      listed.emplace_back(std::move(path), text.substr(at, space - at));
      at = end + 1;
    }
    return listed;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace olt
