#pragma once
// One frame of the `propagate` stage: what its files are computed from (FrameInputs, and as digests
// the record whose hash is its cache key), and the labeling of the frame into a cache entry of its
// own: class.png, instance.png, masks.json (the instances' COCO masks, for the export), frame.json
// [, class_color.png, instance_color.png: where the colour camera is not the depth camera; where it is,
// the colour labels are class.png and instance.png] [, overlay.jpg] [, cloud.pcd | cloud.ply].
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "olt/config/params.h"
#include "olt/propagate/label_map.h"
#include "olt/propagate/propagate.h"
#include "olt/stages/stage.h"

namespace olt {

enum class CloudFiles { none, pcd, ply };
/// Their names in jobs, which are also the files' extensions.
const Names<CloudFiles>& cloud_file_names();
std::string name_of(CloudFiles files);

struct PropagateConfig {
  std::map<std::string, int> class_ids;  ///< fixed class ids by name (1..65534); others follow alphabetically
  bool overlays = true;                  ///< write an overlay JPEG per observation
  bool color_labels = true;              ///< also write class and instance images at colour resolution
  int color_fill_px = 2;                 ///< colour pixels no depth point reaches: fill from this far (0 = no_depth)
  double color_fill_tolerance_m = 0.05;  ///< ... from neighbours this close to the front surface
  CloudFiles point_clouds = CloudFiles::none;  ///< a labeled point cloud per observation, and its format
  bool keep_flagged = false;                   ///< also label observations whose pose is flagged
};

// Everything one frame's files are computed from.
struct FrameInputs {
  const Observation& observation;
  const ObservationPose& pose;
  const SensorCalibration& calibration;
  const DepthView& view;
  std::vector<LabeledBox> boxes;  ///< the boxes in view, in priority order
};

/// The digests frames' records share (a box's, a sensor's calibration), computed once per job rather
/// than once per frame that names them.
struct SharedDigests {
  std::vector<std::string> boxes;                   ///< by position in the priority order
  std::map<std::string, std::string> calibrations;  ///< by sensor
};
SharedDigests shared_digests(const std::vector<LabeledBox>& ordered, const Calibration& calibration,
                             const LabelMap& map);

/// What a frame's files are computed from, as digests: the frame's record as a unit (its hash is the
/// frame's cache key; `olt plan` compares it with the previous run's to say why a frame is labeled
/// again). `in_view`: the positions in the priority order of the boxes in its view.
nlohmann::json frame_inputs_record(const Observation& o, const ObservationPose& pose,
                                   const std::vector<uint32_t>& in_view, const std::vector<LabeledBox>& ordered,
                                   const SharedDigests& digests, const PropagateConfig& c);

/// The boxes frames' records name, by digest, exactly (their labeling part's pose as a matrix, not
/// the quaternion the digest is of): the next run reads them to know the boxes a frame saw before.
std::string box_table_text(const std::vector<LabeledBox>& ordered, const SharedDigests& digests);
/// Throws on text that is not a box table.
std::map<std::string, LabeledBox> read_box_table(const std::string& text);

/// A frame as the previous run labeled it: the boxes in its view then (in priority order), its
/// labels and counts, and its entry, whose files are kept where the labels come out the same.
struct PreviousFrame {
  std::vector<LabeledBox> boxes;
  FrameLabels labels;
  Artifact entry;
};

/// The frame's previous labels: its class and instance images as this process made them (kept in
/// memory: decoding them from the entry's PNGs takes longer than labeling afresh), its counts from
/// the entry's frame.json (checked against the digest the entry lists); none when they cannot serve.
std::optional<PreviousFrame> read_previous_frame(const Artifact& entry, std::vector<LabeledBox> boxes,
                                                 const cv::Mat& class_ids, const cv::Mat& instance_ids,
                                                 const Intrinsics& depth_camera);

/// A frame's labels, and whether they were made from its previous ones.
struct FrameLabeled {
  FrameLabels labels;
  bool from_previous = false;
};

/// Labels one frame into its cache entry; with `previous`, only the pixels the changed boxes reach
/// are labeled again (where that is less work), and files that come out the same are copied from
/// the previous entry rather than encoded again (the same bytes either way).
FrameLabeled label_frame(const FrameInputs& f, const PropagateConfig& c, const LabelMap& map,
                         const PreviousFrame* previous, ArtifactWriter& out);

}  // namespace olt
