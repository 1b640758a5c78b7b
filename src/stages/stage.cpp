#include "olt/stages/stage.h"

#include <mutex>

#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/core/hash.h"
#include "olt/core/process_memory.h"
#include "olt/formats/annotations.h"
#include "olt/stages/artifacts.h"

namespace olt {

std::string StageContext::kept_name(std::string_view what) const {
  return std::string(what) + ":" + job_file.string() + ":" + stage.id;
}

Unit unit_of(std::string name, std::string_view record) { return {std::move(name), Digest(sha256_hex(record))}; }

StageKind make_stage_kind(KindSpec spec, int version, std::function<std::vector<fs::path>(const StageDecl&)> files_read,
                          StageFunction run) {
  StageKind kind;
  kind.spec = std::move(spec);
  kind.version = version;
  kind.files_read = files_read ? std::move(files_read) : [](const StageDecl&) { return std::vector<fs::path>{}; };
  kind.run = std::move(run);
  return kind;
}

const StageInput* StageContext::input(const std::string& kind) const {
  auto it = inputs.find(kind);
  return it == inputs.end() ? nullptr : &it->second;
}

const StageInput& StageContext::need(const std::string& kind) const {
  const StageInput* found = input(kind);
  if (!found) throw std::logic_error("stage '" + stage.id + "' has no input of kind " + kind);
  return *found;
}

namespace {

// `file` of `input`'s artifact as `read` makes it: the one in `slot` when that is it (the same digest
// listed, the same folder), else read and kept there. Read afresh where the input has no shared
// reads or its artifact does not list the file. A process that keeps memory between runs (`olt
// watch`) keeps it for the next run too: parsing a 10,000-observation recording and its poses was 3 %
// of each cycle after a one-box edit. What it holds is taken as twice its file's size.
template <typename T>
std::shared_ptr<const T> read_shared(const StageInput& input, SharedReads::Slot<T> SharedReads::*slot_of,
                                     const std::string& file, const std::function<T()>& read) {
  const std::optional<ListedFile> listed = input.artifact.file(file);
  if (!input.shared || !listed || listed->sha256.empty()) return std::make_shared<const T>(read());
  SharedReads::Slot<T>& slot = input.shared->*slot_of;
  const std::string key = listed->sha256.hex() + "\n" + input.artifact.dir.string();
  std::lock_guard<std::mutex> lock(slot.mutex);  // held while reading: a second reader waits for the first
  if (!slot.value || slot.key != key) {
    slot.value.reset();  // the one before let go first
    const size_t bytes = 2 * listed->size;
    slot.value =
        remembered_or_made<T>("read:" + file + " of " + input.stage_id, key, read, [bytes](const T&) { return bytes; });
    slot.key = key;
  }
  return slot.value;
}

template <typename T>
void clear_slot(SharedReads::Slot<T>& slot) {
  std::lock_guard<std::mutex> lock(slot.mutex);
  slot.key.clear();
  slot.value.reset();
}

}  // namespace

void SharedReads::clear() {
  clear_slot(recording);
  clear_slot(poses);
}

namespace {

constexpr char kRecordingFile[] = "recording.json";

}  // namespace

bool recording_lookup(const ListedFile& f) { return referred_file(f) || f.path == kRecordingFile; }

std::shared_ptr<const Recording> shared_recording(const StageInput& source) {
  return read_shared<Recording>(source, &SharedReads::recording, kRecordingFile, [&] {
    Recording r = recording_from_text(*open_file_stream(source.artifact.path(kRecordingFile)));
    auto absolute = [&](std::string& path) {
      if (!path.empty() && fs::path(path).is_relative()) path = source.artifact.path(path).string();
    };
    // An image the source wrote is in its folder (one shared folder); one it refers to, elsewhere.
    const auto folder = std::make_shared<const fs::path>(source.artifact.dir);
    auto place = [&](ImageFile& image) {
      if (image.path.empty() || fs::path(image.path).is_absolute()) return;
      const std::optional<ListedFile> listed = source.artifact.file(image.path);
      if (listed && !listed->in.empty())
        absolute(image.path);
      else
        image.folder = folder;
    };
    for (auto& o : r.observations) {
      place(o.depth);
      if (o.color) place(*o.color);
    }
    absolute(r.groundtruth);
    absolute(r.boxes);
    absolute(r.laser_scans);
    absolute(r.odometry);
    return r;
  });
}

std::shared_ptr<const std::vector<ObservationPose>> shared_poses(const StageInput& poses) {
  return read_shared<std::vector<ObservationPose>>(poses, &SharedReads::poses, "poses.json", [&] {
    return poses_from_text(*open_file_stream(poses.artifact.path("poses.json")));
  });
}

std::string overlay_file(const std::string& sensor, const std::string& observation) {
  return sensor + "/overlay/" + observation + ".jpg";
}

bool is_overlay_file(std::string_view path) {
  const std::string_view folder = "/overlay/", extension = ".jpg";
  const size_t at = path.find('/');
  return at != std::string_view::npos && path.substr(at, folder.size()) == folder &&
         path.size() >= at + folder.size() + extension.size() &&
         path.substr(path.size() - extension.size()) == extension;
}

Recording load_recording(const StageInput& source) { return *shared_recording(source); }

Calibration load_calibration(const StageInput& calibrate) {
  Calibration c;
  const auto j = nlohmann::json::parse(read_file(calibrate.artifact.path("calibration.json")));
  for (const auto& [sensor, value] : j.items()) c[sensor] = calibration_from_json(value);
  return c;
}

void check_poses_match(const Recording& recording, const std::vector<ObservationPose>& poses,
                       const std::string& stage) {
  bool match = poses.size() == recording.observations.size();
  for (size_t i = 0; match && i < poses.size(); ++i) match = poses[i].observation == recording.observations[i].id;
  if (!match)
    throw std::runtime_error("stage '" + stage +
                             "': its poses do not belong to the recording it reads; name the "
                             "poses stage of that recording in needs");
}

std::vector<Box> load_boxes(const StageInput& annotations) {
  // Written by the annotations stage from boxes it validated: read as trusted.
  return read_native_annotations(read_file(annotations.artifact.path("boxes.json")));
}

}  // namespace olt
