// RAII GPU resources. Every object has a debug name, counts against the context's memory
// budget, and is destroyed through Context::defer_destroy so that dropping it never races
// the GPU. Move-only.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <string>

#include "core/result.h"
#include "vk/context.h"

namespace ddgi::vk {

enum class MemoryUsage {
  kDeviceLocal,  // GPU only
  kUpload,       // host-visible, coherent: CPU writes, GPU reads (once: staging, builds)
  // host-visible, coherent, and device-local where the GPU has such memory (resizable BAR):
  // small buffers the CPU writes and shaders read over and over (the probe list every probe
  // ray looks up, shader binding tables), which would otherwise be read across the bus
  kDeviceUpload,
  kReadback,  // host-visible, cached: GPU writes, CPU reads
};

class Buffer {
 public:
  Buffer() = default;
  static Result<Buffer> create(Context& context, VkDeviceSize size, VkBufferUsageFlags usage,
                               MemoryUsage memory, const std::string& name);
  ~Buffer() { reset(); }
  Buffer(Buffer&& other) noexcept { *this = std::move(other); }
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  void reset();
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }
  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  VkDeviceAddress address() const { return address_; }
  // Host pointer for kUpload / kReadback buffers (nullptr for device-local ones).
  void* mapped() const { return mapped_; }
  VkDescriptorBufferInfo descriptor() const { return {buffer_, 0, VK_WHOLE_SIZE}; }

 private:
  Context* context_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  VkDeviceSize allocation_size_ = 0;
  VkDeviceAddress address_ = 0;
  void* mapped_ = nullptr;
};

class Image {
 public:
  Image() = default;
  static Result<Image> create_2d(Context& context, uint32_t width, uint32_t height, VkFormat format,
                                 VkImageUsageFlags usage, const std::string& name);
  ~Image() { reset(); }
  Image(Image&& other) noexcept { *this = std::move(other); }
  Image& operator=(Image&& other) noexcept;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  void reset();
  explicit operator bool() const { return image_ != VK_NULL_HANDLE; }
  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }
  VkFormat format() const { return format_; }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  uint64_t bytes() const { return allocation_size_; }

 private:
  Context* context_ = nullptr;
  VkImage image_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize allocation_size_ = 0;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  uint32_t width_ = 0;
  uint32_t height_ = 0;
};

class Sampler {
 public:
  Sampler() = default;
  static Result<Sampler> create(Context& context, VkFilter filter, VkSamplerAddressMode address_u,
                                VkSamplerAddressMode address_v, const std::string& name);
  ~Sampler() { reset(); }
  Sampler(Sampler&& other) noexcept { *this = std::move(other); }
  Sampler& operator=(Sampler&& other) noexcept;
  Sampler(const Sampler&) = delete;
  Sampler& operator=(const Sampler&) = delete;
  void reset();
  VkSampler handle() const { return sampler_; }

 private:
  Context* context_ = nullptr;
  VkSampler sampler_ = VK_NULL_HANDLE;
};

// Creates a device-local buffer holding `bytes` (through a staging copy).
Result<Buffer> upload_buffer(Context& context, std::span<const uint8_t> bytes,
                             VkBufferUsageFlags usage, const std::string& name);
template <typename T>
Result<Buffer> upload_vector(Context& context, std::span<const T> items, VkBufferUsageFlags usage,
                             const std::string& name) {
  return upload_buffer(
      context, {reinterpret_cast<const uint8_t*>(items.data()), items.size_bytes()}, usage, name);
}

// Fills an image from tightly packed texels (staging copy), leaving it in `final_layout`.
Status upload_image(Context& context, Image& image, std::span<const uint8_t> texels,
                    VkImageLayout final_layout);

// Overwrites the start of a device-local buffer with `bytes` (through a staging copy).
Status update_buffer(Context& context, const Buffer& buffer, std::span<const uint8_t> bytes);

// Copies a device buffer into host memory.
Status download_buffer(Context& context, const Buffer& buffer, void* out, VkDeviceSize size);
// Copies a whole 2D colour image (mip 0, layer 0), tightly packed, into host memory after every
// earlier GPU write; `size` must be width x height x texel_bytes(format). The image stays in
// `layout` (GENERAL: storage images such as the fields' atlases).
Status download_image(Context& context, const Image& image, void* out, VkDeviceSize size,
                      VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL);
// Bytes per texel of the colour formats images are made with here; 0 for any other format.
uint32_t texel_bytes(VkFormat format);
// Channels of a 32-bit float colour format (R32, RG32, RGBA32 SFLOAT); 0 for any other format.
uint32_t float_channels(VkFormat format);

// A full pipeline barrier between compute / ray-tracing / transfer writes and reads.
void barrier_all(VkCommandBuffer cmd);
// Moves every mip/layer of `image` from `old_layout` to `new_layout`.
void transition_image(VkCommandBuffer cmd, VkImage image, VkImageLayout old_layout,
                      VkImageLayout new_layout);

}  // namespace ddgi::vk
