// One JPEG from strips compressed in parallel (encode/jpeg.h, encode_jpeg_strips). Each strip
// is a complete JPEG from TurboJPEG: SOI, the same tables (standard Huffman tables, the same
// quality), a frame header with the strip's height, one scan, EOI. The joined file is the first
// strip's headers with the whole image's height, a restart interval of one strip's MCUs (DRI),
// then every strip's entropy-coded data with a restart marker RST0..RST7 (cycling) before each
// but the first.
#include <algorithm>
#include <string>

#include "encode/jpeg.h"
#include "encode/jpeg_planes.h"

namespace ddgi::encode {
namespace {

constexpr uint8_t kMarker = 0xFF;
constexpr uint8_t kSof0 = 0xC0;  // baseline frame header
constexpr uint8_t kSos = 0xDA;   // start of scan
constexpr uint8_t kDri = 0xDD;   // define restart interval
constexpr uint8_t kRst0 = 0xD0;  // restart markers: RST0 .. RST7
constexpr uint8_t kEoi = 0xD9;
constexpr uint32_t kMcuSide = 16;  // 4:2:0

// Where the parts of one strip's JPEG lie.
struct StripLayout {
  size_t sof = 0;         // the SOF0 marker; its height field is at sof + 5
  size_t sos = 0;         // the SOS marker: headers end here
  size_t scan_begin = 0;  // the entropy-coded data, which runs to the EOI at the end
};

Result<StripLayout> parse_strip(const std::vector<uint8_t>& jpeg) {
  auto broken = [](const std::string& what) {
    return internal_error("the JPEG encoder wrote a strip the joiner cannot read: " + what);
  };
  const size_t n = jpeg.size();
  if (n < 4 || jpeg[0] != kMarker || jpeg[n - 2] != kMarker || jpeg[n - 1] != kEoi) {
    return broken("no SOI/EOI");
  }
  StripLayout layout;
  bool have_sof = false;
  for (size_t at = 2; at + 4 <= n;) {
    if (jpeg[at] != kMarker) return broken("no marker at byte " + std::to_string(at));
    const uint8_t marker = jpeg[at + 1];
    const size_t length = (size_t{jpeg[at + 2]} << 8) | jpeg[at + 3];
    if (marker == kSof0) {
      layout.sof = at;
      have_sof = true;
    }
    if (marker == kSos) {
      layout.sos = at;
      layout.scan_begin = at + 2 + length;
      if (!have_sof || layout.scan_begin > n - 2) return broken("no SOF0 or a short scan");
      return layout;
    }
    at += 2 + length;
  }
  return broken("no SOS");
}

// The planes of rows [first_row, first_row + rows) of `image` (first_row a multiple of 16).
Yuv420Planes strip_planes(const ImageYuv420& image, uint32_t first_row, uint32_t rows) {
  Yuv420Planes planes = yuv420_planes(image);
  planes.y += size_t{first_row} * image.y_stride;
  planes.cb += size_t{first_row / 2} * image.chroma_stride;
  planes.cr += size_t{first_row / 2} * image.chroma_stride;
  planes.height = rows;
  return planes;
}

// Joins the strips as the file comment says. Every strip's headers must equal the first's but
// for the height (the same tables), or the scans would not decode with the first's tables.
Result<std::vector<uint8_t>> join_strips(const std::vector<std::vector<uint8_t>>& strips,
                                         uint32_t height, uint32_t restart_interval) {
  std::vector<StripLayout> layouts;
  for (const std::vector<uint8_t>& strip : strips) {
    DDGI_ASSIGN_OR_RETURN(StripLayout layout, parse_strip(strip));
    layouts.push_back(layout);
  }
  const std::vector<uint8_t>& first = strips[0];
  const StripLayout& head = layouts[0];
  for (size_t i = 1; i < strips.size(); ++i) {
    const bool same_tables =
        layouts[i].sof == head.sof && layouts[i].sos == head.sos &&
        std::equal(first.begin(), first.begin() + head.sof + 5, strips[i].begin()) &&
        std::equal(first.begin() + head.sof + 7, first.begin() + head.sos,
                   strips[i].begin() + head.sof + 7);
    if (!same_tables) return internal_error("JPEG strips were written with different tables");
  }
  std::vector<uint8_t> out(first.begin(), first.begin() + head.sos);
  out[head.sof + 5] = static_cast<uint8_t>(height >> 8);
  out[head.sof + 6] = static_cast<uint8_t>(height & 0xFF);
  out.insert(out.end(), {kMarker, kDri, 0, 4, static_cast<uint8_t>(restart_interval >> 8),
                         static_cast<uint8_t>(restart_interval & 0xFF)});
  out.insert(out.end(), first.begin() + head.sos, first.end() - 2);
  for (size_t i = 1; i < strips.size(); ++i) {
    out.push_back(kMarker);
    out.push_back(static_cast<uint8_t>(kRst0 + (i - 1) % 8));
    out.insert(out.end(), strips[i].begin() + layouts[i].scan_begin, strips[i].end() - 2);
  }
  out.insert(out.end(), {kMarker, kEoi});
  return out;
}

}  // namespace

Result<std::vector<uint8_t>> encode_jpeg_strips(const ImageYuv420& image, int quality,
                                                uint32_t max_strips,
                                                const ParallelFor& parallel_for) {
  DDGI_TRY(check_jpeg_input(image.width, image.height, quality));
  DDGI_TRY(validate(image));
  const uint32_t mcu_columns = (image.width + kMcuSide - 1) / kMcuSide;
  const uint32_t mcu_rows = (image.height + kMcuSide - 1) / kMcuSide;
  const uint32_t wanted = std::clamp(mcu_rows / kMinStripMcuRows, 1u, std::max(max_strips, 1u));
  // The restart interval (one strip's MCUs) is a 16-bit field.
  const uint32_t strip_mcu_rows =
      std::min((mcu_rows + wanted - 1) / wanted, std::max(65535u / mcu_columns, 1u));
  const uint32_t strips = (mcu_rows + strip_mcu_rows - 1) / strip_mcu_rows;
  if (strips == 1) return compress_yuv420_planes(yuv420_planes(image), quality);

  const uint32_t strip_rows = strip_mcu_rows * kMcuSide;
  std::vector<Result<std::vector<uint8_t>>> compressed(strips, internal_error("not run"));
  parallel_for(strips, [&](size_t i) {
    const uint32_t first_row = static_cast<uint32_t>(i) * strip_rows;
    const uint32_t rows = std::min(strip_rows, image.height - first_row);
    compressed[i] = compress_yuv420_planes(strip_planes(image, first_row, rows), quality);
  });
  std::vector<std::vector<uint8_t>> bytes;
  for (Result<std::vector<uint8_t>>& strip : compressed) {
    if (!strip.ok()) return strip.error();
    bytes.push_back(std::move(strip).value());
  }
  return join_strips(bytes, image.height, strip_mcu_rows * mcu_columns);
}

}  // namespace ddgi::encode
