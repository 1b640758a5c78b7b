#include "manifest.h"

#include <algorithm>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "olt/core/hash.h"
#include "olt/core/json_text.h"
#include "olt/core/pieces.h"

namespace olt {
namespace {

// The listing's first line: its format, as ninja's log names its version.
const std::string kListingFormat = "# olt listing 1\n";

}  // namespace

int EntryPath::compare(const EntryPath& other) const {
  // Both walked a part at a time: what is left of each one's current part, and the part after it.
  std::string_view a = head.empty() ? tail : head, b = other.head.empty() ? other.tail : other.head;
  std::string_view a_next = head.empty() ? std::string_view() : tail,
                   b_next = other.head.empty() ? std::string_view() : other.tail;
  while (true) {
    if (a.empty()) a = std::exchange(a_next, {});
    if (b.empty()) b = std::exchange(b_next, {});
    if (a.empty() || b.empty()) return a.empty() ? (b.empty() ? 0 : -1) : 1;
    const size_t n = std::min(a.size(), b.size());
    if (const int c = a.substr(0, n).compare(b.substr(0, n))) return c;
    a.remove_prefix(n);
    b.remove_prefix(n);
  }
}

uint32_t Entries::keep(std::string_view text) {
  if (blocks_.empty() || used_ + text.size() > kBlock) {
    if (blocks_.size() >= std::numeric_limits<uint32_t>::max() / kBlock)
      throw std::length_error("more than 4 GB of output paths to publish");
    blocks_.push_back(std::make_unique<char[]>(kBlock));
    used_ = 0;
  }
  std::copy(text.begin(), text.end(), blocks_.back().get() + used_);
  const uint32_t at = static_cast<uint32_t>(blocks_.size() - 1) * kBlock + used_;
  used_ += static_cast<uint32_t>(text.size());
  return at;
}

uint16_t Entries::name(std::string_view name) {
  if (const auto found = name_places_.find(name); found != name_places_.end()) return found->second;
  if (names_.size() > std::numeric_limits<uint16_t>::max())
    throw std::length_error("more than 65,536 kinds, sensors and stages in the files to publish");
  names_.emplace_back(name);
  return name_places_.emplace(names_.back(), static_cast<uint16_t>(names_.size() - 1)).first->second;
}

uint16_t Entries::add_stage(const std::string& stage, const Artifact& artifact) {
  if (stages_.size() > std::numeric_limits<uint16_t>::max())
    throw std::length_error("more than 65,536 stages publishing files");
  stages_.push_back({name(stage), name(stage + "/"), &artifact});
  return static_cast<uint16_t>(stages_.size() - 1);
}

void Entries::add(const Published& p, size_t place) {
  // A block holds the longest of them (a path is below 64 KB, as is a file's name in an artifact).
  for (const std::string* text : {&p.path, &p.observation})
    if (text->size() > std::numeric_limits<uint16_t>::max())
      throw std::length_error("an output path or observation id of 64 KB or more: " + text->substr(0, 200) + "...");
  if (place > std::numeric_limits<uint32_t>::max()) throw std::length_error("an artifact of over 4 billion files");
  if (list.size() >= std::numeric_limits<uint32_t>::max())
    throw std::length_error("4 billion files or more to publish");
  Entry e;
  e.stage = static_cast<uint16_t>(stages_.size() - 1);
  // As path() makes it again: the stage's folder, and the file's name as the artifact lists it.
  const std::string& folder = names_[stages_[e.stage].folder];
  const std::string_view file = stages_[e.stage].artifact->files[place].path;
  e.path_size = static_cast<uint16_t>(p.path.size());
  if (p.path.size() == folder.size() + file.size() && p.path.compare(0, folder.size(), folder) == 0 &&
      p.path.compare(folder.size(), std::string::npos, file) == 0)
    e.path_at = Entry::kInStageFolder;
  else
    e.path_at = keep(p.path);
  e.place = static_cast<uint32_t>(place);
  if (!p.observation.empty()) {  // an observation's files come together: kept once for them
    if (observations_.empty() || observations_.back().first != p.observation ||
        observations_.back().second != p.timestamp) {
      const uint32_t at = keep(p.observation);
      observations_.emplace_back(std::string_view(blocks_[at / kBlock].get() + at % kBlock, p.observation.size()),
                                 p.timestamp);
    }
    e.observation = static_cast<uint32_t>(observations_.size());
  }
  e.kind = name(p.kind);
  e.sensor = name(p.sensor);
  list.push_back(e);
}

std::vector<uint32_t> sorting_order(const Entries& entries) {
  std::vector<uint32_t> order(entries.list.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<uint32_t>(i);
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return entries.goes_before(entries.list[a], entries.list[b]); });
  return order;
}

