// The GPU's RGBA8 -> YCbCr 4:2:0 conversion (shaders/render/yuv420.comp), which the service's
// streams read back instead of RGBA8: its planes equal the CPU reference (encode::to_yuv420)
// computed from the same frame's RGBA8 image, at a size with partial 8x2 blocks and chroma
// pairs on both edges (the padding column and row included).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "encode/image.h"
#include "gpu_scene/gpu_scene.h"
#include "render/renderer.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"

namespace ddgi::test {
namespace {

class Yuv420Test : public GpuTest {};

struct PlaneDifference {
  int max = 0;           // largest difference in code values
  size_t differing = 0;  // samples that differ at all
  size_t samples = 0;
  int min_value = 255;  // the GPU plane's range: a constant plane proves nothing
  int max_value = 0;
};

// One plane of `width` x `rows` samples, `gpu_stride` and `cpu_stride` bytes per row.
PlaneDifference compare_plane(const uint8_t* gpu, uint32_t gpu_stride, const uint8_t* cpu,
                              uint32_t cpu_stride, uint32_t width, uint32_t rows) {
  PlaneDifference d;
  for (uint32_t y = 0; y < rows; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const int g = gpu[size_t{y} * gpu_stride + x], c = cpu[size_t{y} * cpu_stride + x];
      d.max = std::max(d.max, std::abs(g - c));
      d.differing += g != c ? 1 : 0;
      d.min_value = std::min(d.min_value, g);
      d.max_value = std::max(d.max_value, g);
      ++d.samples;
    }
  }
  return d;
}

// Both planes come from one frame: the renderer converts and reads back the YUV planes, then
// the test copies the same frame's RGBA8 image back too and converts it on the CPU. The kernel
// and the reference do the same float arithmetic, so only the GPU's rounding (fused
// multiply-adds) could move a sample by one code. Measured on lavapipe: every sample equal
// (Y 0 to 255, Cb 88 to 128, Cr 96 to 201).
TEST_F(Yuv420Test, PlanesEqualTheCpuConversionOfTheSameFrame) {
  const Scene scene = make_cornell_box();
  auto gpu_scene = GpuScene::create(context(), scene);
  ASSERT_TRUE(gpu_scene.ok()) << gpu_scene.error().message;
  auto renderer = Renderer::create(context(), **gpu_scene, nullptr, vk::TraceBackend::kRayQuery);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  FrameSettings settings;
  settings.width = 37;   // Y rows padded to 40 bytes, 19 chroma columns (the last one half)
  settings.height = 23;  // 24 Y rows in the buffer, 12 chroma rows (the last one half)
  settings.camera = scene.cameras[0];
  settings.read_radiance = false;
  settings.read_yuv420 = true;
  auto target = FrameTarget::create(context(), settings.width, settings.height);
  ASSERT_TRUE(target.ok()) << target.error().message;
  auto frame = (*renderer)->render(settings, **target);
  ASSERT_TRUE(frame.ok()) << frame.error().message;
  EXPECT_TRUE(frame->ldr.empty()) << "RGBA8 is not read back when the planes are";
  const gpu::Yuv420Layout& layout = frame->yuv420_layout;
  ASSERT_EQ(frame->yuv420.size(), layout.total_bytes);
  EXPECT_EQ(layout.y_stride, 40u);
  EXPECT_EQ(layout.y_rows, 24u);

  const vk::Pass copy_rgba8 = (*target)->images().readback_pass(false);
  ASSERT_TRUE(context()
                  .submit_and_wait([&](VkCommandBuffer cmd) {
                    vk::record_passes(cmd, nullptr, std::span(&copy_rgba8, 1));
                  })
                  .ok());
  const encode::ImageYuv420 reference = encode::to_yuv420(
      encode::ImageRgba8{settings.width, settings.height, (*target)->images().read_ldr()});

  const uint8_t* planes = frame->yuv420.data();
  const uint8_t* cpu = reference.bytes.data();
  const uint32_t chroma_width = (settings.width + 1) / 2, chroma_rows = (settings.height + 1) / 2;
  // Y with its padding column and row (libjpeg-turbo reads them into the edge's DCT blocks).
  const PlaneDifference y = compare_plane(planes, layout.y_stride, cpu, reference.y_stride,
                                          chroma_width * 2, chroma_rows * 2);
  const PlaneDifference cb =
      compare_plane(planes + layout.cb_offset, layout.chroma_stride, cpu + reference.cb_offset,
                    reference.chroma_stride, chroma_width, chroma_rows);
  const PlaneDifference cr =
      compare_plane(planes + layout.cr_offset, layout.chroma_stride, cpu + reference.cr_offset,
                    reference.chroma_stride, chroma_width, chroma_rows);
  for (const auto& [name, d] : {std::pair{"Y", y}, std::pair{"Cb", cb}, std::pair{"Cr", cr}}) {
    std::printf("%s: %zu of %zu samples differ, by at most %d; GPU values %d to %d\n", name,
                d.differing, d.samples, d.max, d.min_value, d.max_value);
    EXPECT_LE(d.max, 1) << name;
    EXPECT_LE(d.differing, d.samples / 100) << name;
  }
  // Not trivial: a lit box with a red and a green wall has bright and dark luma and chroma on
  // both sides of grey (128).
  EXPECT_GT(y.max_value - y.min_value, 100);
  EXPECT_LT(cr.min_value, 120);
  EXPECT_GT(cr.max_value, 136);
  EXPECT_LT(cb.min_value, 120);
}

}  // namespace
}  // namespace ddgi::test
