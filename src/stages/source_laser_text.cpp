// `source` format laser_text: laser scans and odometry as text (formats/laser_text.h), left where
// they are.
#include "olt/formats/laser_text.h"
#include "olt/model/recording.h"
#include "source_formats.h"

namespace olt::source {
namespace {

struct LaserText {
  std::vector<LaserScan> scans;
  std::vector<OdometrySample> odometry;
};

LaserText read_laser_text(const SourceConfig& c) {
  LaserText t;
  t.scans = parse_laser_scans(c.scans, read_file(c.scans));
  if (t.scans.empty()) throw InputError(c.scans, "holds no scans");
  if (!c.odometry.empty()) t.odometry = parse_odometry(c.odometry, read_file(c.odometry));
  return t;
}

}  // namespace

std::vector<fs::path> laser_text_files(const SourceConfig& c) {
  read_laser_text(c);
  std::vector<fs::path> files = {c.scans};
  if (!c.odometry.empty()) files.push_back(c.odometry);
  return files;
}

// A laser-only recording: the scans and odometry stay where they are.
nlohmann::json run_laser_text(const StageContext& /*ctx*/, ArtifactWriter& out, const SourceConfig& c) {
  const LaserText t = read_laser_text(c);
  Recording r;
  r.laser_scans = fs::absolute(c.scans).string();
  if (!c.odometry.empty()) r.odometry = fs::absolute(c.odometry).string();
  write_recording(out, r);
  return {{"observations", 0}, {"laser_scans", t.scans.size()}, {"odometry_samples", t.odometry.size()}};
}

}  // namespace olt::source
