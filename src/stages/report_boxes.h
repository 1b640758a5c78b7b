#pragma once
// The report's box pictures: the levelled scene (top and front view of the annotation frame) with
// every box drawn, coloured by class and named by id, and one picture around each box (the others
// thinner), so a box in the wrong place, of the wrong size or class is seen at a glance. The PNGs
// hold the scene alone; the boxes are drawn over them by the page (inline SVG, each edge titled
// with its box), so a picture depends on the scene and its region only: an edit redraws the
// pictures of the boxes it moved, not those they show in (the scene's only when a box leaves the
// region it spans).
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "olt/stages/report.h"

namespace olt {

struct BoxPictures {
  std::vector<std::pair<std::string, std::string>> files;  ///< (file, PNG bytes): scene_boxes.png, boxes/ID.png
  std::string html;                                        ///< the "Boxes" section
};

/// "#rrggbb".
std::string hex_colour(const std::array<uint8_t, 3>& rgb);

/// Text for HTML: < > & " escaped.
std::string html_escape(const std::string& text);

/// A relative path as a URL path: every byte but letters, digits and / . - _ ~ percent-encoded.
std::string url_path(const std::string& path);

/// Needs in.scene; the section says so when there is none.
BoxPictures draw_box_pictures(const ReportInputs& in, const ReportConfig& c);

}  // namespace olt
