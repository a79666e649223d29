#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>

#include "encode/exr.h"
#include "encode/file_io.h"
#include "encode/image.h"
#include "encode/jpeg.h"
#include "encode/png.h"
#include "encode/write_image.h"
#include "test_images.h"

namespace ddgi::encode {
namespace {

// Smooth RGB ramps (what rendered frames mostly are) with a varying alpha. No hard edges: the
// JPEG bounds below hold for smooth content only.
ImageRgba8 smooth_rgba(uint32_t width, uint32_t height) {
  ImageRgba8 image{width, height, std::vector<uint8_t>(size_t{width} * height * 4)};
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      uint8_t* p = &image.pixels[(size_t{y} * width + x) * 4];
      p[0] = uint8_t(x * 255 / (width - 1));
      p[1] = uint8_t(y * 255 / (height - 1));
      p[2] = uint8_t(64 + (x + y) * 127 / (width + height - 2));
      p[3] = uint8_t((x * 7 + y * 3) % 256);
    }
  }
  return image;
}

int max_rgb_error(const ImageRgba8& a, const ImageRgba8& b) {
  int worst = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    if (i % 4 == 3) continue;
    worst = std::max(worst, std::abs(int(a.pixels[i]) - int(b.pixels[i])));
  }
  return worst;
}

TEST(Jpeg, RoundTripAtQuality95StaysWithinStatedError) {
  const ImageRgba8 image = smooth_rgba(64, 48);
  // Measured with libjpeg-turbo 2.1.5 on this image: 4:4:4 is off by at most 3 codes, 4:2:0 by
  // at most 4; the bounds leave one code of slack for other builds (SIMD paths round differently).
  for (auto [chroma, bound] : {std::pair{JpegChroma::k444, 4}, std::pair{JpegChroma::k420, 5}}) {
    Result<std::vector<uint8_t>> bytes = encode_jpeg(image, 95, chroma);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message;
    ASSERT_GT(bytes->size(), 2u);
    EXPECT_EQ((*bytes)[0], 0xFF);  // SOI marker
    EXPECT_EQ((*bytes)[1], 0xD8);
    Result<ImageRgba8> decoded = decode_jpeg(*bytes);
    ASSERT_TRUE(decoded.ok()) << decoded.error().message;
    EXPECT_EQ(decoded->width, 64u);
    EXPECT_EQ(decoded->height, 48u);
    EXPECT_LE(max_rgb_error(image, *decoded), bound);
    for (size_t i = 3; i < decoded->pixels.size(); i += 4) ASSERT_EQ(decoded->pixels[i], 255);
  }
}

TEST(Jpeg, LowerQualityIsSmallerAndWorse) {
  const ImageRgba8 image = smooth_rgba(64, 48);
  Result<std::vector<uint8_t>> high = encode_jpeg(image, 95);
  Result<std::vector<uint8_t>> low = encode_jpeg(image, 10);
  ASSERT_TRUE(high.ok() && low.ok());
  EXPECT_LT(low->size(), high->size());
  EXPECT_GT(max_rgb_error(image, *decode_jpeg(*low)), max_rgb_error(image, *decode_jpeg(*high)));
}

TEST(Jpeg, QualityOutOfRangeIsInvalidArgument) {
  const ImageRgba8 image = smooth_rgba(8, 8);
  for (int quality : {0, -5, 101}) {
    Result<std::vector<uint8_t>> bytes = encode_jpeg(image, quality);
    ASSERT_FALSE(bytes.ok()) << quality;
    EXPECT_EQ(bytes.error().code, ErrorCode::kInvalidArgument);
    EXPECT_NE(bytes.error().message.find(std::to_string(quality)), std::string::npos);
  }
  EXPECT_TRUE(encode_jpeg(image, 1).ok());
  EXPECT_TRUE(encode_jpeg(image, 100).ok());
}

TEST(Jpeg, RejectsBadInput) {
  ImageRgba8 short_buffer = smooth_rgba(8, 8);
  short_buffer.pixels.pop_back();
  EXPECT_FALSE(encode_jpeg(short_buffer, 90).ok());
  EXPECT_FALSE(encode_jpeg(ImageRgba8{}, 90).ok());
  const std::vector<uint8_t> garbage = {1, 2, 3, 4, 5, 6, 7, 8};
  Result<ImageRgba8> decoded = decode_jpeg(garbage);
  ASSERT_FALSE(decoded.ok());
  EXPECT_EQ(decoded.error().code, ErrorCode::kInvalidArgument);
  EXPECT_FALSE(decode_jpeg({}).ok());
}

