#pragma once
// The `source` stage's formats, one file each (src/stages/source_<format>.cpp); source_stage.cpp
// holds the parameters, validation and dispatch.
#include <string>
#include <vector>

#include "olt/config/params.h"
#include "olt/core/error.h"
#include "olt/core/fs.h"
#include "olt/model/recording.h"
#include "olt/stages/stage.h"

namespace olt::source {

enum class SourceFormat { tum, synthetic, laser_text, rawlog, plain_text };
/// Their names in jobs.
const Names<SourceFormat>& source_format_names();
std::string name_of(SourceFormat format);

struct SourceConfig {
  SourceFormat format = SourceFormat::tum;  ///< the recording's layout
  std::string path;              ///< tum: the dataset folder holding rgb.txt and depth.txt; rawlog: the file;
                                 ///< plain_text: the sequence file
  std::string observations;      ///< plain_text: the folder of the observation files (default: the sequence
                                 ///< file's path without its extension)
  std::string laser_sensor;      ///< rawlog: the laser whose scans are used (sensorLabel; default: the first)
  std::string scans;             ///< laser_text: the scans file
  std::string odometry;          ///< laser_text: the odometry file (optional)
  std::string sensor = "rgbd";   ///< id given to the recording's RGB-D camera
  double max_color_dt_s = 0.02;  ///< tum: largest depth-colour time difference of a pair, seconds
  int frames = 30;               ///< synthetic: number of observations
  int width = 640;               ///< synthetic: image width, pixels
  int height = 480;              ///< synthetic: image height, pixels
  double rate_hz = 10;           ///< synthetic: observations per second (per camera)
  int cameras = 0;               ///< synthetic: 0 = hand-held camera; 1..4 = a robot with a laser and this many cameras
  int seed = 1;                  ///< synthetic robot: noise and odometry drift
  double color_dt_s = 0;         ///< synthetic: colour taken this long after depth, alternating sign, seconds
  double tilt_deg = 0;           ///< synthetic hand-held: the truth's frame tilted from gravity, degrees
};

/// TUM RGB-D's depth units per metre.
inline constexpr double kTumDepthScale = 5000;

/// The recording's index, recording.json, written an observation at a time.
void write_recording(ArtifactWriter& out, const Recording& r);

/// Ids name output folders and files (labels/<sensor>/..., <id>.png): nothing that could leave them.
bool safe_id(const std::string& id);
void image_size(const fs::path& file, int* width, int* height);

/// A problem of one line of a list file (`subject`: what the line names, e.g. "colour image rgb/1.jpg").
struct LineProblem {
  int line = 0;
  std::string subject, problem;
};
/// The problems of `list` as diagnostics, repeats folded: of each problem (the same words) the first
/// three as they are, then one "... and N more <plural> with this problem (lines A to B): <problem>"
/// at the fourth's line, so 250 frames of one mistake give four lines, not 250.
void add_folded(const std::string& list, const std::vector<LineProblem>& problems, const std::string& plural,
                std::vector<Diagnostic>& errors);
/// Observations in time order; those of one moment by sensor id (stable otherwise).
void sort_by_time(std::vector<Observation>& observations);

// Per format: the input files (parsed, so bad input is found before anything runs) and the run.
std::vector<fs::path> tum_files(const SourceConfig& c);
/// Every listed image exists, is a PNG of a readable size, depth 16-bit grey, and each list's images
/// share one size: found before anything runs, at the list's line.
void check_tum_images(const fs::path& dir, std::vector<Diagnostic>& errors);
nlohmann::json run_tum(const StageContext& ctx, ArtifactWriter& out, const SourceConfig& c);
nlohmann::json run_synthetic(const StageContext& ctx, ArtifactWriter& out, const SourceConfig& c);
nlohmann::json run_rawlog(const StageContext& ctx, ArtifactWriter& out, const SourceConfig& c);
std::vector<fs::path> plain_text_files(const SourceConfig& c);
nlohmann::json run_plain_text(const StageContext& ctx, ArtifactWriter& out, const SourceConfig& c);
std::vector<fs::path> laser_text_files(const SourceConfig& c);
nlohmann::json run_laser_text(const StageContext& ctx, ArtifactWriter& out, const SourceConfig& c);

}  // namespace olt::source
