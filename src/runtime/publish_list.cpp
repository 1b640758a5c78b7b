#include "publish_list.h"

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "olt/core/json_text.h"

namespace olt {

std::string publish_list_text(const std::vector<Published>& list) {
  if (list.empty()) return "[]";
  std::string text = "[";
  for (const Published& p : list) {
    // Members in nlohmann's (sorted) order: file, kind, observation, path, sensor.
    text += text.size() == 1 ? "\n {\n  \"file\": " : ",\n {\n  \"file\": ";
    text += json_string(p.file) + ",\n  \"kind\": " + json_string(p.kind);
    if (!p.observation.empty())
      text += ",\n  \"observation\": {\n   \"id\": " + json_string(p.observation) +
              ",\n   \"timestamp\": " + nlohmann::json(p.timestamp).dump() + "\n  }";
    text += ",\n  \"path\": " + json_string(p.path);
    if (!p.sensor.empty()) text += ",\n  \"sensor\": " + json_string(p.sensor);
    text += "\n }";
  }
  return text + "\n]";
}

namespace {

// nlohmann's SAX events for an array of entry objects: each entry filled as its members come, handed
// on at its end. Members this version does not know are ignored (strings and numbers); anything else
// is an error.
class ListReader : public nlohmann::json_sax<nlohmann::json> {
 public:
  ListReader(const std::string& name, const std::function<void(Published&&)>& each) : name_(name), each_(each) {}

  bool null() override { return fail("null"); }
  bool boolean(bool) override { return fail("a boolean"); }
  bool number_integer(number_integer_t v) override { return number(static_cast<double>(v)); }
  bool number_unsigned(number_unsigned_t v) override { return number(static_cast<double>(v)); }
  bool number_float(number_float_t v, const string_t&) override { return number(v); }
  bool binary(binary_t&) override { return fail("binary data"); }
  bool string(string_t& v) override {
    std::string* field = depth_ == 2                   ? key_ == "file"     ? &entry_.file
                                                         : key_ == "path"   ? &entry_.path
                                                         : key_ == "kind"   ? &entry_.kind
                                                         : key_ == "sensor" ? &entry_.sensor
                                                                            : nullptr
                         : depth_ == 3 && key_ == "id" ? &entry_.observation
                                                       : nullptr;
    if (!field) return depth_ >= 2 || fail("a string");  // a member this version does not know: ignored
    *field = std::move(v);
    seen_ |= depth_ == 2 && key_ == "file"   ? 1
             : depth_ == 2 && key_ == "path" ? 2
             : depth_ == 2 && key_ == "kind" ? 4
                                             : 0;
    return true;
  }
  bool start_object(std::size_t) override {
    if (depth_ == 1) {
      entry_ = Published{};
      seen_ = 0;
    } else if (!(depth_ == 2 && key_ == "observation")) {
      return fail("an object");
    }
    ++depth_;
    return true;
  }
  bool key(string_t& k) override {
    key_ = std::move(k);
    return true;
  }
  bool end_object() override {
    if (--depth_ == 1) {
      if (seen_ != 7) return fail("an entry without file, path or kind");
      each_(std::move(entry_));
    }
    return true;
  }
  bool start_array(std::size_t) override { return depth_++ == 0 || fail("an array"); }
  bool end_array() override {
    --depth_;
    return true;
  }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
    throw std::runtime_error(name_ + ": not a publish list (at byte " + std::to_string(position) + "): " + e.what());
  }

 private:
  bool number(double v) {
    if (depth_ != 3 || key_ != "timestamp") return depth_ >= 2 || fail("a number");
    entry_.timestamp = v;
    return true;
  }
  bool fail(const std::string& what) {
    throw std::runtime_error(name_ + ": not a publish list: " + what + " where an entry's member belongs");
  }

  const std::string& name_;
  const std::function<void(Published&&)>& each_;
  int depth_ = 0;
  int seen_ = 0;
  std::string key_;
  Published entry_;
};

}  // namespace

void read_publish_list(const std::string& text, const std::string& name, const std::function<void(Published&&)>& each) {
  ListReader reader(name, each);
  nlohmann::json::sax_parse(text, &reader);
}

}  // namespace olt
