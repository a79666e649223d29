#include "compare_args.h"

#include <charconv>
#include <cmath>

namespace ddgi::client {

namespace {

Result<double> parse_number(const std::string& flag, const std::string& text) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) {
    return invalid_argument(flag + " needs a number, got '" + text + "'");
  }
  return value;
}

}  // namespace

std::string compare_usage() {
  return R"(usage: ddgi-compare REFERENCE TEST [--flip-map OUT] [--ppd 67] [--exposure 0] [--json]

Compares two images of the same size and prints RMSE, PSNR, SSIM and mean LDR-FLIP.

Inputs: any format OpenImageIO reads (PNG, JPEG, EXR, TIFF, HDR, ...). All metrics are computed
on display-encoded (sRGB) RGB values in [0,1]:
  - integer images (8/16-bit PNG, JPEG, TIFF) are taken as already sRGB-encoded;
  - floating-point images (EXR, HDR, float TIFF) are taken as linear HDR and shown the way a
    viewer without tone mapping would: sRGB(clamp(value * 2^EXPOSURE, 0, 1)). Values above 1
    clip; the share clipped is reported. Use --exposure to bring highlights into range.
Alpha and channels beyond the third are ignored; grey images count as R = G = B.

Metrics:
  RMSE   root mean square difference over all channels, in [0,1] units
  PSNR   20 log10(1 / RMSE) dB (peak 1.0); identical images: inf (null in JSON)
  SSIM   Wang et al. 2004, 11x11 Gaussian window (sigma 1.5), K1 0.01, K2 0.03, on luma
         0.2126 R + 0.7152 G + 0.0722 B; needs images of at least 11x11 (else n/a)
  FLIP   mean LDR-FLIP (Andersson et al. 2020), 0 = identical, 1 = maximal difference

Options:
  --flip-map OUT   write the per-pixel FLIP error as a colour-mapped image (.png, .jpg, .exr)
  --ppd N          FLIP pixels per degree (default 67: 0.7 m from a 0.7 m wide 4K monitor)
  --exposure E     stops applied to floating-point inputs before clipping (default 0)
  --json           print one JSON object instead of a table
  -h, --help       this text

Exit status: 0 when the comparison ran (whatever the difference), 2 on any error (unreadable
file, size mismatch, bad arguments).
)";
}

Result<CompareArgs> parse_compare_args(const std::vector<std::string>& args) {
  CompareArgs parsed;
  std::vector<std::string> positional;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    const auto value = [&]() -> Result<std::string> {
      if (i + 1 >= args.size()) return invalid_argument(arg + " needs a value");
      return args[++i];
    };
    if (arg == "-h" || arg == "--help") {
      parsed.help = true;
    } else if (arg == "--json") {
      parsed.json = true;
    } else if (arg == "--flip-map") {
      DDGI_ASSIGN_OR_RETURN(parsed.flip_map, value());
    } else if (arg == "--ppd") {
      DDGI_ASSIGN_OR_RETURN(const std::string text, value());
      DDGI_ASSIGN_OR_RETURN(parsed.ppd, parse_number(arg, text));
      if (!(parsed.ppd > 0.0 && parsed.ppd <= 1000.0)) {
        return invalid_argument("--ppd must be in (0, 1000], got " + text);
      }
    } else if (arg == "--exposure") {
      DDGI_ASSIGN_OR_RETURN(const std::string text, value());
      DDGI_ASSIGN_OR_RETURN(parsed.exposure, parse_number(arg, text));
    } else if (arg.size() > 1 && arg[0] == '-') {
      return invalid_argument("unknown option " + arg);
    } else {
      positional.push_back(arg);
    }
  }
  if (parsed.help) return parsed;
  if (positional.size() != 2) {
    return invalid_argument("expected two images (REFERENCE TEST), got " +
                            std::to_string(positional.size()));
  }
  parsed.reference = positional[0];
  parsed.test = positional[1];
  return parsed;
}

}  // namespace ddgi::client
