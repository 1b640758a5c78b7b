#include "olt/core/image_strips.h"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string_view>

#include "olt/core/image.h"

namespace olt {
namespace {

// ---- Label PNGs: sig, IHDR, IDAT(zlib header), IDAT(band) per band, IDAT(last block, adler-32), IEND

constexpr std::string_view kPngSignature("\x89PNG\r\n\x1a\n", 8);
constexpr std::string_view kZlibHeader("\x78\x01", 2);  // deflate, 32 KB window, fastest level
constexpr std::string_view kLastBlock("\x03\x00", 2);   // an empty final block of fixed codes

uint32_t read_u32(const std::string& bytes, size_t at) {
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data() + at);
  return (uint32_t{b[0]} << 24) | (uint32_t{b[1]} << 16) | (uint32_t{b[2]} << 8) | b[3];
}

void append_u32(std::string& out, uint32_t value) {
  const char b[4] = {static_cast<char>(value >> 24), static_cast<char>(value >> 16), static_cast<char>(value >> 8),
                     static_cast<char>(value)};
  out.append(b, 4);
}

void append_chunk(std::string& out, std::string_view type, std::string_view data) {
  append_u32(out, static_cast<uint32_t>(data.size()));
  const size_t typed = out.size();
  out.append(type).append(data);
  const auto* crc_from = reinterpret_cast<const Bytef*>(out.data() + typed);
  append_u32(out, static_cast<uint32_t>(crc32(0, crc_from, static_cast<uInt>(data.size() + 4))));
}

std::string header_data(const cv::Mat& image) {  // 16-bit grey, no interlacing
  std::string data;
  append_u32(data, static_cast<uint32_t>(image.cols));
  append_u32(data, static_cast<uint32_t>(image.rows));
  data.append("\x10\x00\x00\x00\x00", 5);
  return data;
}

void check_label_image(const cv::Mat& image) {
  if (image.type() != CV_16UC1 || image.empty())
    throw std::invalid_argument("encode_label_png: expected a 16-bit single-channel image");
}

size_t filtered_row_bytes(const cv::Mat& image) { return 1 + 2 * static_cast<size_t>(image.cols); }

// Rows [first, last) as PNG stores them with the "up" filter: each row its filter's type, then each
// byte of its big-endian samples less the byte above it (0 above the first row).
std::string filtered_band(const cv::Mat& image, int first, int last) {
  std::string out(filtered_row_bytes(image) * static_cast<size_t>(last - first), '\0');
  auto* o = reinterpret_cast<unsigned char*>(out.data());
  for (int v = first; v < last; ++v) {
    const uint16_t* row = image.ptr<uint16_t>(v);
    const uint16_t* above = v > 0 ? image.ptr<uint16_t>(v - 1) : nullptr;
    *o++ = 2;  // up
    for (int u = 0; u < image.cols; ++u) {
      const uint16_t a = above ? above[u] : 0;
      *o++ = static_cast<unsigned char>((row[u] >> 8) - (a >> 8));
      *o++ = static_cast<unsigned char>((row[u] & 0xFF) - (a & 0xFF));
    }
  }
  return out;
}

// Bands deflated each on its own (level 1, run-length), ending byte-aligned and not last.
class BandDeflater {
 public:
  BandDeflater() {
    if (deflateInit2(&stream_, 1, Z_DEFLATED, -15, 8, Z_RLE) != Z_OK)
      throw std::runtime_error("PNG encoding failed: out of memory");
  }
  ~BandDeflater() { deflateEnd(&stream_); }
  BandDeflater(const BandDeflater&) = delete;
  BandDeflater& operator=(const BandDeflater&) = delete;

  std::string deflated(const std::string& band) {
    deflateReset(&stream_);
    std::string out(deflateBound(&stream_, band.size()) + 16, '\0');  // + the flush's empty block
    stream_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(band.data()));
    stream_.avail_in = static_cast<uInt>(band.size());
    stream_.next_out = reinterpret_cast<Bytef*>(out.data());
    stream_.avail_out = static_cast<uInt>(out.size());
    if (deflate(&stream_, Z_SYNC_FLUSH) != Z_OK || stream_.avail_in != 0 || stream_.avail_out == 0)
      throw std::runtime_error("PNG encoding failed");
    out.resize(out.size() - stream_.avail_out);
    return out;
  }

 private:
  z_stream stream_{};
};

int band_count(const cv::Mat& image) { return (image.rows + kLabelPngBandRows - 1) / kLabelPngBandRows; }

