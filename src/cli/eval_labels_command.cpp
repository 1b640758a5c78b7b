// `olt eval labels A B`: agreement of two labelings of one recording (olt/eval/label_agreement.h).
// A and B are output folders of `olt run` (OUTPUT/manifest.json lists the class_label images by
// sensor and observation; OUTPUT/labels.json names the classes), or folders of class-id PNGs
// matched by their path below the folder (classes named by a labels.json in the folder or its
// parent, if there is one).
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "eval_commands.h"
#include "olt/config/document.h"
#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/image.h"
#include "olt/eval/label_agreement.h"

namespace olt {
namespace {

// One frame's class-id image in a labeled folder.
struct LabelFrame {
  std::string key;          ///< "SENSOR/OBSERVATION", or the image's path below the folder
  std::string sensor;       ///< "" for a folder of PNGs
  std::string observation;  ///< observation id; "" for a folder of PNGs
  fs::path image;
};

struct LabelFolder {
  std::string folder;                        ///< as given
  bool has_manifest = false;                 ///< an output folder of olt run
  std::map<std::string, LabelFrame> frames;  ///< by key
  std::optional<ClassCoding> coding;         ///< from labels_file
  std::string labels_file;                   ///< "" when there is none
};

std::string text_at(const Document& doc, const std::string& pointer) {
  const nlohmann::json& v = doc.value.at(nlohmann::json::json_pointer(pointer));
  if (!v.is_string()) throw InputError({doc.error_at(pointer, "expected a string")});
  return v.get<std::string>();
}

// The class_label files of OUTPUT/manifest.json ({"files": [{"path", "kind", "sensor",
// "observation": {"id", "timestamp"}}]}).
void read_manifest(const fs::path& folder, LabelFolder* set) {
  const fs::path file = folder / "manifest.json";
  const Document doc = parse_json_document(file.string(), read_file(file));
  if (!doc.value.contains("files") || !doc.value["files"].is_array())
    throw InputError({doc.error_at("", "expected {\"files\": [...]}")});
  const auto& files = doc.value["files"];
  for (size_t i = 0; i < files.size(); ++i) {
    const std::string at = "/files/" + std::to_string(i);
    if (!files[i].is_object() || files[i].value("kind", nlohmann::json()) != "class_label") continue;
    for (const char* key : {"/path", "/sensor", "/observation/id"})
      if (!doc.value.contains(nlohmann::json::json_pointer(at + key)))
        throw InputError({doc.error_at(at, std::string("a class_label file without ") + (key + 1))});
    LabelFrame frame{"", text_at(doc, at + "/sensor"), text_at(doc, at + "/observation/id"),
                     folder / text_at(doc, at + "/path")};
    frame.key = frame.sensor + "/" + frame.observation;
    if (!set->frames.emplace(frame.key, frame).second)
      throw InputError({doc.error_at(at, "a second class_label file of " + frame.key)});
  }
  if (set->frames.empty()) throw InputError(file.string(), "lists no class_label file");
}

void read_png_folder(const fs::path& folder, LabelFolder* set) {
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".png") continue;
    const std::string key = entry.path().lexically_relative(folder).generic_string();
    set->frames[key] = {key, "", "", entry.path()};
  }
  if (set->frames.empty()) throw InputError(folder.string(), "holds no PNG file (and no manifest.json)");
}

// labels.json: {"classes": [{"id", "name", ...}], "unlabeled": 0, "no_depth": 65535}.
ClassCoding read_class_coding(const fs::path& file) {
  const Document doc = parse_json_document(file.string(), read_file(file));
  auto id_at = [&](const std::string& pointer) {
    const nlohmann::json& v = doc.value.at(nlohmann::json::json_pointer(pointer));
    if (!v.is_number_integer() || v.get<int64_t>() < 0 || v.get<int64_t>() > 65535)
      throw InputError({doc.error_at(pointer, "expected a class id, an integer in 0..65535")});
    return static_cast<uint16_t>(v.get<int64_t>());
  };
  if (!doc.value.is_object() || !doc.value.contains("classes") || !doc.value["classes"].is_array())
    throw InputError({doc.error_at("", "expected {\"classes\": [{\"id\", \"name\"}, ...]}")});
  ClassCoding coding;
  for (size_t i = 0; i < doc.value["classes"].size(); ++i) {
    const std::string at = "/classes/" + std::to_string(i);
    if (!doc.value.contains(nlohmann::json::json_pointer(at + "/id")) ||
        !doc.value.contains(nlohmann::json::json_pointer(at + "/name")))
      throw InputError({doc.error_at(at, "a class without \"id\" or \"name\"")});
    if (!coding.names.emplace(id_at(at + "/id"), text_at(doc, at + "/name")).second)
      throw InputError({doc.error_at(at + "/id", "a second class of this id")});
  }
  if (doc.value.contains("unlabeled")) coding.unlabeled = id_at("/unlabeled");
  if (doc.value.contains("no_depth")) coding.no_depth = id_at("/no_depth");
  return coding;
}

