// `source` format tum: the TUM RGB-D layout (rgb.txt, depth.txt, groundtruth.txt); images stay
// where they are, identified by content hash.
#include <chrono>
#include <map>
#include <optional>

#include "olt/core/file_system.h"
#include "olt/core/hash.h"
#include "olt/core/image.h"
#include "olt/core/parallel.h"
#include "olt/core/process_memory.h"
#include "olt/core/progress.h"
#include "olt/formats/tum.h"
#include "olt/model/recording.h"
#include "olt/source/associate.h"
#include "source_formats.h"

namespace olt::source {
namespace {

struct TumLists {
  std::vector<TumListEntry> depth, color;
};

// An image's header with the file it was read from, as it was then.
struct KeptHeader {
  FileStat file;
  ImageHeader header;
};

// The header of `file`; in a process that keeps memory (`olt watch` loads the job, and checks the
// images, every cycle), the one read before where the file is the same (inode, size and time): a
// stat, not an open and a read (20,000 of them a cycle at 10,000 frames). A file whose time was within
// 2 s of the read, or after it, is read again: a file system that keeps times in seconds could see it
// written again, to the same size, in the same second. (Not guarded against: a network file server
// whose clock is behind this machine's by more than that, or a client that caches what a stat says.)
ImageHeader remembered_image_header(const fs::path& file) {
  if (!keeping_memory()) return read_image_header(file);
  const std::string name = "image header " + file.string();
  const FileStat before_read = real_file_system().stat(file, /*follow_link=*/true);  // never newer than the read
  if (const auto kept = remembered<KeptHeader>(name); kept && kept->file.same_file(before_read)) return kept->header;
  ImageHeader header = read_image_header(file);
  const int64_t read_at =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  if (read_at - before_read.mtime_ns >= int64_t{2'000'000'000})
    remember<KeptHeader>(name, std::make_shared<const KeptHeader>(KeptHeader{before_read, header}),
                         sizeof(KeptHeader) + header.format.size());
  return header;
}

TumLists read_tum_lists(const fs::path& dir) {
  const fs::path depth = dir / "depth.txt", color = dir / "rgb.txt";
  return {parse_tum_list(depth.string(), read_file(depth)), parse_tum_list(color.string(), read_file(color))};
}

}  // namespace

std::vector<fs::path> tum_files(const SourceConfig& c) {
  const fs::path dir = c.path;
  const TumLists lists = read_tum_lists(dir);
  std::vector<fs::path> files = {dir / "depth.txt", dir / "rgb.txt"};
  for (const auto& e : lists.depth) files.push_back(resolve_path(dir, e.file));
  for (const auto& e : lists.color) files.push_back(resolve_path(dir, e.file));
  return files;
}

nlohmann::json run_tum(const StageContext& ctx, ArtifactWriter& out, const SourceConfig& c) {
  const fs::path dir = c.path;
  const TumLists lists = read_tum_lists(dir);
  if (lists.depth.empty()) throw InputError((dir / "depth.txt").string(), "lists no depth images");
  std::vector<double> depth_times, color_times;
  for (const auto& e : lists.depth) depth_times.push_back(e.timestamp);
  for (const auto& e : lists.color) color_times.push_back(e.timestamp);
  const auto pairs = associate_nearest(depth_times, color_times, c.max_color_dt_s);

  Recording r;
  SensorInfo sensor;
  sensor.id = c.sensor;
  // TUM's format stores depth in units of 1/5000 m: the default unless the job's calibrate stage
  // says otherwise (a preset or depth_scale); no intrinsics (fx 0: unknown).
  sensor.calibration = SensorCalibration{};
  sensor.calibration->depth_scale = kTumDepthScale;
  image_size(resolve_path(dir, lists.depth.front().file), &sensor.depth_width, &sensor.depth_height);
  int unpaired = 0;
  Progress hashed("observations read", lists.depth.size());  // their images hashed (once: memoized)
  for (size_t i = 0; i < lists.depth.size(); ++i) {
    hashed.advance();
    const fs::path depth = resolve_path(dir, lists.depth[i].file);
    Observation o;
    o.id = fs::path(lists.depth[i].file).stem().string();
    o.sensor = c.sensor;
    o.timestamp = lists.depth[i].timestamp;
    o.depth = {depth.string(), Digest(ctx.digest_file(depth))};
    if (pairs[i]) {
      const fs::path color = resolve_path(dir, lists.color[*pairs[i]].file);
      o.color = ImageFile{color.string(), Digest(ctx.digest_file(color))};
      o.color_dt_s = lists.color[*pairs[i]].timestamp - o.timestamp;
      if (sensor.color_width == 0) image_size(color, &sensor.color_width, &sensor.color_height);
    } else {
      ++unpaired;
    }
    r.observations.push_back(o);
  }
  r.sensors.push_back(sensor);
  r.root = dir.string();
  const fs::path groundtruth = dir / "groundtruth.txt";
  if (fs::exists(groundtruth)) r.groundtruth = groundtruth.string();
  write_recording(out, r);
  return {{"observations", r.observations.size()}, {"without_color", unpaired}};
}

void check_tum_images(const fs::path& dir, std::vector<Diagnostic>& errors) {
  TumLists lists;
  try {
    lists = read_tum_lists(dir);
  } catch (const InputError& e) {
    errors.insert(errors.end(), e.diagnostics().begin(), e.diagnostics().end());
    return;
  }
  if (lists.depth.empty()) {
    errors.push_back({(dir / "depth.txt").string(), 0, 0, "lists no depth images"});
    return;
  }
  // Observation ids are the depth images' names without extension: they name output files and cache
  // entries, so two images of one name (in two folders, or one listed twice) would overwrite each other.
  std::map<std::string, int> line_of_id;
  for (const auto& e : lists.depth) {
    const auto [at, fresh] = line_of_id.emplace(fs::path(e.file).stem().string(), e.line);
    if (!fresh)
      errors.push_back({(dir / "depth.txt").string(), e.line, 1,
                        "depth image " + e.file + ": its observation id '" + at->first + "' (the file name without " +
                            "extension) is line " + std::to_string(at->second) +
                            "'s too; ids name output files, so each depth image needs a name of its own"});
  }
  for (const bool depth : {true, false}) {
    std::vector<LineProblem> problems;
    std::optional<ImageHeader> first;
    const auto& entries = depth ? lists.depth : lists.color;
    // Every header read in parallel (a file each: `olt watch` loads the job every cycle), then checked
    // in the list's order.
    std::vector<ImageHeader> headers(entries.size());
    std::vector<std::optional<std::string>> unreadable(entries.size());  // why a header was not read
    parallel_for(entries.size(), [&](size_t i) {
      try {
        headers[i] = remembered_image_header(resolve_path(dir, entries[i].file));
      } catch (const InputError& error) {
        unreadable[i] = error.diagnostics().front().message;
      }
    });
    for (size_t i = 0; i < entries.size(); ++i) {
      const auto& e = entries[i];
      const auto problem = [&](const std::string& what) {
        problems.push_back({e.line, (depth ? "depth image " : "colour image ") + e.file, what});
      };
      if (unreadable[i]) {
        problem(*unreadable[i]);
        continue;
      }
      const ImageHeader& header = headers[i];
      if (depth && !header.grey16())
        problem("expected a 16-bit single-channel image (PNG or TIFF; depth in units of depth_scale), found " +
                header.describe());
      if (!first) {
        first = header;
      } else if (header.width != first->width || header.height != first->height) {
        problem("is " + std::to_string(header.width) + "x" + std::to_string(header.height) + ", the list's first is " +
                std::to_string(first->width) + "x" + std::to_string(first->height));
      }
    }
    add_folded((dir / (depth ? "depth.txt" : "rgb.txt")).string(), problems, depth ? "depth images" : "colour images",
               errors);
  }
}

}  // namespace olt::source
