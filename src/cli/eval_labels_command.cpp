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

}  // namespace

int eval_labels(const Args& args) {
  check_flags(args, "labels", {"--json", "--worst"});
  const std::string worst_text = args.value("--worst", "5");
  char* end = nullptr;
  const long worst = std::strtol(worst_text.c_str(), &end, 10);
  if (worst_text.empty() || *end != '\0' || worst < 0)
    throw InputError("--worst", "expected a number of frames (0 or more), got '" + worst_text + "'");
  LabelFolder a = read_label_folder(args.positional[1]), b = read_label_folder(args.positional[2]);
  if (a.has_manifest != b.has_manifest)
    throw InputError(b.folder, std::string(b.has_manifest ? "is" : "is not") + " an output folder of olt run (" +
                                   (b.has_manifest ? "has" : "no") + " manifest.json) and " + a.folder +
                                   (a.has_manifest ? " is" : " is not") + ": give two of one sort");
  // Classes are matched by name when both sides name them; with one labels.json, it names both
  // sides' ids, which are then compared as they are.
  const bool by_name = a.coding && b.coding;
  if (!a.coding) a.coding = b.coding.value_or(ClassCoding{});
  if (!b.coding) b.coding = a.coding;

  std::vector<const LabelFrame*> compared;
  std::vector<FrameComparison> comparisons;
  for (const auto& [key, frame_a] : a.frames) {
    const auto it = b.frames.find(key);
    if (it == b.frames.end()) continue;
    const cv::Mat image_a = read_png_u16(frame_a.image), image_b = read_png_u16(it->second.image);
    if (image_a.size() != image_b.size())
      throw InputError(it->second.image.string(), std::to_string(image_b.cols) + "x" + std::to_string(image_b.rows) +
                                                      ", but the image of this frame in A (" + frame_a.image.string() +
                                                      ") is " + std::to_string(image_a.cols) + "x" +
                                                      std::to_string(image_a.rows));
    compared.push_back(&frame_a);
    comparisons.push_back(compare_labels(image_a, image_b, *a.coding, *b.coding));
  }
  if (compared.empty())
    throw InputError(b.folder, "no frame in common with " + a.folder + " (" + std::to_string(a.frames.size()) +
                                   " and " + std::to_string(b.frames.size()) + " class-id images)");
  const LabelAgreement s = summarize_agreement(comparisons);
  const std::vector<size_t> worst_list = worst_frames(s, static_cast<size_t>(worst));
  const auto only_a = keys_only_in(a, b), only_b = keys_only_in(b, a);

  if (args.has("--json")) {
    auto side = [](const LabelFolder& f) {
      return nlohmann::ordered_json{
          {"folder", f.folder},
          {"manifest", f.has_manifest},
          {"labels_json", f.labels_file.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(f.labels_file)},
          {"frames", f.frames.size()}};
    };
    auto frame = [&](size_t i) {
      nlohmann::ordered_json j = frame_json(*compared[i]);
      j["agreement"] = s.frame_agreement[i];
      j["labeled_pixels"] = comparisons[i].labeled;
      j["agreeing_pixels"] = comparisons[i].agreeing;
      j["depth_differs_pixels"] = comparisons[i].depth_differs;
      return j;
    };
    nlohmann::ordered_json classes = nlohmann::ordered_json::array(), frames = nlohmann::ordered_json::array(),
                           worst_json = nlohmann::ordered_json::array(), only_a_json = nlohmann::ordered_json::array(),
                           only_b_json = nlohmann::ordered_json::array();
    for (const auto& c : s.classes)
      classes.push_back({{"name", c.name},
                         {"iou", c.iou},
                         {"pixels_a", c.pixels.in_a},
                         {"pixels_b", c.pixels.in_b},
                         {"intersection", c.pixels.both},
                         {"union", c.pixels.union_pixels()}});
    for (size_t i = 0; i < compared.size(); ++i) frames.push_back(frame(i));
    for (size_t i : worst_list) worst_json.push_back(frame(i));
    for (const auto& key : only_a) only_a_json.push_back(frame_json(a.frames.at(key)));
    for (const auto& key : only_b) only_b_json.push_back(frame_json(b.frames.at(key)));
    const nlohmann::ordered_json out = {
        {"a", side(a)},
        {"b", side(b)},
        {"classes_matched_by", by_name ? "name" : "id"},
        {"frames_compared", compared.size()},
        {"frames_only_in_a", only_a_json},
        {"frames_only_in_b", only_b_json},
        {"classes", classes},
        {"mean_iou", s.mean_iou},
        {"agreement", s.agreement},
        {"labeled_pixels", s.labeled},
        {"agreeing_pixels", s.agreeing},
        {"depth_differs_pixels", s.depth_differs},
        {"frame_agreement", {{"min", s.min_frame_agreement}, {"median", s.median_frame_agreement}}},
        {"worst_frames", worst_json},
        {"frames", frames}};
    std::printf("%s\n", out.dump(2).c_str());  // in the order above, as the text report
    return kExitOk;
  }
  std::printf("classes matched by     %s\n", by_name                 ? "name (labels.json on both sides)"
                                             : a.labels_file.empty() ? "id (no labels.json)"
                                                                     : "id (one labels.json)");
  std::printf("frames compared        %zu\n", compared.size());
  print_keys("frames only in A", only_a);
  print_keys("frames only in B", only_b);
  std::printf("%-23s%8s %12s %12s\n", "class", "IoU", "pixels A", "pixels B");
  for (const auto& c : s.classes)
    std::printf("  %-21s%8.4f %12lld %12lld\n", c.name.c_str(), c.iou, static_cast<long long>(c.pixels.in_a),
                static_cast<long long>(c.pixels.in_b));
  std::printf("mean IoU               %.4f over %zu classes\n", s.mean_iou, s.classes.size());
  std::printf("agreement              %.4f of %lld pixels labeled in A or B\n", s.agreement,
              static_cast<long long>(s.labeled));
  std::printf("depth on one side only %lld pixels (left out)\n", static_cast<long long>(s.depth_differs));
  std::printf("frame agreement        min %.4f, median %.4f\n", s.min_frame_agreement, s.median_frame_agreement);
  if (worst_list.empty()) return kExitOk;
  std::printf("worst frames           agreement  labeled pixels  %s\n", a.has_manifest ? "sensor" : "");
  for (size_t i : worst_list) {
    const LabelFrame& f = *compared[i];
    std::printf("  %-21s%9.4f %15lld  %s\n", (a.has_manifest ? f.observation : f.key).c_str(), s.frame_agreement[i],
                static_cast<long long>(comparisons[i].labeled), f.sensor.c_str());
  }
  return kExitOk;
}

}  // namespace olt
