// ddgi-compare: image-difference report (RMSE, PSNR, SSIM, LDR-FLIP) for two images of any
// format. See compare_usage() for every convention; docs/metrics.md for the background.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compare_args.h"
#include "encode/image.h"
#include "encode/write_image.h"
#include "load_image.h"
#include "metrics/colormap.h"
#include "metrics/flip.h"
#include "metrics/pixel_error.h"
#include "metrics/ssim.h"

namespace ddgi::client {
namespace {

constexpr int kExitError = 2;

struct Report {
  double rmse = 0.0;
  double psnr = 0.0;
  std::optional<double> ssim;  // empty when the images are smaller than the SSIM window
  metrics::FlipResult flip;
};

metrics::RgbImageView view(const DisplayImage& image) {
  return {image.width, image.height, image.rgb};
}

Result<Report> measure(const DisplayImage& reference, const DisplayImage& test, double ppd) {
  if (reference.width != test.width || reference.height != test.height) {
    return invalid_argument("image sizes differ: " + reference.path + " is " +
                            encode::size_string(reference.width, reference.height) + ", " +
                            test.path + " is " + encode::size_string(test.width, test.height));
  }
  Report report;
  DDGI_ASSIGN_OR_RETURN(report.rmse, metrics::rmse(view(reference), view(test)));
  DDGI_ASSIGN_OR_RETURN(report.psnr, metrics::psnr(view(reference), view(test), 1.0));
  const metrics::SsimOptions ssim_options;
  const uint32_t window = 2 * uint32_t(ssim_options.radius) + 1;
  if (reference.width >= window && reference.height >= window) {
    DDGI_ASSIGN_OR_RETURN(report.ssim, metrics::ssim(view(reference), view(test), ssim_options));
  }
  DDGI_ASSIGN_OR_RETURN(report.flip,
                        metrics::flip(view(reference), view(test), {.pixels_per_degree = ppd}));
  return report;
}

Status write_flip_map(const std::string& path, const metrics::FlipResult& flip) {
  const encode::ImageRgba8 image{flip.width, flip.height, metrics::colorize_errors(flip.error_map)};
  return encode::write_image(path, image);
}

std::string describe(const DisplayImage& image, double exposure) {
  std::ostringstream out;
  out << image.width << "x" << image.height << ", " << image.pixel_type;
  if (image.hdr) {
    out << " linear HDR, exposure " << std::showpos << exposure << std::noshowpos << " EV, clipped "
        << 100.0 * image.clipped_fraction << "% of values, sRGB-encoded";
  } else {
    out << ", taken as sRGB-encoded";
  }
  return out.str();
}

nlohmann::json image_json(const DisplayImage& image) {
  nlohmann::json out = {{"path", image.path}, {"pixel_type", image.pixel_type}, {"hdr", image.hdr}};
  if (image.hdr) out["clipped_fraction"] = image.clipped_fraction;
  return out;
}

void print_json(const CompareArgs& args, const DisplayImage& reference, const DisplayImage& test,
                const Report& report) {
  nlohmann::json out = {
      {"reference", image_json(reference)},
      {"test", image_json(test)},
      {"width", reference.width},
      {"height", reference.height},
      {"rmse", report.rmse},
      // JSON has no infinity: identical images give null here and "identical": true.
      {"psnr_db", std::isinf(report.psnr) ? nlohmann::json(nullptr) : nlohmann::json(report.psnr)},
      {"identical", report.rmse == 0.0},
      {"ssim", report.ssim ? nlohmann::json(*report.ssim) : nlohmann::json(nullptr)},
      {"flip_mean", report.flip.mean},
      {"ppd", args.ppd},
      {"exposure", args.exposure},
      {"flip_map", args.flip_map ? nlohmann::json(*args.flip_map) : nlohmann::json(nullptr)},
  };
  std::cout << out.dump(2) << "\n";
}

void print_table(const CompareArgs& args, const DisplayImage& reference, const DisplayImage& test,
                 const Report& report) {
  std::printf("reference  %s  (%s)\n", reference.path.c_str(),
              describe(reference, args.exposure).c_str());
  std::printf("test       %s  (%s)\n", test.path.c_str(), describe(test, args.exposure).c_str());
  std::printf("RMSE       %.6f\n", report.rmse);
  if (std::isinf(report.psnr)) {
    std::printf("PSNR       inf dB (identical)\n");
  } else {
    std::printf("PSNR       %.3f dB (peak 1.0)\n", report.psnr);
  }
  if (report.ssim) {
    std::printf("SSIM       %.6f\n", *report.ssim);
  } else {
    std::printf("SSIM       n/a (images smaller than the 11x11 window)\n");
  }
  std::printf("FLIP       %.6f (mean LDR-FLIP at %.1f ppd)\n", report.flip.mean, args.ppd);
  if (args.flip_map) std::printf("FLIP map   %s\n", args.flip_map->c_str());
}

int run(const std::vector<std::string>& argv) {
  Result<CompareArgs> args = parse_compare_args(argv);
  if (!args.ok()) {
    std::cerr << "ddgi-compare: " << args.error().message << " (--help for usage)\n";
    return kExitError;
  }
  if (args->help) {
    std::cout << compare_usage();
    return 0;
  }
  const auto fail = [](const Error& error) {
    std::cerr << "ddgi-compare: error: " << error.message << "\n";
    return kExitError;
  };
  Result<DisplayImage> reference = load_display_image(args->reference, args->exposure);
  if (!reference.ok()) return fail(reference.error());
  Result<DisplayImage> test = load_display_image(args->test, args->exposure);
  if (!test.ok()) return fail(test.error());
  Result<Report> report = measure(*reference, *test, args->ppd);
  if (!report.ok()) return fail(report.error());
  if (args->flip_map) {
    if (Status written = write_flip_map(*args->flip_map, report->flip); !written.ok()) {
      return fail(written.error());
    }
  }
  if (args->json) {
    print_json(*args, *reference, *test, *report);
  } else {
    print_table(*args, *reference, *test, *report);
  }
  return 0;
}

}  // namespace
}  // namespace ddgi::client

int main(int argc, char** argv) {
  return ddgi::client::run(std::vector<std::string>(argv + 1, argv + argc));
}
