#include "vk/resources.h"

#include <cstring>
#include <utility>

#include "vk/check.h"

namespace ddgi::vk {
namespace {

VkMemoryPropertyFlags required_flags(MemoryUsage usage) {
  switch (usage) {
    case MemoryUsage::kDeviceLocal:
      return VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    case MemoryUsage::kUpload:
    case MemoryUsage::kDeviceUpload:
    case MemoryUsage::kReadback:
      return VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  }
  return 0;
}

VkMemoryPropertyFlags preferred_flags(MemoryUsage usage) {
  switch (usage) {
    case MemoryUsage::kReadback:
      return VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
    case MemoryUsage::kDeviceUpload:
      return VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    default:
      return 0;
  }
}

}  // namespace

Result<Buffer> Buffer::create(Context& context, VkDeviceSize size, VkBufferUsageFlags usage,
                              MemoryUsage memory_usage, const std::string& name) {
  if (size == 0) size = 16;  // empty scene arrays still need a bindable buffer
  Buffer buffer;
  buffer.context_ = &context;
  buffer.size_ = size;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VK_TRY(vkCreateBuffer(context.device(), &info, nullptr, &buffer.buffer_));
  context.set_name(reinterpret_cast<uint64_t>(buffer.buffer_), VK_OBJECT_TYPE_BUFFER, name);

  VkMemoryRequirements requirements{};
  vkGetBufferMemoryRequirements(context.device(), buffer.buffer_, &requirements);
  DDGI_TRY(context.reserve_memory(requirements.size, "buffer '" + name + "'"));
  buffer.allocation_size_ = requirements.size;
  DDGI_ASSIGN_OR_RETURN(uint32_t type, context.find_memory_type(requirements.memoryTypeBits,
                                                                required_flags(memory_usage),
                                                                preferred_flags(memory_usage)));
  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.pNext = &flags;
  alloc.allocationSize = requirements.size;
  alloc.memoryTypeIndex = type;
  VK_TRY_AT(context, FaultSite::kAllocateMemory,
            vkAllocateMemory(context.device(), &alloc, nullptr, &buffer.memory_));
  VK_TRY(vkBindBufferMemory(context.device(), buffer.buffer_, buffer.memory_, 0));
  if (memory_usage != MemoryUsage::kDeviceLocal) {
    VK_TRY(vkMapMemory(context.device(), buffer.memory_, 0, VK_WHOLE_SIZE, 0, &buffer.mapped_));
  }
  VkBufferDeviceAddressInfo address{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  address.buffer = buffer.buffer_;
  buffer.address_ = vkGetBufferDeviceAddress(context.device(), &address);
  return buffer;
}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(other.size_, 0);
    allocation_size_ = std::exchange(other.allocation_size_, 0);
    address_ = std::exchange(other.address_, 0);
    mapped_ = std::exchange(other.mapped_, nullptr);
  }
  return *this;
}

void Buffer::reset() {
  if (!context_) return;
  // A buffer whose creation failed half way still releases what it got.
  if (allocation_size_) context_->release_memory(allocation_size_);
  VkDevice device = context_->device();
  VkBuffer buffer = buffer_;
  VkDeviceMemory memory = memory_;
  context_->defer_destroy([device, buffer, memory] {
    if (buffer) vkDestroyBuffer(device, buffer, nullptr);
    if (memory) vkFreeMemory(device, memory, nullptr);
  });
  context_ = nullptr;
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  size_ = allocation_size_ = 0;
  address_ = 0;
  mapped_ = nullptr;
}