LabelFolder read_label_folder(const std::string& given) {
  const fs::path folder(given);
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(given, "no such folder (expected an output folder of olt run, or a folder of class-id PNGs)");
  LabelFolder set;
  set.folder = given;
  set.has_manifest = fs::exists(folder / "manifest.json");
  if (set.has_manifest)
    read_manifest(folder, &set);
  else
    read_png_folder(folder, &set);
  std::vector<fs::path> candidates = {folder / "labels.json"};
  if (!set.has_manifest) candidates.push_back(fs::canonical(folder).parent_path() / "labels.json");
  for (const auto& candidate : candidates) {
    if (fs::is_regular_file(candidate, ec)) {
      set.labels_file = candidate.string();
      set.coding = read_class_coding(candidate);
      break;
    }
  }
  return set;
}

nlohmann::ordered_json frame_json(const LabelFrame& f) {
  if (f.observation.empty()) return {{"frame", f.key}};
  return {{"frame", f.key}, {"sensor", f.sensor}, {"observation", f.observation}};
}

std::vector<std::string> keys_only_in(const LabelFolder& x, const LabelFolder& y) {
  std::vector<std::string> keys;
  for (const auto& [key, frame] : x.frames)
    if (!y.frames.count(key)) keys.push_back(key);
  return keys;
}

void print_keys(const char* label, const std::vector<std::string>& keys) {
  std::printf("%-23s%zu", label, keys.size());
  for (size_t i = 0; i < keys.size() && i < 10; ++i) std::printf("%s %s", i ? "," : ":", keys[i].c_str());
  std::printf("%s\n", keys.size() > 10 ? ", ..." : "");
}

// Two label folders compared frame by frame, with what the reports show.
struct Comparison {
  LabelFolder a, b;
  bool by_name = false;                     ///< classes matched by name (labels.json on both sides)
  std::vector<const LabelFrame*> compared;  ///< frames of A also in B
  std::vector<FrameComparison> frames;      ///< per compared frame
  LabelAgreement summary;
  std::vector<size_t> worst;  ///< indices into compared
  std::vector<std::string> only_a, only_b;
};

void compare(Comparison& c, size_t worst) {
  // Classes are matched by name when both sides name them; with one labels.json, it names both
  // sides' ids, which are then compared as they are.
  c.by_name = c.a.coding && c.b.coding;
  if (!c.a.coding) c.a.coding = c.b.coding.value_or(ClassCoding{});
  if (!c.b.coding) c.b.coding = c.a.coding;
  for (const auto& [key, frame_a] : c.a.frames) {
    const auto it = c.b.frames.find(key);
    if (it == c.b.frames.end()) continue;
    const cv::Mat image_a = read_grey16(frame_a.image), image_b = read_grey16(it->second.image);
    if (image_a.size() != image_b.size())
      throw InputError(it->second.image.string(), std::to_string(image_b.cols) + "x" + std::to_string(image_b.rows) +
                                                      ", but the image of this frame in A (" + frame_a.image.string() +
                                                      ") is " + std::to_string(image_a.cols) + "x" +
                                                      std::to_string(image_a.rows));
    c.compared.push_back(&frame_a);
    c.frames.push_back(compare_labels(image_a, image_b, *c.a.coding, *c.b.coding));
  }
  if (c.compared.empty())
    throw InputError(c.b.folder, "no frame in common with " + c.a.folder + " (" + std::to_string(c.a.frames.size()) +
                                     " and " + std::to_string(c.b.frames.size()) + " class-id images)");
  c.summary = summarize_agreement(c.frames);
  c.worst = worst_frames(c.summary, worst);
  c.only_a = keys_only_in(c.a, c.b);
  c.only_b = keys_only_in(c.b, c.a);
}

nlohmann::ordered_json side_json(const LabelFolder& f) {
  return nlohmann::ordered_json{
      {"folder", f.folder},
      {"manifest", f.has_manifest},
      {"labels_json", f.labels_file.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(f.labels_file)},
      {"frames", f.frames.size()}};
}

nlohmann::ordered_json compared_frame_json(const Comparison& c, size_t i) {
  nlohmann::ordered_json j = frame_json(*c.compared[i]);
  j["agreement"] = c.summary.frame_agreement[i];
  j["labeled_pixels"] = c.frames[i].labeled;
  j["agreeing_pixels"] = c.frames[i].agreeing;
  j["depth_differs_pixels"] = c.frames[i].depth_differs;
  return j;
}

