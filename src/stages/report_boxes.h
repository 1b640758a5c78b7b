#pragma once
// The report's box pictures: the levelled scene (top and front view of the annotation frame) with
// every box drawn, coloured by class and named by id, and one picture around each box, so a box
// in the wrong place, of the wrong size or class is seen at a glance.
#include <string>
#include <utility>
#include <vector>

#include "olt/stages/report.h"

namespace olt {

struct BoxPictures {
  std::vector<std::pair<std::string, std::string>> files;  ///< (file, PNG bytes): scene_boxes.png, boxes/ID.png
  std::string html;                                        ///< the "Boxes" section
};

/// Text for HTML: < > & " escaped.
std::string html_escape(const std::string& text);

/// A relative path as a URL path: every byte but letters, digits and / . - _ ~ percent-encoded.
std::string url_path(const std::string& path);

/// Needs in.scene; the section says so when there is none.
BoxPictures draw_box_pictures(const ReportInputs& in, const ReportConfig& c);

}  // namespace olt