// The planes path (what the service streams: the GPU converts, TurboJPEG compresses) decodes
// as close to the source as the RGBA path. Measured with libjpeg-turbo 2.1.5 on this image at
// quality 95: both are off by at most 6 codes (the files differ: libjpeg's own 4:2:0
// conversion rounds differently). Planes without the Y padding row and column made it 9.
TEST(Jpeg, YuvPlanesEncodeLikeRgba) {
  const ImageRgba8 image = smooth_rgba(37, 23);  // odd sizes: partial chroma blocks
  const ImageYuv420 planes = to_yuv420(image);
  Result<std::vector<uint8_t>> from_planes = encode_jpeg(planes, 95);
  Result<std::vector<uint8_t>> from_rgba = encode_jpeg(image, 95);
  ASSERT_TRUE(from_planes.ok()) << from_planes.error().message;
  ASSERT_TRUE(from_rgba.ok());
  Result<ImageRgba8> decoded = decode_jpeg(*from_planes);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  ASSERT_EQ(decoded->width, 37u);
  ASSERT_EQ(decoded->height, 23u);
  const int planes_error = max_rgb_error(image, *decoded);
  const int rgba_error = max_rgb_error(image, *decode_jpeg(*from_rgba));
  std::printf("max error: planes %d, rgba %d codes\n", planes_error, rgba_error);
  EXPECT_LE(planes_error, 7);
  EXPECT_LE(planes_error, rgba_error + 1);
}

// to_yuv420 against JFIF's matrix on single colours (Cb, Cr of grey are 128; the primaries'
// values are the matrix's rows, rounded).
TEST(Jpeg, Yuv420ConversionMatchesTheJfifMatrix) {
  struct Case {
    uint8_t r, g, b, y, cb, cr;
  };
  for (const Case& c : {Case{0, 0, 0, 0, 128, 128}, Case{255, 255, 255, 255, 128, 128},
                        Case{255, 0, 0, 76, 85, 255}, Case{0, 255, 0, 150, 44, 21},
                        Case{0, 0, 255, 29, 255, 107}}) {
    ImageRgba8 image{3, 3, {}};
    for (int i = 0; i < 9; ++i) image.pixels.insert(image.pixels.end(), {c.r, c.g, c.b, 7});
    const ImageYuv420 yuv = to_yuv420(image);
    ASSERT_TRUE(validate(yuv).ok());
    EXPECT_EQ(yuv.bytes.size(), 16u + 2 * 4);  // Y padded to 4x4, chroma 2x2
    for (int i = 0; i < 16; ++i) EXPECT_EQ(yuv.bytes[i], c.y) << int(c.r) << "," << int(c.g);
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(yuv.bytes[yuv.cb_offset + i], c.cb) << int(c.r) << "," << int(c.g);
      EXPECT_EQ(yuv.bytes[yuv.cr_offset + i], c.cr) << int(c.r) << "," << int(c.g);
    }
  }
}

TEST(Jpeg, YuvPlanesThatDoNotFitAreRefused) {
  const ImageYuv420 good = to_yuv420(smooth_rgba(8, 6));
  ImageYuv420 narrow = good;
  narrow.y_stride = 7;
  ImageYuv420 short_buffer = good;
  short_buffer.bytes.pop_back();
  ImageYuv420 overlapping = good;
  overlapping.cr_offset = overlapping.cb_offset + 1;
  for (const ImageYuv420* bad : {&narrow, &short_buffer, &overlapping}) {
    Result<std::vector<uint8_t>> bytes = encode_jpeg(*bad, 90);
    ASSERT_FALSE(bytes.ok());
    EXPECT_EQ(bytes.error().code, ErrorCode::kInvalidArgument);
    EXPECT_NE(bytes.error().message.find("8x6"), std::string::npos) << bytes.error().message;
  }
  EXPECT_TRUE(encode_jpeg(good, 90).ok());
  EXPECT_FALSE(encode_jpeg(ImageYuv420{}, 90).ok());
}

// Runs the strips one after another (the service runs them on its TaskPool).
void sequential(size_t count, const std::function<void(size_t)>& body) {
  for (size_t i = 0; i < count; ++i) body(i);
}