void put_in_order(Entries& entries, const std::vector<uint32_t>& order) {
  auto& list = entries.list;
  const auto refuse = [] { throw std::invalid_argument("put_in_order: not a permutation of the entries' places"); };
  if (order.size() != list.size()) refuse();
  std::vector<bool> placed(order.size(), false);  // first: whether each place is taken by one entry
  for (const uint32_t from : order) {
    if (from >= placed.size() || placed[from]) refuse();
    placed[from] = true;
  }
  placed.assign(order.size(), false);  // now: whether each place holds its entry
  for (size_t start = 0; start < order.size(); ++start) {
    if (placed[start]) continue;
    const Entry first = list[start];  // the one value overwritten before it is read
    for (size_t at = start;;) {
      placed[at] = true;
      const size_t from = order[at];
      if (from == start) {
        list[at] = first;
        break;
      }
      list[at] = list[from];
      at = from;
    }
  }
}

bool sorted(const Entries& entries) {
  for (size_t i = 1; i < entries.list.size(); ++i)
    if (entries.goes_before(entries.list[i], entries.list[i - 1])) return false;
  return true;
}

std::vector<uint32_t> listed_places(const Entries& entries, const PreviousManifest& previous) {
  if (previous.files.size() >= kNotListed) throw std::length_error("a manifest of 4 billion files or more");
  std::vector<uint32_t> places(entries.list.size(), kNotListed);
  size_t j = 0;
  std::string scratch;
  for (size_t i = 0; i < entries.list.size(); ++i) {
    const std::string_view path = entries.path(entries.list[i]).in(scratch);
    while (j < previous.files.size() && previous.path(previous.files[j]) < path) ++j;
    if (j < previous.files.size() && previous.path(previous.files[j]) == path) places[i] = static_cast<uint32_t>(j);
  }
  return places;
}

