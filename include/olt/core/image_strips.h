#pragma once
// Images written in horizontal strips that are coded independently, so that an image whose rows
// changed in a few places is encoded again only there: label PNGs in bands, overlay JPEGs with a
// restart marker per row of MCUs. A spliced image's bytes are those encoding it whole gives.
// The PNGs are framed here over zlib rather than written by libpng: libpng's flush keeps the deflate
// window, so its bands would depend on the ones before them.
#include <cstdint>
#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace olt {

/// An image of `image`'s size and type holding the rows of it that `rows` (a flag per row) flags; its
/// other rows are undefined (for work that reads only those). std::invalid_argument where the flags
/// are not one per row.
cv::Mat rows_of(const cv::Mat& image, const std::vector<bool>& rows);

/// True when a row of [first, last) differs between two images of the same size and type.
bool rows_differ(const cv::Mat& a, const cv::Mat& b, int first, int last);

/// Per row of `a`, whether it differs from the same row of `b`. `maybe` (a flag per row) names the
/// only rows that can differ, the others being known to be the same: those are not compared. Without
/// it (or with one of another length) every row is compared; where the images are not of one size
/// and type, every row differs.
std::vector<bool> differing_rows(const cv::Mat& a, const cv::Mat& b, const std::vector<bool>& maybe = {});

/// Rows of a label PNG's band.
inline constexpr int kLabelPngBandRows = 32;

/// A label PNG: its bytes, and per band the adler-32 of the band's filtered bytes (what splicing it
/// again needs: the zlib stream's checksum is theirs, joined).
struct LabelPng {
  std::string bytes;
  std::vector<uint32_t> band_sums;
};

/// A 16-bit single-channel label image as PNG, encoded for speed: the "up" filter turns label images
/// (long runs repeated from row to row) into zeros, and run-length deflate at level 1 packs them. Each
/// band of kLabelPngBandRows rows is deflated on its own into an IDAT chunk of its own (any PNG reader
/// reads it: the chunks are one zlib stream). Deterministic.
LabelPng label_png(const cv::Mat& image);
/// label_png(image)'s bytes.
std::string encode_label_png(const cv::Mat& image);

/// label_png(now) made from `before_bytes` and `before_sums`, label_png of an image before: only the
/// bands holding a row v with `changed_rows[v]` (or whose row above, which the filter reads, is one)
/// are deflated again, the others kept. The image before is not read: the flags say where it differs
/// (differing_rows(now, before)). Encodes whole where the flags are not one per row, or the bytes and
/// sums are not such a PNG of `now`'s size.
LabelPng splice_label_png(const std::string& before_bytes, const std::vector<uint32_t>& before_sums, const cv::Mat& now,
                          const std::vector<bool>& changed_rows);

/// `rows` (a flag per row) with every row of a strip flagged where one is: the rows a picture must be
/// drawn in to be encoded again in strips of `strip_rows`.
std::vector<bool> whole_strips(std::vector<bool> rows, int strip_rows);

/// encode_jpeg_in_strips(now, quality) made from `before_bytes`, encode_jpeg_in_strips of an image of
/// the same size, type and quality: only the strips holding a row v with `changed_rows[v]` are
/// encoded again (`now` need hold its pixels in those strips only). None where the bytes are not such
/// a JPEG of `now`'s size or the flags are not one per row: the caller encodes a whole picture.
std::optional<std::string> splice_jpeg_strips(const std::string& before_bytes, const cv::Mat& now,
                                              const std::vector<bool>& changed_rows, int quality = 90);

/// The JPEG in strips of a picture `draw(rows)` draws (it need draw only the rows flagged; every row
/// where none is): where `before_bytes` are the strips of it before (a picture of its size), drawn
/// and encoded again only in the strips holding a row v with `changed_rows[v]`; else drawn and
/// encoded whole, so a picture drawn in part is never encoded whole.
std::string redrawn_jpeg_strips(const std::string* before_bytes, const std::vector<bool>& changed_rows,
                                const std::function<cv::Mat(const std::vector<bool>& rows)>& draw, int quality = 90);

}  // namespace olt