void print_json(const Comparison& c) {
  const LabelAgreement& s = c.summary;
  using ojson = nlohmann::ordered_json;
  ojson classes = ojson::array(), frames = ojson::array(), worst = ojson::array(), only_a = ojson::array(),
        only_b = ojson::array();
  for (const auto& k : s.classes)
    classes.push_back({{"name", k.name},
                       {"iou", k.iou},
                       {"pixels_a", k.pixels.in_a},
                       {"pixels_b", k.pixels.in_b},
                       {"intersection", k.pixels.both},
                       {"union", k.pixels.union_pixels()}});
  for (size_t i = 0; i < c.compared.size(); ++i) frames.push_back(compared_frame_json(c, i));
  for (size_t i : c.worst) worst.push_back(compared_frame_json(c, i));
  for (const auto& key : c.only_a) only_a.push_back(frame_json(c.a.frames.at(key)));
  for (const auto& key : c.only_b) only_b.push_back(frame_json(c.b.frames.at(key)));
  const ojson out = {{"a", side_json(c.a)},
                     {"b", side_json(c.b)},
                     {"classes_matched_by", c.by_name ? "name" : "id"},
                     {"frames_compared", c.compared.size()},
                     {"frames_only_in_a", only_a},
                     {"frames_only_in_b", only_b},
                     {"classes", classes},
                     {"mean_iou", s.mean_iou},
                     {"agreement", s.agreement},
                     {"labeled_pixels", s.labeled},
                     {"agreeing_pixels", s.agreeing},
                     {"depth_differs_pixels", s.depth_differs},
                     {"frame_agreement", {{"min", s.min_frame_agreement}, {"median", s.median_frame_agreement}}},
                     {"worst_frames", worst},
                     {"frames", frames}};
  std::printf("%s\n", out.dump(2).c_str());  // in the order above, as the text report
}

void print_text(const Comparison& c) {
  const LabelAgreement& s = c.summary;
  std::printf("classes matched by     %s\n", c.by_name                 ? "name (labels.json on both sides)"
                                             : c.a.labels_file.empty() ? "id (no labels.json)"
                                                                       : "id (one labels.json)");
  std::printf("frames compared        %zu\n", c.compared.size());
  print_keys("frames only in A", c.only_a);
  print_keys("frames only in B", c.only_b);
  std::printf("%-23s%8s %12s %12s\n", "class", "IoU", "pixels A", "pixels B");
  for (const auto& k : s.classes)
    std::printf("  %-21s%8.4f %12lld %12lld\n", k.name.c_str(), k.iou, static_cast<long long>(k.pixels.in_a),
                static_cast<long long>(k.pixels.in_b));
  std::printf("mean IoU               %.4f over %zu classes\n", s.mean_iou, s.classes.size());
  std::printf("agreement              %.4f of %lld pixels labeled in A or B\n", s.agreement,
              static_cast<long long>(s.labeled));
  std::printf("depth on one side only %lld pixels (left out)\n", static_cast<long long>(s.depth_differs));
  std::printf("frame agreement        min %.4f, median %.4f\n", s.min_frame_agreement, s.median_frame_agreement);
  if (c.worst.empty()) return;
  std::printf("worst frames           agreement  labeled pixels  %s\n", c.a.has_manifest ? "sensor" : "");
  for (size_t i : c.worst) {
    const LabelFrame& f = *c.compared[i];
    std::printf("  %-21s%9.4f %15lld  %s\n", (c.a.has_manifest ? f.observation : f.key).c_str(), s.frame_agreement[i],
                static_cast<long long>(c.frames[i].labeled), f.sensor.c_str());
  }
}

}  // namespace

int eval_labels(const Args& args) {
  check_flags(args, "labels", {"--json", "--worst"});
  const std::string worst_text = args.value("--worst", "5");
  char* end = nullptr;
  const long worst = std::strtol(worst_text.c_str(), &end, 10);
  if (worst_text.empty() || *end != '\0' || worst < 0)
    throw InputError("--worst", "expected a number of frames (0 or more), got '" + worst_text + "'");
  Comparison c;
  c.a = read_label_folder(args.positional[1]);
  c.b = read_label_folder(args.positional[2]);
  if (c.a.has_manifest != c.b.has_manifest)
    throw InputError(c.b.folder, std::string(c.b.has_manifest ? "is" : "is not") + " an output folder of olt run (" +
                                     (c.b.has_manifest ? "has" : "no") + " manifest.json) and " + c.a.folder +
                                     (c.a.has_manifest ? " is" : " is not") + ": give two of one sort");
  compare(c, static_cast<size_t>(worst));
  if (args.has("--json"))
    print_json(c);
  else
    print_text(c);
  return kExitOk;
}

}  // namespace olt