std::pair<int, int> band_rows(const cv::Mat& image, int band) {
  return {band * kLabelPngBandRows, std::min(image.rows, (band + 1) * kLabelPngBandRows)};
}

std::string png_start(const cv::Mat& image) {
  std::string out(kPngSignature);
  append_chunk(out, "IHDR", header_data(image));
  append_chunk(out, "IDAT", kZlibHeader);
  return out;
}

void png_end(std::string& out, uint32_t adler) {
  std::string last(kLastBlock);
  append_u32(last, adler);
  append_chunk(out, "IDAT", last);
  append_chunk(out, "IEND", "");
}

struct Chunk {
  std::string_view type;
  size_t at;    ///< where the chunk starts (its length)
  size_t size;  ///< of its data
  std::string_view data(const std::string& bytes) const { return std::string_view(bytes).substr(at + 8, size); }
  std::string_view whole(const std::string& bytes) const { return std::string_view(bytes).substr(at, size + 12); }
};

// The chunks of a PNG; none where the bytes are not a signature and whole chunks.
std::vector<Chunk> chunks_of(const std::string& bytes) {
  if (bytes.compare(0, kPngSignature.size(), kPngSignature) != 0) return {};
  std::vector<Chunk> chunks;
  for (size_t at = kPngSignature.size(); at < bytes.size();) {
    if (bytes.size() - at < 12) return {};
    const size_t size = read_u32(bytes, at);
    if (size > bytes.size() - at - 12) return {};
    chunks.push_back({std::string_view(bytes).substr(at + 4, 4), at, size});
    at += 12 + size;
  }
  return chunks;
}

// ---- Overlay JPEGs: a header up to the scan's data, then each strip's coded bytes, a restart marker
// (RST0..RST7 in turn) between them, and the end marker.

// The header and strips of a JPEG in strips of `height`×`width` pixels of `channels` components; no
// header where it is not one.
struct JpegStrips {
  std::string_view header;
  std::vector<std::string_view> strips;
};

JpegStrips strips_of(const std::string& bytes, int width, int height, int channels) {
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  const size_t n = bytes.size();
  if (n < 4 || b[0] != 0xFF || b[1] != 0xD8) return {};
  size_t at = 2;
  int frame_width = -1, frame_height = -1, frame_channels = -1;
  for (;;) {  // marker segments up to the start of scan
    if (n - at < 4 || b[at] != 0xFF) return {};
    const unsigned char marker = b[at + 1];
    const size_t length = (size_t{b[at + 2]} << 8) | b[at + 3];
    if (length < 2 || length > n - at - 2) return {};
    if (marker == 0xC0 && length >= 8) {  // baseline frame: precision, height, width, components
      frame_height = (b[at + 5] << 8) | b[at + 6];
      frame_width = (b[at + 7] << 8) | b[at + 8];
      frame_channels = b[at + 9];
    }
    at += 2 + length;
    if (marker == 0xDA) break;
  }
  if (frame_width != width || frame_height != height || frame_channels != channels) return {};
  JpegStrips out{std::string_view(bytes).substr(0, at), {}};
  size_t strip = at;
  for (;;) {
    const void* found = std::memchr(b + at, 0xFF, n - at);
    if (!found) return {};
    at = static_cast<size_t>(static_cast<const unsigned char*>(found) - b);
    if (at + 1 >= n) return {};
    const unsigned char marker = b[at + 1];
    if (marker == 0x00) {  // a stuffed 0xFF of coded data
      at += 2;
      continue;
    }
    const bool restart = marker == 0xD0 + out.strips.size() % 8;
    if (!restart && marker != 0xD9) return {};
    out.strips.push_back(std::string_view(bytes).substr(strip, at - strip));
    at += 2;
    strip = at;
    if (marker == 0xD9) return at == n ? out : JpegStrips{};
  }
}

}  // namespace

cv::Mat rows_of(const cv::Mat& image, const std::vector<bool>& rows) {
  if (rows.size() != static_cast<size_t>(image.rows)) throw std::invalid_argument("rows_of: expected a flag per row");
  cv::Mat kept(image.size(), image.type());
  for (int v = 0; v < image.rows; ++v)
    if (rows[static_cast<size_t>(v)]) image.row(v).copyTo(kept.row(v));
  return kept;
}

