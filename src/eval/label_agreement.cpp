#include "olt/eval/label_agreement.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace olt {
namespace {

std::string size_text(const cv::Mat& m) { return std::to_string(m.cols) + "x" + std::to_string(m.rows); }

// Pixels per (id in A, id in B) pair, key = a << 16 | b. Label images are long runs of one id, so
// the loop extends a run with one comparison per pixel and touches the map once per run; class
// names are then looked up once per pair instead of once per pixel.
std::map<uint32_t, int64_t> count_id_pairs(const cv::Mat& a, const cv::Mat& b) {
  std::map<uint32_t, int64_t> pairs;
  for (int r = 0; r < a.rows; ++r) {
    const uint16_t* pa = a.ptr<uint16_t>(r);
    const uint16_t* pb = b.ptr<uint16_t>(r);
    for (int c = 0; c < a.cols;) {
      int end = c + 1;
      while (end < a.cols && pa[end] == pa[c] && pb[end] == pb[c]) ++end;
      pairs[static_cast<uint32_t>(pa[c]) << 16 | pb[c]] += end - c;
      c = end;
    }
  }
  return pairs;
}

// The class name of a labeled id ("" is never returned: an unnamed id is "id N").
std::string class_name(const ClassCoding& coding, uint16_t id) {
  const auto it = coding.names.find(id);
  return it != coding.names.end() ? it->second : "id " + std::to_string(id);
}

}  // namespace

double ClassPixels::iou() const {
  const int64_t u = union_pixels();
  return u > 0 ? static_cast<double>(both) / u : 0.0;
}

double FrameComparison::agreement() const { return labeled > 0 ? static_cast<double>(agreeing) / labeled : 1.0; }

FrameComparison compare_labels(const cv::Mat& a, const cv::Mat& b, const ClassCoding& coding_a,
                               const ClassCoding& coding_b) {
  if (a.type() != CV_16UC1 || b.type() != CV_16UC1)
    throw std::invalid_argument("class-id images must be 16-bit single-channel");
  if (a.size() != b.size())
    throw std::invalid_argument("images of different sizes, " + size_text(a) + " and " + size_text(b));
  FrameComparison f;
  for (const auto& [pair, pixels] : count_id_pairs(a, b)) {
    const auto id_a = static_cast<uint16_t>(pair >> 16), id_b = static_cast<uint16_t>(pair & 0xffff);
    const bool depth_a = id_a != coding_a.no_depth, depth_b = id_b != coding_b.no_depth;
    if (!depth_a || !depth_b) {
      if (depth_a != depth_b) f.depth_differs += pixels;
      continue;
    }
    const bool labeled_a = id_a != coding_a.unlabeled, labeled_b = id_b != coding_b.unlabeled;
    if (!labeled_a && !labeled_b) continue;
    const std::string name_a = labeled_a ? class_name(coding_a, id_a) : "";
    const std::string name_b = labeled_b ? class_name(coding_b, id_b) : "";
    f.labeled += pixels;
    if (labeled_a) f.classes[name_a].in_a += pixels;
    if (labeled_b) f.classes[name_b].in_b += pixels;
    if (labeled_a && labeled_b && name_a == name_b) {
      f.classes[name_a].both += pixels;
      f.agreeing += pixels;
    }
  }
  return f;
}

LabelAgreement summarize_agreement(const std::vector<FrameComparison>& frames) {
  LabelAgreement s;
  std::map<std::string, ClassPixels> classes;
  for (const auto& f : frames) {
    for (const auto& [name, p] : f.classes) {
      ClassPixels& sum = classes[name];
      sum.in_a += p.in_a;
      sum.in_b += p.in_b;
      sum.both += p.both;
    }
    s.labeled += f.labeled;
    s.agreeing += f.agreeing;
    s.depth_differs += f.depth_differs;
    s.frame_agreement.push_back(f.agreement());
  }
  for (const auto& [name, p] : classes) s.classes.push_back({name, p, p.iou()});
  double iou_sum = 0;
  for (const auto& c : s.classes) iou_sum += c.iou;
  if (!s.classes.empty()) s.mean_iou = iou_sum / s.classes.size();
  if (s.labeled > 0) s.agreement = static_cast<double>(s.agreeing) / s.labeled;
  std::vector<double> sorted = s.frame_agreement;
  std::sort(sorted.begin(), sorted.end());
  if (!sorted.empty()) {
    const size_t n = sorted.size();
    s.min_frame_agreement = sorted.front();
    s.median_frame_agreement = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  }
  return s;
}

std::vector<size_t> worst_frames(const LabelAgreement& summary, size_t n) {
  std::vector<size_t> order(summary.frame_agreement.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t i, size_t j) { return summary.frame_agreement[i] < summary.frame_agreement[j]; });
  order.resize(std::min(n, order.size()));
  return order;
}

}  // namespace olt