PreviousManifest previous_manifest(const FileSystem& files, const fs::path& manifest_file) {
  PreviousManifest previous;
  if (!files.stat(manifest_file, true).is_file()) return previous;
  try {
    for_each_at(files.read(manifest_file), 2, [&](const nlohmann::json& f) {
      if (!(f.is_object() && f.contains("path") && f.contains("sha256") && f["path"].is_string() &&
            f["sha256"].is_string()))
        return;
      const std::string &path = f["path"].get_ref<const std::string&>(),
                        &sha256 = f["sha256"].get_ref<const std::string&>();
      const size_t at = previous.text.size();
      previous.files.push_back({at, path.size(), at + path.size(), sha256.size()});
      previous.text += path + sha256;
    });
  } catch (const nlohmann::json::exception&) {
    return {};  // not a manifest OLT can read: nothing in the output is taken for ours
  }
  std::sort(previous.files.begin(), previous.files.end(),
            [&](const PreviousManifest::File& a, const PreviousManifest::File& b) {
              return previous.path(a) < previous.path(b);
            });
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
// it): as JSON values, 80,000 entries took 0.2-0.5 s to build and dump, and ~1 KB each. Appended in
// place, with what entries share quoted once (an observation's member, their kinds, sensors and
// stages). A publish that changes the output needs the text twice (its digest, then the file);
// manifest_text holds one of at most kManifestHeldBytes and makes a longer one twice: at 10,000
// observations (31 MB, made twice) it was a tenth of an `olt watch` cycle.
void manifest_pieces(const Entries& entries, const PieceSink& sink) {
  Pieces pieces(sink);
  std::string& text = pieces.text();
  const auto& list = entries.list;
  std::string scratch;  // a path assembled
  text = list.empty() ? "{\n \"files\": []\n}\n" : "{\n \"files\": [\n";
  std::map<const std::string*, std::string> quoted;  // names quoted, by their address among the entries' names
  const auto quote = [&](const std::string& name) -> const std::string& {
    auto [it, made] = quoted.try_emplace(&name);
    if (made) it->second = json_string(name);
    return it->second;
  };
  std::string observation;  // the member of the last entry's observation
  uint32_t observation_of = 0;
  for (size_t i = 0; i < list.size(); ++i) {
    const Entry& e = list[i];
    text += i ? ",\n  {\n" : "  {\n";
    text += "   \"kind\": ";
    text += quote(entries.kind(e));
    text += ",\n";
    if (e.observation) {
      if (e.observation != observation_of) {
        observation = "   \"observation\": {\n    \"id\": ";
        append_json_string(observation, entries.observation(e));
        observation += ",\n    \"timestamp\": " + nlohmann::json(entries.timestamp(e)).dump() + "\n   },\n";
        observation_of = e.observation;
      }
      text += observation;
    }
    text += "   \"path\": ";
    append_json_string(text, entries.path(e).in(scratch));
    text += ",\n";
    if (!entries.sensor(e).empty()) {
      text += "   \"sensor\": ";
      text += quote(entries.sensor(e));
      text += ",\n";
    }
    text += "   \"sha256\": \"";
    entries.file(e).sha256.append_hex(text);
    text += "\",\n   \"stage\": ";
    text += quote(entries.stage(e));
    text += "\n  }";
    pieces.next();
  }
  if (!list.empty()) text += "\n ]\n}\n";
  pieces.flush();
}

ManifestText manifest_text(const Entries& entries, size_t held_bytes) {
  ManifestText manifest;
  manifest.text.emplace();
  Sha256 hash;
  manifest_pieces(entries, [&](std::string_view piece) {
    hash.update(piece);
    if (!manifest.text) return;
    if (manifest.text->size() + piece.size() > held_bytes)
      manifest.text.reset();
    else
      manifest.text->append(piece);
  });
  manifest.digest = hash.hex();
  return manifest;
}

void ManifestText::pieces(const Entries& entries, const PieceSink& sink) const {
  if (text)
    sink(*text);
  else
    manifest_pieces(entries, sink);
}

// Read instead of the manifest (31 MB of JSON at 80,000 files, 0.3 s to parse) when it copies the
// manifest there.
void listing_pieces(const std::string& digest, const Entries& entries, const PieceSink& sink) {
  Pieces pieces(sink);
  std::string& text = pieces.text();
  text = kListingFormat + digest + "\n";
  std::string scratch;
  for (const Entry& e : entries.list) {
    const std::string_view path = entries.path(e).in(scratch);
    text += entries.file(e).sha256.hex() + " " + std::to_string(path.size()) + " ";
    text += path;
    text += '\n';
    pieces.next();
  }
  pieces.flush();
}

std::optional<PreviousManifest> read_listing(const FileSystem& files, const fs::path& file,
                                             const std::string& manifest_digest) {
  if (file.empty() || manifest_digest.empty() || !files.stat(file).is_file()) return std::nullopt;
  try {
    PreviousManifest listed;
    listed.text = files.read(file);
    const std::string_view text = listed.text;
    const std::string head = kListingFormat + manifest_digest + "\n";  // another format's is a miss
    if (text.compare(0, head.size(), head) != 0) return std::nullopt;
    listed.files.reserve(static_cast<size_t>(std::count(text.begin(), text.end(), '\n')));  // a line a file
    for (size_t at = head.size(); at < text.size();) {
      const size_t space = text.find(' ', at);
      const size_t second = space == std::string::npos ? space : text.find(' ', space + 1);
      if (second == std::string::npos || second == space + 1) return std::nullopt;
      const std::string digits(text.substr(space + 1, second - space - 1));
      if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
      const size_t length = std::stoul(digits), end = second + 1 + length;
      if (end >= text.size() || text[end] != '\n') return std::nullopt;
      const std::string_view path = text.substr(second + 1, length);
      if (!listed.files.empty() && !(listed.path(listed.files.back()) < path))
        return std::nullopt;  // sorted, as written
      listed.files.push_back({second + 1, length, at, space - at});
      at = end + 1;
    }
    return listed;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace olt