// Strips joined with restart markers decode to exactly the one-piece JPEG's pixels: 11 strips
// (so the restart markers cycle past RST7), an odd width with a partial MCU column and an odd
// last strip. Measured: 11 strips, 2 bytes per strip over the one-piece file (the marker).
TEST(Jpeg, StripsDecodeToTheOnePieceImage) {
  const ImageRgba8 image = smooth_rgba(67, 1401);
  const ImageYuv420 planes = to_yuv420(image);
  Result<std::vector<uint8_t>> whole = encode_jpeg(planes, 85);
  Result<std::vector<uint8_t>> strips = encode_jpeg_strips(planes, 85, 16, sequential);
  ASSERT_TRUE(whole.ok());
  ASSERT_TRUE(strips.ok()) << strips.error().message;
  size_t markers = 0;
  for (size_t i = 0; i + 1 < strips->size(); ++i) {
    markers += (*strips)[i] == 0xFF && ((*strips)[i + 1] & 0xF8) == 0xD0 ? 1 : 0;
  }
  std::printf("%zu restart markers, %zu bytes vs %zu in one piece\n", markers, strips->size(),
              whole->size());
  EXPECT_EQ(markers, 10u);  // 1401 rows: 88 MCU rows, strips of 8
  EXPECT_LE(strips->size(), whole->size() + 8 * (markers + 1));
  Result<ImageRgba8> from_whole = decode_jpeg(*whole);
  Result<ImageRgba8> from_strips = decode_jpeg(*strips);
  ASSERT_TRUE(from_strips.ok()) << from_strips.error().message;
  ASSERT_EQ(from_strips->width, 67u);
  ASSERT_EQ(from_strips->height, 1401u);
  EXPECT_EQ(from_strips->pixels, from_whole->pixels);
  EXPECT_LE(max_rgb_error(image, *from_strips), 12);  // not trivially equal: it is the image
}

// Small images stay in one piece (strips are at least 8 MCU rows), and a strip limit of 1 is
// the plain encoder.
TEST(Jpeg, SmallImagesAndOneStripAreOnePiece) {
  const ImageYuv420 small = to_yuv420(smooth_rgba(64, 200));
  const ImageYuv420 tall = to_yuv420(smooth_rgba(32, 600));
  EXPECT_EQ(*encode_jpeg_strips(small, 90, 8, sequential), *encode_jpeg(small, 90));
  EXPECT_EQ(*encode_jpeg_strips(tall, 90, 1, sequential), *encode_jpeg(tall, 90));
  EXPECT_NE(*encode_jpeg_strips(tall, 90, 4, sequential), *encode_jpeg(tall, 90));
  EXPECT_FALSE(encode_jpeg_strips(tall, 0, 4, sequential).ok());
}

TEST(Png, RoundTripIsExactIncludingAlpha) {
  const ImageRgba8 image = smooth_rgba(37, 21);
  Result<std::vector<uint8_t>> bytes = encode_png(image);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message;
  Result<ImageRgba8> decoded = decode_png(*bytes);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded->width, image.width);
  EXPECT_EQ(decoded->height, image.height);
  EXPECT_EQ(decoded->pixels, image.pixels);
}

TEST(Png, DecodeRejectsNonPng) {
  Result<std::vector<uint8_t>> jpeg = encode_jpeg(smooth_rgba(8, 8), 90);
  ASSERT_TRUE(jpeg.ok());
  EXPECT_FALSE(decode_png(*jpeg).ok());  // stb could decode it, but it is not a PNG
}

TEST(Exr, FloatRoundTripIsBitExactIncludingExtremes) {
  const float specials[] = {0.0f,
                            -0.0f,
                            1e-6f,
                            1e-30f,
                            0.5f,
                            1.0f,
                            65000.0f,
                            1e6f,
                            3.4e38f,
                            -3.25f,
                            std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN()};
  ImageRgbF image{4, 3, {}};
  for (size_t i = 0; i < 36; ++i) image.rgb.push_back(specials[i % std::size(specials)]);
  const test::TempDir dir;
  const std::string path = (dir / "extremes.exr").string();
  ASSERT_TRUE(write_exr(path, image).ok());
  Result<ImageRgbF> read = read_exr(path);
  ASSERT_TRUE(read.ok()) << read.error().message;
  EXPECT_EQ(read->width, 4u);
  EXPECT_EQ(read->height, 3u);
  ASSERT_EQ(read->rgb.size(), image.rgb.size());
  // NaN is documented to survive: FLOAT channels store the bits untouched.
  EXPECT_EQ(std::memcmp(read->rgb.data(), image.rgb.data(), image.rgb.size() * sizeof(float)), 0);
  EXPECT_TRUE(std::isnan(read->rgb[11]));
}

