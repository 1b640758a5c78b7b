#pragma once
// Agreement of two labelings of the same frames: the original Object Labeling Toolkit's Benchmark
// (one recording labeled twice, e.g. with poses from motion capture and from registration), with
// pixel metrics over 16-bit class-id images at depth resolution:
//   IoU of class c  = |A = c and B = c| / |A = c or B = c|
//   mean IoU        = mean of the IoUs of the classes present in A or B
//   agreement       = |labeled in A or B, and A = B| / |labeled in A or B|
// A pixel is labeled when it is neither the unlabeled nor the no-depth value. Every figure counts
// only pixels with depth on both sides (neither is no-depth): a pixel without depth cannot be
// labeled, so a difference there is one of depth, not of labeling (counted as depth_differs).
// Classes are matched by name, so outputs whose labels.json number the classes differently compare
// correctly; an id that labels.json does not name is matched by its number.
#include <cstdint>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace olt {

/// How one side's class-id images read (its labels.json).
struct ClassCoding {
  std::map<uint16_t, std::string> names;  ///< class id -> class name; ids not listed are named "id N"
  uint16_t unlabeled = 0;                 ///< value of a pixel with depth in no object
  uint16_t no_depth = 65535;              ///< value of a pixel without depth
};

/// Pixels of one class (with depth on both sides).
struct ClassPixels {
  int64_t in_a = 0;  ///< pixels of the class in A
  int64_t in_b = 0;  ///< pixels of the class in B
  int64_t both = 0;  ///< pixels of the class in A and in B (the intersection)
  int64_t union_pixels() const { return in_a + in_b - both; }
  double iou() const;  ///< both / union; 0 when the class has no pixel
};

/// The comparison of one frame's two class-id images.
struct FrameComparison {
  std::map<std::string, ClassPixels> classes;  ///< by class name: every class present in A or B
  int64_t labeled = 0;                         ///< pixels labeled in A or in B
  int64_t agreeing = 0;                        ///< of those, pixels of the same class in A and B
  int64_t depth_differs = 0;                   ///< pixels with depth on one side only (left out of every figure)
  double agreement() const;                    ///< agreeing / labeled; 1 when neither side labels a pixel
};

/// Compares two class-id images (CV_16UC1) of one frame. Throws std::invalid_argument when an image
/// is of another type or the sizes differ (the caller names the files).
FrameComparison compare_labels(const cv::Mat& a, const cv::Mat& b, const ClassCoding& coding_a,
                               const ClassCoding& coding_b);

struct ClassAgreement {
  std::string name;
  ClassPixels pixels;  ///< summed over the frames
  double iou = 0;
};

/// The figures over all frames compared.
struct LabelAgreement {
  std::vector<ClassAgreement> classes;                   ///< every class present in A or B, by name
  double mean_iou = 0;                                   ///< mean over `classes`; 0 when there is none
  int64_t labeled = 0, agreeing = 0, depth_differs = 0;  ///< pixels, summed over the frames
  double agreement = 1;                                  ///< agreeing / labeled; 1 when nothing is labeled
  std::vector<double> frame_agreement;                   ///< per frame, in the order given
  double min_frame_agreement = 1;                        ///< 1 when there is no frame
  double median_frame_agreement = 1;                     ///< 1 when there is no frame
};

LabelAgreement summarize_agreement(const std::vector<FrameComparison>& frames);

/// Indices of the `n` frames of least agreement, least first (equal ones in the order given).
std::vector<size_t> worst_frames(const LabelAgreement& summary, size_t n);

}  // namespace olt
