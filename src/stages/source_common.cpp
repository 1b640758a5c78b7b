// What the source formats share.
#include <algorithm>
#include <cctype>

#include "olt/core/image.h"
#include "source_formats.h"

namespace olt::source {

bool safe_id(const std::string& id) {
  return !id.empty() && id.size() <= 64 && (std::isalnum(static_cast<unsigned char>(id[0])) || id[0] == '_') &&
         std::all_of(id.begin(), id.end(), [](char ch) {
           return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '-';
         });
}

void image_size(const fs::path& file, int* width, int* height) {
  const PngHeader header = read_png_header(file);
  *width = header.width;
  *height = header.height;
}

}  // namespace olt::source