TEST(Exr, ErrorsNameTheFile) {
  Result<ImageRgbF> missing = read_exr("/nonexistent/dir/missing.exr");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
  EXPECT_NE(missing.error().message.find("/nonexistent/dir/missing.exr"), std::string::npos);

  const test::TempDir dir;
  const std::string not_exr = (dir / "not.exr").string();
  ASSERT_TRUE(write_file(not_exr, std::vector<uint8_t>{'h', 'e', 'l', 'l', 'o'}).ok());
  Result<ImageRgbF> bad = read_exr(not_exr);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find(not_exr), std::string::npos);

  Status unwritable = write_exr("/nonexistent/dir/out.exr", ImageRgbF{1, 1, {0, 0, 0}});
  ASSERT_FALSE(unwritable.ok());
  EXPECT_NE(unwritable.error().message.find("/nonexistent/dir/out.exr"), std::string::npos);
}

TEST(WriteImage, ChoosesEncoderByExtension) {
  const test::TempDir dir;
  const ImageRgba8 image = smooth_rgba(16, 8);
  for (const char* name : {"a.png", "b.PNG", "c.jpg", "d.jpeg", "e.exr"}) {
    const std::string path = (dir / name).string();
    Status written = write_image(path, image);
    ASSERT_TRUE(written.ok()) << name << ": " << written.error().message;
  }
  Result<ImageRgba8> png = decode_png(*read_file((dir / "a.png").string()));
  ASSERT_TRUE(png.ok());
  EXPECT_EQ(png->pixels, image.pixels);
  EXPECT_TRUE(decode_jpeg(*read_file((dir / "c.jpg").string())).ok());
  Result<ImageRgbF> exr = read_exr((dir / "e.exr").string());
  ASSERT_TRUE(exr.ok());
  // The 8-bit image went to EXR as linear values; converting back gives the same codes.
  const ImageRgba8 back = to_srgb8(*exr);
  for (size_t i = 0; i < back.pixels.size(); ++i) {
    if (i % 4 == 3) continue;  // alpha is not stored in the EXR
    ASSERT_EQ(back.pixels[i], image.pixels[i]) << i;
  }
}

TEST(WriteImage, FloatImageToPngClampsWithoutToneMapping) {
  const test::TempDir dir;
  const std::string path = (dir / "hdr.png").string();
  ASSERT_TRUE(write_image(path, ImageRgbF{2, 1, {4.0f, 0.5f, -1.0f, 0.0f, 1.0f, 0.25f}}).ok());
  Result<ImageRgba8> png = decode_png(*read_file(path));
  ASSERT_TRUE(png.ok());
  const std::vector<uint8_t> expected = {255, 188, 0, 255, 0, 255, 137, 255};
  EXPECT_EQ(png->pixels, expected);
}

TEST(WriteImage, UnknownExtensionAndUnwritablePathAreClearErrors) {
  const ImageRgba8 image = smooth_rgba(4, 4);
  Status unknown = write_image("/tmp/out.bmp", image);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(unknown.error().message.find("/tmp/out.bmp"), std::string::npos);
  EXPECT_NE(unknown.error().message.find(".bmp"), std::string::npos);
  EXPECT_FALSE(write_image("/tmp/no_extension", image).ok());

  for (const char* path : {"/nonexistent/dir/out.png", "/nonexistent/dir/out.jpg"}) {
    Status status = write_image(path, image);
    ASSERT_FALSE(status.ok()) << path;
    EXPECT_NE(status.error().message.find(path), std::string::npos) << status.error().message;
  }
  ImageRgba8 broken = image;
  broken.pixels.resize(3);
  Status invalid = write_image("/tmp/broken.png", broken);
  ASSERT_FALSE(invalid.ok());
  EXPECT_NE(invalid.error().message.find("/tmp/broken.png"), std::string::npos);
}

TEST(Image, SrgbConversionRoundTripsEveryCode) {
  ImageRgba8 all_codes{256, 1, {}};
  for (int code = 0; code < 256; ++code) {
    all_codes.pixels.insert(all_codes.pixels.end(),
                            {uint8_t(code), uint8_t(255 - code), uint8_t(code), 255});
  }
  EXPECT_EQ(to_srgb8(to_linear(all_codes)).pixels, all_codes.pixels);
  // The transfer function's known points.
  EXPECT_EQ(srgb_to_linear(1.0f), 1.0f);
  EXPECT_EQ(linear_to_srgb(1.0f), 1.0f);
  EXPECT_FLOAT_EQ(srgb_to_linear(0.0f), 0.0f);
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.2140f, 1e-4f);
}

TEST(Image, ValidateNamesTheSizes) {
  Status status = validate(ImageRgbF{3, 2, std::vector<float>(17)});
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().message.find("3x2"), std::string::npos);
  EXPECT_NE(status.error().message.find("18"), std::string::npos);
}

}  // namespace
}  // namespace ddgi::encode
