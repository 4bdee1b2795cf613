#include "engine/vk/Resources.h"

#include <stdexcept>
#include <string>

#include "engine/vk/Check.h"

namespace vkr::vk {
namespace {

VkDeviceMemory Allocate(Device& device, const VkMemoryRequirements& req, MemoryUse use) {
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = device.FindMemoryType(req.memoryTypeBits, use);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateMemory(device.handle(), &ai, nullptr, &memory));
  device.CountAllocation(int64_t(req.size));
  return memory;
}

}  // namespace

uint32_t BytesPerTexel(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R8_UNORM:
      return 1;
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_R32_UINT:
      return 4;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R32G32_SFLOAT:
    case VK_FORMAT_R32G32_UINT:
      return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
      return 16;
    default:
      throw std::invalid_argument("BytesPerTexel: unsupported format " + std::to_string(int(format)));
  }
}

bool IsDepthFormat(VkFormat format) { return format == VK_FORMAT_D32_SFLOAT; }

Buffer::Buffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use)
    : device_(&device), size_(size) {
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = size;
  bi.usage = usage;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VK_CHECK(vkCreateBuffer(device.handle(), &bi, nullptr, &buffer_));
  try {
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device.handle(), buffer_, &req);
    memory_ = Allocate(device, req, use);
    allocated_ = req.size;
    VK_CHECK(vkBindBufferMemory(device.handle(), buffer_, memory_, 0));
    if (use != MemoryUse::Device)
      VK_CHECK(vkMapMemory(device.handle(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
  } catch (...) {
    Release();
    throw;
  }
}

Buffer::~Buffer() { Release(); }

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    Release();
    device_ = o.device_;
    buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
    size_ = o.size_;
    allocated_ = std::exchange(o.allocated_, 0);
    mapped_ = std::exchange(o.mapped_, nullptr);
  }
  return *this;
}

void Buffer::Release() {
  if (!device_) return;
  if (buffer_) vkDestroyBuffer(device_->handle(), buffer_, nullptr);
  if (memory_) {
    vkFreeMemory(device_->handle(), memory_, nullptr);  // unmaps implicitly
    device_->CountAllocation(-int64_t(allocated_));
  }
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  allocated_ = 0;
}

GpuImage::GpuImage(Device& device, const GpuImageInfo& info) : device_(&device), info_(info) {
  VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ii.imageType = VK_IMAGE_TYPE_2D;
  ii.format = info.format;
  ii.extent = {info.width, info.height, 1};
  ii.mipLevels = info.mip_levels;
  ii.arrayLayers = info.layers;
  ii.samples = VK_SAMPLE_COUNT_1_BIT;
  ii.tiling = VK_IMAGE_TILING_OPTIMAL;
  ii.usage = info.usage;
  ii.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VK_CHECK(vkCreateImage(device.handle(), &ii, nullptr, &image_));
  try {
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device.handle(), image_, &req);
    memory_ = Allocate(device, req, MemoryUse::Device);
    allocated_ = req.size;
    VK_CHECK(vkBindImageMemory(device.handle(), image_, memory_, 0));
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = image_;
    vi.viewType = info.layers > 1 || info.array_view ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
    vi.format = info.format;
    vi.subresourceRange = {aspect(), 0, info.mip_levels, 0, info.layers};
    VK_CHECK(vkCreateImageView(device.handle(), &vi, nullptr, &view_));
  } catch (...) {
    Release();
    throw;
  }
}

GpuImage::~GpuImage() { Release(); }

GpuImage& GpuImage::operator=(GpuImage&& o) noexcept {
  if (this != &o) {
    Release();
    device_ = o.device_;
    info_ = o.info_;
    image_ = std::exchange(o.image_, VK_NULL_HANDLE);
    view_ = std::exchange(o.view_, VK_NULL_HANDLE);
    memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
    allocated_ = std::exchange(o.allocated_, 0);
  }
  return *this;
}

void GpuImage::Release() {
  if (!device_) return;
  if (view_) vkDestroyImageView(device_->handle(), view_, nullptr);
  if (image_) vkDestroyImage(device_->handle(), image_, nullptr);
  if (memory_) {
    vkFreeMemory(device_->handle(), memory_, nullptr);
    device_->CountAllocation(-int64_t(allocated_));
  }
  view_ = VK_NULL_HANDLE;
  image_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  allocated_ = 0;
}

VkImageAspectFlags GpuImage::aspect() const {
  return IsDepthFormat(info_.format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

VkDeviceSize GpuImage::layer_bytes() const {
  return VkDeviceSize(info_.width) * info_.height * BytesPerTexel(info_.format);
}

ShaderModule CreateShaderModule(const Device& device, const uint32_t* code, size_t bytes) {
  VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  ci.codeSize = bytes;
  ci.pCode = code;
  VkShaderModule module = VK_NULL_HANDLE;
  VK_CHECK(vkCreateShaderModule(device.handle(), &ci, nullptr, &module));
  return ShaderModule(device.handle(), module);
}

namespace {

Sampler CreateClampSampler(const Device& device, VkFilter filter, bool mipmaps = false) {
  VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  si.magFilter = filter;
  si.minFilter = filter;
  si.mipmapMode = mipmaps ? VK_SAMPLER_MIPMAP_MODE_LINEAR : VK_SAMPLER_MIPMAP_MODE_NEAREST;
  si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  si.maxLod = mipmaps ? VK_LOD_CLAMP_NONE : 0.0f;
  VkSampler sampler = VK_NULL_HANDLE;
  VK_CHECK(vkCreateSampler(device.handle(), &si, nullptr, &sampler));
  return Sampler(device.handle(), sampler);
}

}  // namespace

Sampler CreateLinearClampSampler(const Device& device) { return CreateClampSampler(device, VK_FILTER_LINEAR); }
Sampler CreateNearestClampSampler(const Device& device) { return CreateClampSampler(device, VK_FILTER_NEAREST); }
Sampler CreateTrilinearClampSampler(const Device& device) { return CreateClampSampler(device, VK_FILTER_LINEAR, true); }

ImageView CreateLayerView(const Device& device, const GpuImage& image, uint32_t layer) {
  VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vi.image = image.handle();
  vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vi.format = image.info().format;
  vi.subresourceRange = {image.aspect(), 0, 1, layer, 1};
  VkImageView view = VK_NULL_HANDLE;
  VK_CHECK(vkCreateImageView(device.handle(), &vi, nullptr, &view));
  return ImageView(device.handle(), view);
}

}  // namespace vkr::vk