bool rows_differ(const cv::Mat& a, const cv::Mat& b, int first, int last) {
  const size_t row_bytes = static_cast<size_t>(a.cols) * a.elemSize();
  for (int v = first; v < last; ++v)
    if (std::memcmp(a.ptr(v), b.ptr(v), row_bytes) != 0) return true;
  return false;
}

std::vector<bool> differing_rows(const cv::Mat& a, const cv::Mat& b, const std::vector<bool>& maybe) {
  std::vector<bool> out(static_cast<size_t>(a.rows), true);
  if (a.size() != b.size() || a.type() != b.type()) return out;
  const bool all = maybe.size() != out.size();
  for (int v = 0; v < a.rows; ++v)
    out[static_cast<size_t>(v)] = (all || maybe[static_cast<size_t>(v)]) && rows_differ(a, b, v, v + 1);
  return out;
}

namespace {

// The adler-32 of a band's filtered bytes, on its own.
uint32_t band_sum(const std::string& filtered) {
  return static_cast<uint32_t>(adler32(adler32(0, nullptr, 0), reinterpret_cast<const Bytef*>(filtered.data()),
                                       static_cast<uInt>(filtered.size())));
}

// The zlib stream's checksum: the bands' sums joined, each band as long as its filtered rows.
uint32_t stream_sum(const cv::Mat& image, const std::vector<uint32_t>& band_sums) {
  uLong adler = adler32(0, nullptr, 0);
  for (int band = 0; band < band_count(image); ++band) {
    const auto [first, last] = band_rows(image, band);
    const auto length = static_cast<z_off_t>(filtered_row_bytes(image) * static_cast<size_t>(last - first));
    adler = adler32_combine(adler, band_sums[static_cast<size_t>(band)], length);
  }
  return static_cast<uint32_t>(adler);
}

}  // namespace

LabelPng label_png(const cv::Mat& image) {
  check_label_image(image);
  BandDeflater deflater;
  LabelPng png{png_start(image), {}};
  for (int band = 0; band < band_count(image); ++band) {
    const auto [first, last] = band_rows(image, band);
    const std::string filtered = filtered_band(image, first, last);
    png.band_sums.push_back(band_sum(filtered));
    append_chunk(png.bytes, "IDAT", deflater.deflated(filtered));
  }
  png_end(png.bytes, stream_sum(image, png.band_sums));
  return png;
}

std::string encode_label_png(const cv::Mat& image) { return label_png(image).bytes; }

LabelPng splice_label_png(const std::string& before_bytes, const std::vector<uint32_t>& before_sums, const cv::Mat& now,
                          const std::vector<bool>& changed_rows) {
  check_label_image(now);
  const size_t bands = static_cast<size_t>(band_count(now));
  if (before_sums.size() != bands || changed_rows.size() != static_cast<size_t>(now.rows)) return label_png(now);
  const std::vector<Chunk> chunks = chunks_of(before_bytes);
  // IHDR, the zlib header, a chunk per band, the last block and checksum (the bands' sums'), IEND.
  const auto is = [&](size_t k, std::string_view type) { return chunks[k].type == type; };
  if (chunks.size() != bands + 4 || !is(0, "IHDR") || chunks[0].data(before_bytes) != header_data(now) ||
      !is(1, "IDAT") || chunks[1].data(before_bytes) != kZlibHeader || !is(bands + 2, "IDAT") ||
      chunks[bands + 2].size != 6 || chunks[bands + 2].data(before_bytes).substr(0, 2) != kLastBlock ||
      !is(bands + 3, "IEND") || read_u32(before_bytes, chunks[bands + 2].at + 10) != stream_sum(now, before_sums))
    return label_png(now);
  for (size_t k = 2; k < bands + 2; ++k)
    if (!is(k, "IDAT")) return label_png(now);
  std::optional<BandDeflater> deflater;
  LabelPng png{png_start(now), before_sums};
  for (size_t band = 0; band < bands; ++band) {
    const auto [first, last] = band_rows(now, static_cast<int>(band));
    const auto from = changed_rows.begin() + std::max(first - 1, 0), to = changed_rows.begin() + last;
    if (std::find(from, to, true) == to) {  // its rows and the row above (the filter's) as they were
      png.bytes.append(chunks[band + 2].whole(before_bytes));
      continue;
    }
    const std::string filtered = filtered_band(now, first, last);
    png.band_sums[band] = band_sum(filtered);
    if (!deflater) deflater.emplace();
    append_chunk(png.bytes, "IDAT", deflater->deflated(filtered));
  }
  png_end(png.bytes, stream_sum(now, png.band_sums));
  return png;
}