Result<Image> Image::create_2d(Context& context, uint32_t width, uint32_t height, VkFormat format,
                               VkImageUsageFlags usage, const std::string& name) {
  Image image;
  image.context_ = &context;
  image.format_ = format;
  image.width_ = width;
  image.height_ = height;
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width, height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VK_TRY(vkCreateImage(context.device(), &info, nullptr, &image.image_));
  context.set_name(reinterpret_cast<uint64_t>(image.image_), VK_OBJECT_TYPE_IMAGE, name);

  VkMemoryRequirements requirements{};
  vkGetImageMemoryRequirements(context.device(), image.image_, &requirements);
  DDGI_TRY(context.reserve_memory(requirements.size, "image '" + name + "'"));
  image.allocation_size_ = requirements.size;
  DDGI_ASSIGN_OR_RETURN(
      uint32_t type,
      context.find_memory_type(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT));
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = requirements.size;
  alloc.memoryTypeIndex = type;
  VK_TRY_AT(context, FaultSite::kAllocateMemory,
            vkAllocateMemory(context.device(), &alloc, nullptr, &image.memory_));
  VK_TRY(vkBindImageMemory(context.device(), image.image_, image.memory_, 0));

  VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view.image = image.image_;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = format;
  view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  VK_TRY(vkCreateImageView(context.device(), &view, nullptr, &image.view_));
  context.set_name(reinterpret_cast<uint64_t>(image.view_), VK_OBJECT_TYPE_IMAGE_VIEW,
                   name + " view");
  return image;
}

Image& Image::operator=(Image&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    image_ = std::exchange(other.image_, VK_NULL_HANDLE);
    view_ = std::exchange(other.view_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    allocation_size_ = std::exchange(other.allocation_size_, 0);
    format_ = std::exchange(other.format_, VK_FORMAT_UNDEFINED);
    width_ = std::exchange(other.width_, 0);
    height_ = std::exchange(other.height_, 0);
  }
  return *this;
}

void Image::reset() {
  if (!context_) return;
  if (allocation_size_) context_->release_memory(allocation_size_);
  VkDevice device = context_->device();
  VkImage image = image_;
  VkImageView view = view_;
  VkDeviceMemory memory = memory_;
  context_->defer_destroy([device, image, view, memory] {
    if (view) vkDestroyImageView(device, view, nullptr);
    if (image) vkDestroyImage(device, image, nullptr);
    if (memory) vkFreeMemory(device, memory, nullptr);
  });
  context_ = nullptr;
  image_ = VK_NULL_HANDLE;
  view_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  allocation_size_ = 0;
}

Result<Sampler> Sampler::create(Context& context, VkFilter filter, VkSamplerAddressMode address_u,
                                VkSamplerAddressMode address_v, const std::string& name) {
  Sampler sampler;
  sampler.context_ = &context;
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = filter;
  info.minFilter = filter;
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  info.addressModeU = address_u;
  info.addressModeV = address_v;
  info.addressModeW = address_v;
  info.maxLod = 0.0f;
  VK_TRY(vkCreateSampler(context.device(), &info, nullptr, &sampler.sampler_));
  context.set_name(reinterpret_cast<uint64_t>(sampler.sampler_), VK_OBJECT_TYPE_SAMPLER, name);
  return sampler;
}

Sampler& Sampler::operator=(Sampler&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    sampler_ = std::exchange(other.sampler_, VK_NULL_HANDLE);
  }
  return *this;
}

void Sampler::reset() {
  if (!context_) return;
  VkDevice device = context_->device();
  VkSampler sampler = sampler_;
  context_->defer_destroy([device, sampler] {
    if (sampler) vkDestroySampler(device, sampler, nullptr);
  });
  context_ = nullptr;
  sampler_ = VK_NULL_HANDLE;
}

Result<Buffer> upload_buffer(Context& context, std::span<const uint8_t> bytes,
                             VkBufferUsageFlags usage, const std::string& name) {
  DDGI_ASSIGN_OR_RETURN(
      Buffer buffer, Buffer::create(context, bytes.size(), usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                    MemoryUsage::kDeviceLocal, name));
  if (bytes.empty()) return buffer;
  DDGI_ASSIGN_OR_RETURN(Buffer staging,
                        Buffer::create(context, bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                       MemoryUsage::kUpload, name + " staging"));
  std::memcpy(staging.mapped(), bytes.data(), bytes.size());
  DDGI_TRY(context.submit_and_wait([&](VkCommandBuffer cmd) {
    VkBufferCopy copy{0, 0, bytes.size()};
    vkCmdCopyBuffer(cmd, staging.handle(), buffer.handle(), 1, &copy);
  }));
  return buffer;
}

