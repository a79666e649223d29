// Frame targets and image buffers (render/frame_target.h).
#include "render/frame_target.h"

#include <cstring>

#include "shared/frame_data.h"

namespace ddgi {
namespace {

// Field updates + shadow-field updates (up to 64 each per frame) + frame passes.
constexpr uint32_t kMaxTimedPasses = 5 * 64 + 4 * 64 + 8;

}  // namespace

Status validate_image_size(uint32_t width, uint32_t height) {
  if (width < 1 || width > kMaxImageDimension || height < 1 || height > kMaxImageDimension) {
    return invalid_argument("image size " + std::to_string(width) + "x" + std::to_string(height) +
                            " is out of range: each side must be in [1, " +
                            std::to_string(kMaxImageDimension) + "]");
  }
  return ok_status();
}

Result<ImageBuffers> ImageBuffers::create(vk::Context& context, uint32_t width, uint32_t height,
                                          const std::string& label) {
  DDGI_TRY(validate_image_size(width, height));
  const VkDeviceSize pixels = VkDeviceSize(width) * height;
  const VkBufferUsageFlags usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  ImageBuffers b;
  b.width = width;
  b.height = height;
  DDGI_ASSIGN_OR_RETURN(
      b.radiance, vk::Buffer::create(context, pixels * 16, usage, vk::MemoryUsage::kDeviceLocal,
                                     label + " radiance"));
  DDGI_ASSIGN_OR_RETURN(b.ldr, vk::Buffer::create(context, pixels * 4, usage,
                                                  vk::MemoryUsage::kDeviceLocal, label + " ldr"));
  DDGI_ASSIGN_OR_RETURN(
      b.radiance_readback,
      vk::Buffer::create(context, pixels * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         vk::MemoryUsage::kReadback, label + " radiance readback"));
  DDGI_ASSIGN_OR_RETURN(b.ldr_readback,
                        vk::Buffer::create(context, pixels * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           vk::MemoryUsage::kReadback, label + " ldr readback"));
  return b;
}

vk::Pass ImageBuffers::readback_pass(bool with_radiance) const {
  vk::Pass pass;
  pass.name = "readback";
  pass.group = vk::PassGroup::kReadback;
  pass.reads = {&ldr};
  pass.writes = {&ldr_readback};
  if (with_radiance) {
    pass.reads.push_back(&radiance);
    pass.writes.push_back(&radiance_readback);
  }
  const VkBuffer hdr = radiance.handle(), hdr_host = radiance_readback.handle();
  const VkBuffer ldr8 = ldr.handle(), ldr8_host = ldr_readback.handle();
  const VkBufferCopy hdr_copy{0, 0, radiance.size()}, ldr_copy{0, 0, ldr.size()};
  pass.commands = [=](VkCommandBuffer cmd) {
    if (with_radiance) vkCmdCopyBuffer(cmd, hdr, hdr_host, 1, &hdr_copy);
    vkCmdCopyBuffer(cmd, ldr8, ldr8_host, 1, &ldr_copy);
  };
  return pass;
}

std::vector<float> ImageBuffers::read_radiance() const {
  std::vector<float> pixels(size_t(width) * height * 4);
  std::memcpy(pixels.data(), radiance_readback.mapped(), pixels.size() * sizeof(float));
  return pixels;
}

std::vector<uint8_t> ImageBuffers::read_ldr() const {
  std::vector<uint8_t> pixels(size_t(width) * height * 4);
  std::memcpy(pixels.data(), ldr_readback.mapped(), pixels.size());
  return pixels;
}

std::vector<vk::Binding> frame_set_bindings() {
  return {{gpu::kFrameBindingGBuffer}, {gpu::kFrameBindingRadiance}, {gpu::kFrameBindingLdr}};
}

Result<std::unique_ptr<FrameTarget>> FrameTarget::create(vk::Context& context, uint32_t width,
                                                         uint32_t height) {
  DDGI_TRY(validate_image_size(width, height));
  std::unique_ptr<FrameTarget> target(new FrameTarget());
  DDGI_ASSIGN_OR_RETURN(target->layout_, vk::DescriptorLayout::create(context, frame_set_bindings(),
                                                                      1, "frame target set"));
  DDGI_ASSIGN_OR_RETURN(target->frame_set_, target->layout_.allocate());
  const VkDeviceSize pixels = VkDeviceSize(width) * height;
  DDGI_ASSIGN_OR_RETURN(
      target->gbuffer_,
      vk::Buffer::create(context, pixels * sizeof(gpu::GBufferTexel),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                         vk::MemoryUsage::kDeviceLocal, "gbuffer"));
  DDGI_ASSIGN_OR_RETURN(target->images_, ImageBuffers::create(context, width, height, "frame"));
  DDGI_ASSIGN_OR_RETURN(target->timer_, vk::GpuTimer::create(context, kMaxTimedPasses));
  DDGI_ASSIGN_OR_RETURN(target->commands_, vk::CommandSlot::create(context, "frame commands"));
  vk::DescriptorWriter(target->frame_set_)
      .buffer(gpu::kFrameBindingGBuffer, target->gbuffer_)
      .buffer(gpu::kFrameBindingRadiance, target->images_.radiance)
      .buffer(gpu::kFrameBindingLdr, target->images_.ldr)
      .apply(context.device());
  return target;
}

}  // namespace ddgi