std::vector<bool> whole_strips(std::vector<bool> rows, int strip_rows) {
  if (strip_rows < 1) throw std::invalid_argument("whole_strips: expected strips of a row or more");
  const size_t step = static_cast<size_t>(strip_rows);
  for (size_t first = 0; first < rows.size(); first += step) {
    const auto begin = rows.begin() + static_cast<std::ptrdiff_t>(first);
    const auto end = rows.begin() + static_cast<std::ptrdiff_t>(std::min(rows.size(), first + step));
    if (std::find(begin, end, true) != end) std::fill(begin, end, true);
  }
  return rows;
}

namespace {

// The rows of strip k of strips of `strip_rows` in an image of `rows` rows (the last may be short).
cv::Range strip_range(size_t k, int strip_rows, int rows) {
  const int first = static_cast<int>(k) * strip_rows;
  return {first, std::min(rows, first + strip_rows)};
}

// The coded bytes of strips `changed` (in order) of `now`, in `coded`: stacked and encoded in one
// go, without libjpeg set up again for each. A strip's coded bytes depend on its rows alone: the
// encoder starts afresh after each restart marker (no prediction crosses one) and its Huffman tables
// are the fixed standard ones; only the last strip may be short, and it stays last.
std::vector<std::string_view> encode_strips(const cv::Mat& now, const std::vector<size_t>& changed, int strip_rows,
                                            int quality, std::string& coded) {
  if (changed.empty()) return {};
  cv::Mat stacked;
  if (changed.back() - changed.front() + 1 == changed.size()) {  // one run of strips: no copy
    stacked = now.rowRange(strip_range(changed.front(), strip_rows, now.rows).start,
                           strip_range(changed.back(), strip_rows, now.rows).end);
  } else {
    std::vector<cv::Mat> parts;
    for (const size_t k : changed) parts.push_back(now.rowRange(strip_range(k, strip_rows, now.rows)));
    cv::vconcat(parts, stacked);
  }
  coded = encode_jpeg_in_strips(stacked, quality);
  std::vector<std::string_view> strips = strips_of(coded, stacked.cols, stacked.rows, stacked.channels()).strips;
  if (strips.size() != changed.size())
    throw std::runtime_error("JPEG encoding failed: " + std::to_string(changed.size()) + " strips came out as " +
                             std::to_string(strips.size()));
  return strips;
}

}  // namespace

std::optional<std::string> splice_jpeg_strips(const std::string& before_bytes, const cv::Mat& now,
                                              const std::vector<bool>& changed_rows, int quality) {
  if (changed_rows.size() != static_cast<size_t>(now.rows)) return std::nullopt;
  const int strip_rows = jpeg_strip_rows(now.channels());
  const JpegStrips before = strips_of(before_bytes, now.cols, now.rows, now.channels());
  const size_t strips = static_cast<size_t>((now.rows + strip_rows - 1) / strip_rows);
  if (before.header.empty() || before.strips.size() != strips) return std::nullopt;
  std::vector<size_t> changed;
  for (size_t k = 0; k < strips; ++k) {
    const cv::Range rows = strip_range(k, strip_rows, now.rows);
    const auto begin = changed_rows.begin() + rows.start, end = changed_rows.begin() + rows.end;
    if (std::find(begin, end, true) != end) changed.push_back(k);
  }
  std::string coded;
  const std::vector<std::string_view> coded_strips = encode_strips(now, changed, strip_rows, quality, coded);
  std::string out(before.header);
  out.reserve(before_bytes.size() + before_bytes.size() / 8);
  for (size_t k = 0, next = 0; k < strips; ++k) {
    if (k > 0) out.append({'\xFF', static_cast<char>(0xD0 + (k - 1) % 8)});
    const bool again = next < changed.size() && changed[next] == k;
    out.append(again ? coded_strips[next++] : before.strips[k]);
  }
  out.append("\xFF\xD9", 2);
  return out;
}

std::string redrawn_jpeg_strips(const std::string* before_bytes, const std::vector<bool>& changed_rows,
                                const std::function<cv::Mat(const std::vector<bool>& rows)>& draw, int quality) {
  if (before_bytes && !changed_rows.empty()) {
    const cv::Mat drawn = draw(changed_rows);
    if (std::optional<std::string> spliced = splice_jpeg_strips(*before_bytes, drawn, changed_rows, quality))
      return std::move(*spliced);
  }
  return encode_jpeg_in_strips(draw({}), quality);
}

}  // namespace olt
