#pragma once
// One frame of the `propagate` stage: what its files are computed from (FrameInputs, and as digests
// the record whose hash is its cache key), and the labeling of the frame into a cache entry of its
// own: class.png, instance.png, masks.json (the instances' COCO masks, for the export), frame.json
// [, class_color.png, instance_color.png: where the colour camera is not the depth camera; where it is,
// the colour labels are class.png and instance.png] [, overlay.jpg] [, cloud.pcd | cloud.ply].
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "box_checks.h"
#include "olt/config/params.h"
#include "olt/formats/coco.h"
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

/// What frames' records share, made once per run of the stage rather than once per frame: each box's
/// entry (`"id":"digest"`), each sensor's calibration digest, and the parameters' values, as the
/// record writes them.
struct RecordParts {
  std::vector<std::string> boxes;                                   ///< by position in the priority order
  std::vector<uint32_t> box_ranks;                                  ///< ... the place of its id among the ids, sorted
  std::map<std::string, std::string> calibrations;                  ///< by sensor
  std::string color_labels, frame_version, overlays, point_clouds;  ///< the parameters, as the record writes them
  bool color = false;                                               ///< whether the colour image is an input
};
RecordParts record_parts(const std::vector<LabeledBox>& ordered, const Calibration& calibration, const LabelMap& map,
                         const PropagateConfig& c);
/// A pose as a frame's record names it: the digest of its JSON.
std::string pose_digest(const ObservationPose& pose);

/// What a frame's files are computed from, as digests: the frame's record as a unit (its hash is the
/// frame's cache key; `olt plan` compares it with the previous run's to say why a frame is labeled
/// again), as nlohmann's compact dump writes it (keys sorted), made as text: building and dumping the
/// JSON was 5 % of a watch cycle at 10,000 observations. `in_view`: the positions in the priority order
/// of the boxes in its view.
std::string frame_inputs_record(const Observation& o, const std::string& pose_sha256,
                                const std::vector<uint32_t>& in_view, const RecordParts& parts);

/// A frame as labeled: what from (its record), the boxes in its view (in priority order), its labels
/// and counts, its colour labels where the colour camera is not the depth camera, its instances'
/// masks, and its files' bytes (class.png, instance.png, masks.json[, the colour ones][, overlay.jpg]). `olt watch`
/// keeps it in memory, and the next edit relabels the frame from it.
struct LabeledFrame {
  nlohmann::json record;
  std::vector<LabeledBox> boxes;
  FrameLabels labels;
  ColorLabels color;
  FrameMasks masks;  ///< its instances' COCO masks (masks.json)
  std::map<std::string, std::string> files;
  std::map<std::string, std::vector<uint32_t>> png_band_sums;  ///< of its label PNGs (LabelPng), by file
  bool in_place = false;                                       ///< relabeled in place, from the frame as labeled before
};

/// The bytes a labeled frame holds, as kept in memory.
size_t bytes_of(const LabeledFrame& frame);

/// True when a frame labeled from `before` can be labeled again from it: only its boxes changed.
bool only_boxes_changed(const nlohmann::json& before, const nlohmann::json& now);

/// The frame's record (frame.json, without its last newline): what it labeled, box by box, with the
/// rectangles of its instances (in depth, and in colour where `color`) and of each box's own pixels,
/// and its pose's quality; as nlohmann's dump(1) writes the document (keys sorted).
std::string frame_record_text(const FrameInputs& f, const FrameLabels& labels, const FrameMasks& masks,
                              const ColorLabels* color);

/// The counts frame_counts reads from the frame's record (frame.json), taken from its labels: the
/// frame's pixels, and each box in view whose footprint covers a pixel, by its place in `positions`
/// (the record lists those). A frame labeled in this process is counted without its record parsed.
FrameCounts frame_counts_of(const FrameInputs& f, const FrameLabels& labels,
                            const std::map<std::string, uint32_t>& positions);

/// Labels one frame into its cache entry. With `previous` (the same frame labeled before, only its
/// boxes changed since), only the pixels the changed boxes reach are labeled again (where that is
/// less work), and its images are encoded again only in the strips where they changed (the same
/// bytes either way: olt/core/image_strips.h). Decoding the previous labels from PNG takes longer than labeling
/// afresh, so they come from memory only. `label_over_previous`: the caller holds the only reference
/// to `previous` and lets go of it after, so its label images may be labeled over (left undefined).
LabeledFrame label_frame(const FrameInputs& f, const nlohmann::json& record, const PropagateConfig& c,
                         const LabelMap& map, const LabeledFrame* previous, bool label_over_previous,
                         ArtifactWriter& out);

}  // namespace olt
