#include "publish_list.h"

#include <cstring>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "olt/core/json_text.h"

namespace olt {

// Members in nlohmann's (sorted) order: file, kind, observation, path, sensor. Appended in place, the
// observation's member made once for its files (which come together): the labeling stage lists
// 40,000 entries at 10,000 frames, made again each `olt watch` cycle.
void PublishListText::add(const Published& p) {
  std::string& text = entry_;
  text = count_++ == 0 ? "\n {\n  \"file\": " : ",\n {\n  \"file\": ";
  append_json_string(text, p.file);
  text += ",\n  \"kind\": ";
  append_json_string(text, p.kind);
  if (!p.observation.empty()) {
    // By the timestamp's bits: -0.0 equals 0.0, but is written otherwise.
    if (p.observation != observation_ || std::memcmp(&p.timestamp, &timestamp_, sizeof(double)) != 0 ||
        observation_text_.empty()) {
      observation_ = p.observation;
      timestamp_ = p.timestamp;
      observation_text_ = ",\n  \"observation\": {\n   \"id\": ";
      append_json_string(observation_text_, p.observation);
      observation_text_ += ",\n   \"timestamp\": " + nlohmann::json(p.timestamp).dump() + "\n  }";
    }
    text += observation_text_;
  }
  text += ",\n  \"path\": ";
  append_json_string(text, p.path);
  if (!p.sensor.empty()) {
    text += ",\n  \"sensor\": ";
    append_json_string(text, p.sensor);
  }
  text += "\n }";
  text_.append(text);
}

void PublishListText::pieces(const PieceSink& sink) const {
  if (count_ == 0) {
    sink("[]");
    return;
  }
  sink("[");
  text_.for_each_piece(sink);
  sink("\n]");
}

void publish_list_pieces(const std::deque<Published>& list, const PieceSink& sink) {
  PublishListText text;
  for (const Published& p : list) text.add(p);
  text.pieces(sink);
}

std::string publish_list_text(const std::deque<Published>& list) {
  std::string text;
  publish_list_pieces(list, [&](std::string_view piece) { text += piece; });
  return text;
}

namespace {

// nlohmann's parser events for [{"file": s, "kind": s, "observation": {"id": s, "timestamp": n},
// "path": s, "sensor": s}...]: each entry filled as its members come, handed on at its end. Members
// this version does not know are skipped, whatever they hold (as the store's metadata reader does);
// a known member of another type, an entry without file, path or kind, an observation without id or
// timestamp, or anything but entries in the list, is an error naming the entry.
class ListReader : public nlohmann::json_sax<nlohmann::json> {
 public:
  ListReader(const std::string& name, const std::function<void(Published&&)>& each) : name_(name), each_(each) {}

  bool null() override { return value("null"); }
  bool boolean(bool) override { return value("a boolean"); }
  bool number_integer(number_integer_t v) override { return number(static_cast<double>(v)); }
  bool number_unsigned(number_unsigned_t v) override { return number(static_cast<double>(v)); }
  bool number_float(number_float_t v, const string_t&) override { return number(v); }
  bool binary(binary_t&) override { return value("binary data"); }
  bool string(string_t& v) override {
    std::string* field = nullptr;
    if (in_entry())
      field = key_ == "file"     ? &entry_.file
              : key_ == "path"   ? &entry_.path
              : key_ == "kind"   ? &entry_.kind
              : key_ == "sensor" ? &entry_.sensor
                                 : nullptr;
    else if (in_observation() && key_ == "id")
      field = &entry_.observation;
    if (!field) return value("a string");
    *field = std::move(v);
    seen_ |= in_entry() ? (key_ == "file" ? kFile : key_ == "path" ? kPath : key_ == "kind" ? kKind : 0) : kId;
    return true;
  }
  bool start_object(std::size_t) override {
    if (skip_ == 0 && depth_ == 1) {  // an entry
      entry_ = Published{};
      seen_ = 0;
      ++entries_;
    } else if (!(in_entry() && key_ == "observation")) {
      return enter("an object");
    }
    ++depth_;
    return true;
  }
  bool key(string_t& k) override {
    key_ = std::move(k);
    return true;
  }
  bool end_object() override {
    if (skip_ > 0) return leave();
    if (in_observation() && (seen_ & (kId | kTimestamp)) != (kId | kTimestamp))
      fail("its observation has no id or no timestamp");
    if (--depth_ == 1) {
      if ((seen_ & (kFile | kPath | kKind)) != (kFile | kPath | kKind)) fail("it has no file, path or kind");
      each_(std::move(entry_));
    }
    return true;
  }
  bool start_array(std::size_t) override {
    if (skip_ == 0 && depth_ == 0) return ++depth_, true;  // the list
    return enter("an array");
  }
  bool end_array() override {
    if (skip_ > 0) return leave();
    --depth_;
    return true;
  }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
    throw std::runtime_error(name_ + ": not a publish list (at byte " + std::to_string(position) + "): " + e.what());
  }

 private:
  static constexpr int kFile = 1, kPath = 2, kKind = 4, kId = 8, kTimestamp = 16;

  bool in_entry() const { return skip_ == 0 && depth_ == 2; }
  bool in_observation() const { return skip_ == 0 && depth_ == 3; }
  // Whether the value being read is where this reader expects something of its own (the list, an
  // entry, or a member it knows), so that another type there is an error rather than skipped.
  bool expected() const {
    if (skip_ > 0) return false;
    if (depth_ <= 1) return true;
    if (in_entry())
      return key_ == "file" || key_ == "path" || key_ == "kind" || key_ == "sensor" || key_ == "observation";
    return key_ == "id" || key_ == "timestamp";
  }
  bool value(const std::string& what) {
    if (expected()) fail(what + (depth_ <= 1 ? "" : " in '" + key_ + "'"));
    return true;
  }
  bool enter(const std::string& what) {
    value(what);
    ++skip_;
    return true;
  }
  bool leave() {
    --skip_;
    return true;
  }
  bool number(double v) {
    if (!in_observation() || key_ != "timestamp") return value("a number");
    entry_.timestamp = v;
    seen_ |= kTimestamp;
    return true;
  }
  [[noreturn]] void fail(const std::string& what) const {
    const std::string where = depth_ == 0   ? "the list"
                              : depth_ == 1 ? "the list's entries"
                                            : "entry " + std::to_string(entries_);
    throw std::runtime_error(name_ + ": not a publish list: " + where + ": " + what);
  }

  const std::string& name_;
  const std::function<void(Published&&)>& each_;
  int depth_ = 0, skip_ = 0, seen_ = 0, entries_ = 0;
  std::string key_;
  Published entry_;
};

}  // namespace

void read_publish_list(std::istream& text, const std::string& name, const std::function<void(Published&&)>& each) {
  ListReader reader(name, each);
  nlohmann::json::sax_parse(text, &reader);
}

}  // namespace olt