Status update_buffer(Context& context, const Buffer& buffer, std::span<const uint8_t> bytes) {
  if (bytes.empty()) return ok_status();
  if (bytes.size() > buffer.size()) {
    return internal_error("update of " + std::to_string(bytes.size()) + " bytes exceeds a " +
                          std::to_string(buffer.size()) + "-byte buffer");
  }
  DDGI_ASSIGN_OR_RETURN(Buffer staging,
                        Buffer::create(context, bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                       MemoryUsage::kUpload, "update staging"));
  std::memcpy(staging.mapped(), bytes.data(), bytes.size());
  return context.submit_and_wait([&](VkCommandBuffer cmd) {
    VkBufferCopy copy{0, 0, bytes.size()};
    vkCmdCopyBuffer(cmd, staging.handle(), buffer.handle(), 1, &copy);
  });
}

Status upload_image(Context& context, Image& image, std::span<const uint8_t> texels,
                    VkImageLayout final_layout) {
  DDGI_ASSIGN_OR_RETURN(Buffer staging,
                        Buffer::create(context, texels.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                       MemoryUsage::kUpload, "image staging"));
  std::memcpy(staging.mapped(), texels.data(), texels.size());
  return context.submit_and_wait([&](VkCommandBuffer cmd) {
    transition_image(cmd, image.handle(), VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {image.width(), image.height(), 1};
    vkCmdCopyBufferToImage(cmd, staging.handle(), image.handle(),
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    transition_image(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, final_layout);
  });
}

Status download_buffer(Context& context, const Buffer& buffer, void* out, VkDeviceSize size) {
  DDGI_ASSIGN_OR_RETURN(Buffer readback,
                        Buffer::create(context, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                       MemoryUsage::kReadback, "readback"));
  DDGI_TRY(context.submit_and_wait([&](VkCommandBuffer cmd) {
    barrier_all(cmd);
    VkBufferCopy copy{0, 0, size};
    vkCmdCopyBuffer(cmd, buffer.handle(), readback.handle(), 1, &copy);
  }));
  std::memcpy(out, readback.mapped(), size);
  return ok_status();
}

Status download_image(Context& context, const Image& image, void* out, VkDeviceSize size,
                      VkImageLayout layout) {
  const VkDeviceSize expected =
      VkDeviceSize(image.width()) * image.height() * texel_bytes(image.format());
  if (expected == 0 || size != expected) {
    return internal_error("download of " + std::to_string(size) + " bytes from a " +
                          std::to_string(image.width()) + "x" + std::to_string(image.height()) +
                          " image of format " + std::to_string(int(image.format())) +
                          " (expected " + std::to_string(expected) + ")");
  }
  DDGI_ASSIGN_OR_RETURN(Buffer readback,
                        Buffer::create(context, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                       MemoryUsage::kReadback, "image readback"));
  DDGI_TRY(context.submit_and_wait([&](VkCommandBuffer cmd) {
    barrier_all(cmd);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {image.width(), image.height(), 1};
    vkCmdCopyImageToBuffer(cmd, image.handle(), layout, readback.handle(), 1, &copy);
  }));
  std::memcpy(out, readback.mapped(), size);
  return ok_status();
}

uint32_t texel_bytes(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
      return 4;
    default:
      return 4 * float_channels(format);
  }
}

uint32_t float_channels(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R32_SFLOAT:
      return 1;
    case VK_FORMAT_R32G32_SFLOAT:
      return 2;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
      return 4;
    default:
      return 0;
  }
}

void barrier_all(VkCommandBuffer cmd) {
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                          VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
  barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                          VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                          VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void transition_image(VkCommandBuffer cmd, VkImage image, VkImageLayout old_layout,
                      VkImageLayout new_layout) {
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                          VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.oldLayout = old_layout;
  barrier.newLayout = new_layout;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0,
                              VK_REMAINING_ARRAY_LAYERS};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       0, 0, nullptr, 0, nullptr, 1, &barrier);
}

}  // namespace ddgi::vk
