// Where frames are drawn: the per-view GPU buffers of one image size. ImageBuffers are the HDR
// radiance and RGBA8 images with their host-visible copies (the renderer's frames and the path
// tracer's accumulations both end in them); a FrameTarget adds the G-buffer, the frame
// descriptor set that binds them, the timer of the frames drawn into it and the command buffer
// they are recorded into (with its fence), so a frame can be submitted into one target while
// another target's frame is still on the GPU. The Renderer's kernels are built once per scene;
// every view of a session has two FrameTargets, its frames alternating between them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "shared/frame_data.h"
#include "vk/command_slot.h"
#include "vk/context.h"
#include "vk/pass.h"
#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace ddgi {

// Image size bounds shared by frames and path-traced images: 1..16384 pixels per side.
constexpr uint32_t kMaxImageDimension = 16384;
Status validate_image_size(uint32_t width, uint32_t height);

struct ImageBuffers {
  uint32_t width = 0;
  uint32_t height = 0;
  vk::Buffer radiance;  // RGBA32F per pixel, linear HDR
  vk::Buffer ldr;       // RGBA8 per pixel, tone-mapped sRGB
  vk::Buffer radiance_readback;
  vk::Buffer ldr_readback;

  // `label` names the buffers for the budget and debug tools ("frame", "path-traced").
  static Result<ImageBuffers> create(vk::Context& context, uint32_t width, uint32_t height,
                                     const std::string& label);
  // The copies to the host-visible buffers (the HDR one only when `radiance`).
  vk::Pass readback_pass(bool radiance) const;
  // After the readback pass completed: the images, row 0 = top.
  std::vector<float> read_radiance() const;
  std::vector<uint8_t> read_ldr() const;
};

// Where the Y, Cb and Cr planes of a width x height image lie in the YUV 4:2:0 buffer.
gpu::Yuv420Layout yuv420_layout(uint32_t width, uint32_t height);

// The bindings of the frame descriptor set (set 1 of frame kernels, shaders/shared/frame_data.h).
std::vector<vk::Binding> frame_set_bindings();

class FrameTarget {
 public:
  static Result<std::unique_ptr<FrameTarget>> create(vk::Context& context, uint32_t width,
                                                     uint32_t height);
  uint32_t width() const { return images_.width; }
  uint32_t height() const { return images_.height; }
  const ImageBuffers& images() const { return images_; }
  const vk::Buffer& gbuffer() const { return gbuffer_; }
  const vk::Buffer& yuv420() const { return yuv420_; }
  const gpu::Yuv420Layout& yuv420_layout() const { return yuv420_layout_; }
  // The copies to the host of what a frame hands on: the HDR image when `radiance`, and the
  // 8-bit image as RGBA8 or, when `yuv420`, as the YUV planes.
  vk::Pass readback_pass(bool radiance, bool yuv420) const;
  // After a readback pass with `yuv420` completed: the planes, yuv420_layout() apart.
  std::vector<uint8_t> read_yuv420() const;
  VkDescriptorSet frame_set() const { return frame_set_; }
  vk::GpuTimer& timer() { return timer_; }
  vk::CommandSlot& commands() { return commands_; }
  // Frames drawn into this target so far (FrameResult::frame_index).
  uint64_t next_frame_index() { return frame_index_++; }
  // A frame was submitted into it and not yet finished (read back, or dropped): until then
  // neither its buffers nor its timer may be reused (Renderer::submit refuses it).
  bool busy() const { return busy_; }
  void set_busy(bool busy) { busy_ = busy; }

 private:
  FrameTarget() = default;

  vk::DescriptorLayout layout_;  // identical to the Renderer's frame layout, so compatible
  VkDescriptorSet frame_set_ = VK_NULL_HANDLE;
  vk::Buffer gbuffer_;
  ImageBuffers images_;
  gpu::Yuv420Layout yuv420_layout_{};
  vk::Buffer yuv420_;  // the 8-bit image as YUV 4:2:0 planes (yuv420.comp)
  vk::Buffer yuv420_readback_;
  vk::GpuTimer timer_;
  uint64_t frame_index_ = 0;
  bool busy_ = false;
  vk::CommandSlot commands_;  // last: destroyed first, it waits for a frame still in flight
};

}  // namespace ddgi
