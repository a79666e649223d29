// Frame targets and image buffers (render/frame_target.h).
#include "render/frame_target.h"

#include <cstring>

#include "shared/frame_data.h"

namespace ddgi {
namespace {

// Field updates + shadow-field updates (up to 64 each per frame) + frame passes.
constexpr uint32_t kMaxTimedPasses = 5 * 64 + 4 * 64 + 8;

struct BufferCopy {
  const vk::Buffer* from;
  const vk::Buffer* to;  // host-visible, at least as large
};

// One pass copying whole buffers to the host.
vk::Pass readback(const std::vector<BufferCopy>& copies) {
  vk::Pass pass;
  pass.name = "readback";
  pass.group = vk::PassGroup::kReadback;
  std::vector<std::pair<VkBuffer, VkBuffer>> handles;
  std::vector<VkBufferCopy> regions;
  for (const BufferCopy& copy : copies) {
    pass.reads.push_back(copy.from);
    pass.writes.push_back(copy.to);
    handles.emplace_back(copy.from->handle(), copy.to->handle());
    regions.push_back({0, 0, copy.from->size()});
  }
  pass.commands = [handles, regions](VkCommandBuffer cmd) {
    for (size_t i = 0; i < handles.size(); ++i) {
      vkCmdCopyBuffer(cmd, handles[i].first, handles[i].second, 1, &regions[i]);
    }
  };
  return pass;
}

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
  std::vector<BufferCopy> copies = {{&ldr, &ldr_readback}};
  if (with_radiance) copies.push_back({&radiance, &radiance_readback});
  return readback(copies);
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

gpu::Yuv420Layout yuv420_layout(uint32_t width, uint32_t height) {
  gpu::Yuv420Layout layout{};
  layout.width = width;
  layout.height = height;
  layout.y_stride = (width + 7) / 8 * 8;
  layout.chroma_stride = layout.y_stride / 2;
  layout.y_rows = (height + 1) / 2 * 2;
  const uint32_t chroma_plane = layout.chroma_stride * layout.y_rows / 2;
  layout.cb_offset = layout.y_stride * layout.y_rows;
  layout.cr_offset = layout.cb_offset + chroma_plane;
  layout.total_bytes = layout.cr_offset + chroma_plane;
  return layout;
}

std::vector<vk::Binding> frame_set_bindings() {
  return {{gpu::kFrameBindingGBuffer},
          {gpu::kFrameBindingRadiance},
          {gpu::kFrameBindingLdr},
          {gpu::kFrameBindingYuv420}};
}

vk::Pass FrameTarget::readback_pass(bool radiance, bool yuv420) const {
  if (!yuv420) return images_.readback_pass(radiance);
  std::vector<BufferCopy> copies = {{&yuv420_, &yuv420_readback_}};
  if (radiance) copies.push_back({&images_.radiance, &images_.radiance_readback});
  return readback(copies);
}

std::vector<uint8_t> FrameTarget::read_yuv420() const {
  const auto* bytes = static_cast<const uint8_t*>(yuv420_readback_.mapped());
  return std::vector<uint8_t>(bytes, bytes + yuv420_layout_.total_bytes);
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
  target->yuv420_layout_ = ddgi::yuv420_layout(width, height);
  const VkDeviceSize yuv420_bytes = target->yuv420_layout_.total_bytes;
  DDGI_ASSIGN_OR_RETURN(
      target->yuv420_,
      vk::Buffer::create(context, yuv420_bytes,
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                         vk::MemoryUsage::kDeviceLocal, "frame yuv420"));
  DDGI_ASSIGN_OR_RETURN(target->yuv420_readback_,
                        vk::Buffer::create(context, yuv420_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           vk::MemoryUsage::kReadback, "frame yuv420 readback"));
  DDGI_ASSIGN_OR_RETURN(target->timer_, vk::GpuTimer::create(context, kMaxTimedPasses));
  DDGI_ASSIGN_OR_RETURN(target->commands_, vk::CommandSlot::create(context, "frame commands"));
  vk::DescriptorWriter(target->frame_set_)
      .buffer(gpu::kFrameBindingGBuffer, target->gbuffer_)
      .buffer(gpu::kFrameBindingRadiance, target->images_.radiance)
      .buffer(gpu::kFrameBindingLdr, target->images_.ldr)
      .buffer(gpu::kFrameBindingYuv420, target->yuv420_)
      .apply(context.device());
  return target;
}

}  // namespace ddgi
