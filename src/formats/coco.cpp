#include "olt/formats/coco.h"

#include <algorithm>
#include <climits>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <optional>

#include "olt/core/error.h"
#include "olt/core/image_strips.h"

namespace olt {

std::vector<uint32_t> mask_runs(const cv::Mat& mask) {
  std::vector<uint32_t> runs;
  bool inside = false;
  uint32_t count = 0;
  for (int u = 0; u < mask.cols; ++u) {
    for (int v = 0; v < mask.rows; ++v) {
      const bool here = mask.at<uint8_t>(v, u) != 0;
      if (here != inside) {
        runs.push_back(count);
        count = 0;
        inside = here;
      }
      ++count;
    }
  }
  runs.push_back(count);
  return runs;
}

namespace {

// The masks of the values `slot` says (-1: wanted, -2: not) of a label image, all of whose pixels
// lie in columns [u_first, u_last]: those columns scanned alone, the runs as the whole image's.
std::map<uint16_t, ValueMask> masks_in_columns(const cv::Mat& labels, std::vector<int> slot, int u_first, int u_last) {
  struct Growing {
    ValueMask mask;
    uint32_t end = 0;  // column-major index after the value's last pixel so far
    int u0 = INT32_MAX, v0 = INT32_MAX, u1 = -1, v1 = -1;
  };
  // `slot`: per value, its place in `growing` once seen: a table rather than a map, since this runs
  // for every pixel.
  std::vector<std::pair<uint16_t, Growing>> growing;
  cv::Mat columns;
  if (u_first > u_last) return {};
  cv::transpose(labels.colRange(u_first, u_last + 1), columns);  // row u of `columns`: column u_first + u
  const uint32_t height = static_cast<uint32_t>(labels.rows);
  for (int u = u_first; u <= u_last; ++u) {
    const uint16_t* column = columns.ptr<uint16_t>(u - u_first);
    for (int v = 0; v < columns.cols;) {  // run by run down the column
      const uint16_t value = column[v];
      const int first = v;
      while (v < columns.cols && column[v] == value) ++v;
      const uint32_t length = static_cast<uint32_t>(v - first);
      int& s = slot[value];
      if (s == -2) continue;
      if (s == -1) {
        s = static_cast<int>(growing.size());
        growing.emplace_back(value, Growing{});
      }
      Growing& g = growing[static_cast<size_t>(s)].second;
      const uint32_t index = static_cast<uint32_t>(u) * height + static_cast<uint32_t>(first);
      if (!g.mask.runs.empty() && g.end == index) {
        g.mask.runs.back() += length;
      } else {
        g.mask.runs.push_back(index - g.end);  // the background since the last run
        g.mask.runs.push_back(length);
      }
      g.end = index + length;
      g.mask.area += length;
      g.u0 = std::min(g.u0, u), g.u1 = std::max(g.u1, u);
      g.v0 = std::min(g.v0, first), g.v1 = std::max(g.v1, v - 1);
    }
  }
  std::map<uint16_t, ValueMask> out;
  const uint32_t total = height * static_cast<uint32_t>(labels.cols);
  for (auto& [value, g] : growing) {
    g.mask.runs.push_back(total - g.end);
    if (g.mask.runs.back() == 0) g.mask.runs.pop_back();
    g.mask.bbox = cv::Rect(g.u0, g.v0, g.u1 - g.u0 + 1, g.v1 - g.v0 + 1);
    out[value] = std::move(g.mask);
  }
  return out;
}

// The runs of a compressed COCO string (coco_rle_string's inverse) of an image of `total` pixels; none
// where it is not one.
std::optional<std::vector<uint32_t>> rle_runs(const std::string& text, uint64_t total) {
  std::vector<uint32_t> runs;
  uint64_t sum = 0;
  for (size_t at = 0; at < text.size();) {
    int64_t x = 0;
    for (int k = 0;; ++k) {
      // Seven groups of 5 bits hold any difference of two 32-bit runs, and its sign: no more.
      if (at == text.size() || k > 6) return std::nullopt;
      const int c = text[at++] - 48;
      if (c < 0 || c > 63) return std::nullopt;
      x |= static_cast<int64_t>(c & 0x1f) << (5 * k);
      if (c & 0x20) continue;
      if (c & 0x10) x |= -(int64_t{1} << (5 * (k + 1)));  // negative: the sign bit extended
      break;
    }
    if (runs.size() > 2) x += runs[runs.size() - 2];
    if (x < 0 || x > UINT32_MAX) return std::nullopt;
    runs.push_back(static_cast<uint32_t>(x));
    sum += static_cast<uint64_t>(x);
  }
  if (sum != total) return std::nullopt;
  return runs;
}

// A mask's pixels as column-major index ranges [from, to), in order, from its runs.
using Spans = std::vector<std::pair<uint32_t, uint32_t>>;

void add_spans(const std::vector<uint32_t>& runs, uint32_t from, uint32_t to, Spans& out) {
  uint32_t at = 0;
  for (size_t i = 0; i < runs.size() && at < to; ++i) {
    const uint32_t end = at + runs[i];
    if (i % 2 == 1 && std::max(at, from) < std::min(end, to)) {
      const std::pair<uint32_t, uint32_t> span{std::max(at, from), std::min(end, to)};
      if (!out.empty() && out.back().second == span.first)
        out.back().second = span.second;  // one run across the cut
      else
        out.push_back(span);
    }
    at = end;
  }
}

// The mask of index spans `spans` in an image of `size`: runs (from the background), area, rectangle.
ValueMask mask_of_spans(const Spans& spans, cv::Size size) {
  const uint32_t height = static_cast<uint32_t>(size.height);
  ValueMask mask;
  uint32_t end = 0;
  int u0 = INT32_MAX, v0 = INT32_MAX, u1 = -1, v1 = -1;
  for (const auto& [from, to] : spans) {
    mask.runs.push_back(from - end);
    mask.runs.push_back(to - from);
    mask.area += to - from;
    end = to;
    const int first_u = static_cast<int>(from / height), last_u = static_cast<int>((to - 1) / height);
    u0 = std::min(u0, first_u), u1 = std::max(u1, last_u);
    if (first_u == last_u) {
      v0 = std::min(v0, static_cast<int>(from % height)), v1 = std::max(v1, static_cast<int>((to - 1) % height));
    } else {  // down to a column's foot and on from the next one's head
      v0 = 0, v1 = size.height - 1;
    }
  }
  const uint32_t total = height * static_cast<uint32_t>(size.width);
  if (total > end) mask.runs.push_back(total - end);
  if (u1 >= 0) mask.bbox = cv::Rect(u0, v0, u1 - u0 + 1, v1 - v0 + 1);
  return mask;
}

// The columns [first, last] holding a pixel that differs between the images, in the rows flagged.
std::pair<int, int> differing_columns(const cv::Mat& a, const cv::Mat& b, const std::vector<bool>& rows) {
  int first = a.cols, last = -1;
  for (int v = 0; v < a.rows; ++v) {
    if (!rows[static_cast<size_t>(v)]) continue;
    const uint16_t *x = a.ptr<uint16_t>(v), *y = b.ptr<uint16_t>(v);
    int u = 0;
    while (u < first && x[u] == y[u]) ++u;
    first = std::min(first, u);
    int w = a.cols - 1;
    while (w > last && x[w] == y[w]) --w;
    last = std::max(last, w);
  }
  return {first, last};
}

// The masks of `values` (each -1 in `slot`, the others -2) where only columns [first, last] of the
// label image differ from the one their masks `before` were found in: those columns scanned, each
// value's runs elsewhere taken from its mask before. None where a mask before does not decode.
std::optional<std::map<uint16_t, ValueMask>> spliced_masks(const cv::Mat& labels, const std::vector<int>& slot,
                                                           const std::vector<uint16_t>& values,
                                                           const std::map<uint16_t, CocoMask>& before, int first,
                                                           int last) {
  const uint32_t height = static_cast<uint32_t>(labels.rows);
  const uint32_t cut_from = static_cast<uint32_t>(first) * height, cut_to = static_cast<uint32_t>(last + 1) * height;
  const uint32_t total = height * static_cast<uint32_t>(labels.cols);
  const std::map<uint16_t, ValueMask> inside = masks_in_columns(labels, slot, first, last);
  std::map<uint16_t, ValueMask> out;
  for (const uint16_t value : values) {
    std::vector<uint32_t> runs_before;
    if (const auto it = before.find(value); it != before.end()) {
      std::optional<std::vector<uint32_t>> decoded = rle_runs(it->second.counts, total);
      if (!decoded) return std::nullopt;
      runs_before = std::move(*decoded);
    }
    Spans spans;
    add_spans(runs_before, 0, cut_from, spans);
    if (const auto it = inside.find(value); it != inside.end()) add_spans(it->second.runs, cut_from, cut_to, spans);
    add_spans(runs_before, cut_to, total, spans);
    if (!spans.empty()) out[value] = mask_of_spans(spans, labels.size());
  }
  return out;
}

}  // namespace

std::map<uint16_t, ValueMask> value_masks(const cv::Mat& labels, const std::vector<uint16_t>& skip) {
  std::vector<int> slot(65536, -1);
  for (uint16_t s : skip) slot[s] = -2;
  return masks_in_columns(labels, std::move(slot), 0, labels.cols - 1);
}

std::string coco_rle_string(const std::vector<uint32_t>& runs) {
  std::string text;
  for (size_t i = 0; i < runs.size(); ++i) {
    int64_t x = runs[i];
    if (i > 2) x -= static_cast<int64_t>(runs[i - 2]);
    bool more = true;
    while (more) {
      int64_t c = x & 0x1f;
      x >>= 5;  // arithmetic shift: negative differences end in all ones
      more = (c & 0x10) ? x != -1 : x != 0;
      if (more) c |= 0x20;
      text.push_back(static_cast<char>(c + 48));
    }
  }
  return text;
}

namespace {

CocoMask coco_mask(const ValueMask& mask) { return {coco_rle_string(mask.runs), mask.area, mask.bbox}; }

// Calls `each(value, first, last)` for each run of a row of a label image.
template <class Each>
void for_each_run(const uint16_t* row, int cols, const Each& each) {
  for (int u = 0; u < cols;) {
    const int first = u;
    while (u < cols && row[u] == row[first]) ++u;
    each(row[first], first, u - 1);
  }
}

}  // namespace

FrameMasks frame_masks(const cv::Mat& labels, const std::vector<uint16_t>& skip) {
  FrameMasks out{labels.size(), {}};
  for (const auto& [value, mask] : value_masks(labels, skip)) out.masks[value] = coco_mask(mask);
  return out;
}

FrameMasks frame_masks_changed(const cv::Mat& labels, const std::vector<uint16_t>& skip, const FrameMasks& before,
                               const cv::Mat& before_labels) {
  return frame_masks_changed(labels, skip, before, before_labels, differing_rows(labels, before_labels));
}

FrameMasks frame_masks_changed(const cv::Mat& labels, const std::vector<uint16_t>& skip, const FrameMasks& before,
                               const cv::Mat& before_labels, const std::vector<bool>& changed_rows) {
  if (before_labels.size() != labels.size() || before_labels.type() != labels.type() || before.size != labels.size() ||
      changed_rows.size() != static_cast<size_t>(labels.rows))
    return frame_masks(labels, skip);
  // The values with pixels in a row that differs, and the columns each reaches: where it is in those
  // rows now, and its box before (its other pixels are where they were).
  std::map<uint16_t, std::pair<int, int>> changed;
  const auto reach = [&](uint16_t value, int first, int last) {
    auto [it, fresh] = changed.emplace(value, std::pair<int, int>{first, last});
    if (!fresh) it->second = {std::min(it->second.first, first), std::max(it->second.second, last)};
  };
  for (int v = 0; v < labels.rows; ++v) {
    if (!changed_rows[static_cast<size_t>(v)]) continue;
    for_each_run(labels.ptr<uint16_t>(v), labels.cols, reach);
    for_each_run(before_labels.ptr<uint16_t>(v), labels.cols, [&](uint16_t value, int, int) {
      changed.emplace(value, std::pair<int, int>{INT_MAX, -1});  // its box before says where
    });
  }
  for (uint16_t s : skip) changed.erase(s);
  FrameMasks out = before;
  std::vector<int> slot(65536, -2);
  int u_first = INT_MAX, u_last = -1;
  for (auto& [value, columns] : changed) {
    slot[value] = -1;
    out.masks.erase(value);
    if (const auto it = before.masks.find(value); it != before.masks.end())
      columns = {std::min(columns.first, it->second.bbox.x),
                 std::max(columns.second, it->second.bbox.x + it->second.bbox.width - 1)};
    u_first = std::min(u_first, columns.first), u_last = std::max(u_last, columns.second);
  }
  // Where the pixels that differ lie in fewer columns than the changed values reach (a mug moved on a
  // desk), only those columns are scanned.
  const auto [differ_first, differ_last] = differing_columns(labels, before_labels, changed_rows);
  if (differ_first <= differ_last && (differ_first > u_first || differ_last < u_last)) {
    std::vector<uint16_t> values;
    for (const auto& [value, columns] : changed) values.push_back(value);
    const auto spliced = spliced_masks(labels, slot, values, before.masks, differ_first, differ_last);
    if (!spliced) return frame_masks(labels, skip);  // a mask before that is not one this made: found whole
    for (const auto& [value, mask] : *spliced) out.masks[value] = coco_mask(mask);
    return out;
  }
  for (const auto& [value, mask] : masks_in_columns(labels, std::move(slot), u_first, u_last))
    out.masks[value] = coco_mask(mask);
  return out;
}

std::string frame_masks_text(const FrameMasks& frame) {
  nlohmann::json masks = nlohmann::json::array();
  for (const auto& [value, mask] : frame.masks)
    masks.push_back({{"value", value},
                     {"counts", mask.counts},
                     {"area", mask.area},
                     {"bbox", {mask.bbox.x, mask.bbox.y, mask.bbox.width, mask.bbox.height}}});
  return nlohmann::json({{"width", frame.size.width}, {"height", frame.size.height}, {"masks", masks}}).dump() + "\n";
}

std::string frame_masks_text(const cv::Mat& labels, const std::vector<uint16_t>& skip) {
  return frame_masks_text(frame_masks(labels, skip));
}

size_t bytes_of(const FrameMasks& frame) {
  size_t bytes = 0;
  for (const auto& [value, mask] : frame.masks)  // each in a map node of its own
    bytes += sizeof(std::pair<const uint16_t, CocoMask>) + 4 * sizeof(void*) + mask.counts.capacity();
  return bytes;
}

FrameMasks read_frame_masks(const std::string& text, const std::string& file) {
  try {
    const auto j = nlohmann::json::parse(text);
    FrameMasks out;
    out.size = cv::Size(j.at("width").get<int>(), j.at("height").get<int>());
    for (const auto& m : j.at("masks")) {
      const auto& b = m.at("bbox");
      out.masks[m.at("value").get<uint16_t>()] =
          CocoMask{m.at("counts").get<std::string>(), m.at("area").get<int64_t>(),
                   cv::Rect(b.at(0).get<int>(), b.at(1).get<int>(), b.at(2).get<int>(), b.at(3).get<int>())};
    }
    return out;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, std::string("not a frame's masks file: ") + e.what());
  }
}

}  // namespace olt
