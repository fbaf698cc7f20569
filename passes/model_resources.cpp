#include "model_resources.hpp"

#include "vk_util.hpp"

#include <skygraph/format.hpp>

#include <algorithm>
#include <bit>
#include <cstring>
#include <string>

namespace skygraph::passes {
namespace {

VkSamplerAddressMode addressMode(MeshWrap w) {
    switch (w) {
        case MeshWrap::Repeat: return VK_SAMPLER_ADDRESS_MODE_REPEAT;
        case MeshWrap::ClampToEdge: return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        case MeshWrap::MirroredRepeat: return VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT;
    }
    return VK_SAMPLER_ADDRESS_MODE_REPEAT;
}

uint32_t mipCount(uint32_t width, uint32_t height) { return std::bit_width(std::max(width, height)); }

}  // namespace

ModelResources::ModelResources(VkDevice device, VkPhysicalDevice physicalDevice)
    : device_(device), physicalDevice_(physicalDevice) {
    for (size_t s = 0; s < 3; ++s)
        for (size_t t = 0; t < 3; ++t) {
            VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
            si.magFilter = si.minFilter = VK_FILTER_LINEAR;
            si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
            si.addressModeU = addressMode(MeshWrap(s));
            si.addressModeV = addressMode(MeshWrap(t));
            si.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
            si.maxLod = VK_LOD_CLAMP_NONE;
            VkSampler sampler;
            vk::check(vkCreateSampler(device_, &si, nullptr, &sampler), "vkCreateSampler");
            samplers_[s * 3 + t] = owned::Sampler(device_, sampler);
        }
}

HostBuffer makeHostBuffer(VkDevice device, VkPhysicalDevice physicalDevice, VkDeviceSize size, VkBufferUsageFlags usage,
                          const void* data) {
    HostBuffer h;
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = std::max<VkDeviceSize>(size, 4);
    bi.usage = usage;
    VkBuffer b;
    vk::check(vkCreateBuffer(device, &bi, nullptr, &b), "vkCreateBuffer");
    h.buffer = owned::Buffer(device, b);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, b, &req);
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = vk::findMemoryType(physicalDevice, req.memoryTypeBits,
                                            VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    VkDeviceMemory mem;
    vk::check(vkAllocateMemory(device, &ai, nullptr, &mem), "vkAllocateMemory");
    h.memory = owned::Memory(device, mem);
    vk::check(vkBindBufferMemory(device, b, mem, 0), "vkBindBufferMemory");
    void* mapped;
    vk::check(vkMapMemory(device, mem, 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");
    if (size > 0) std::memcpy(mapped, data, size);
    vkUnmapMemory(device, mem);
    return h;
}

OwnedTexture ModelResources::texture(const SampledImageShape& shape) const {
    OwnedTexture t;
    VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ii.imageType = VK_IMAGE_TYPE_2D;
    ii.format = shape.format.format;
    ii.extent = {shape.width, shape.height, 1};
    ii.mipLevels = mipCount(shape.width, shape.height);
    ii.arrayLayers = 1;
    ii.samples = VK_SAMPLE_COUNT_1_BIT;
    ii.tiling = VK_IMAGE_TILING_OPTIMAL;
    ii.usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImage image;
    vk::check(vkCreateImage(device_, &ii, nullptr, &image), "vkCreateImage");
    t.image = owned::Image(device_, image);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device_, image, &req);
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = vk::findMemoryType(physicalDevice_, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VkDeviceMemory mem;
    vk::check(vkAllocateMemory(device_, &ai, nullptr, &mem), "vkAllocateMemory");
    t.memory = owned::Memory(device_, mem);
    vk::check(vkBindImageMemory(device_, image, mem, 0), "vkBindImageMemory");
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = image;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = ii.format;
    vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, ii.mipLevels, 0, 1};
    VkImageView view;
    vk::check(vkCreateImageView(device_, &vi, nullptr, &view), "vkCreateImageView");
    t.view = owned::ImageView(device_, view);
    return t;
}

void ModelResources::prepareDefault(std::vector<SampledImageFill>& fills) {
    if (white_.image) return;
    const SampledImageShape shape{"white", *findFormat("R8G8B8A8_UNORM"), 1, 1};
    const uint8_t texel[4] = {255, 255, 255, 255};
    whiteStaging_ = hostBuffer(4, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, texel);
    white_ = texture(shape);
    fills.push_back({shape, white_.image.get(), whiteStaging_.buffer.get()});
}

ModelResources::Model& ModelResources::prepare(const std::shared_ptr<const TriangleMesh>& mesh, uint64_t frame,
                                               std::vector<SampledImageFill>& fills) {
    for (auto& m : models_)
        if (m->mesh.get() == mesh.get()) return m->lastFrame = frame, *m;
    auto m = std::make_unique<Model>();
    m->mesh = mesh;
    m->lastFrame = m->filledFrame = frame;
    m->vertices = hostBuffer(mesh->vertices.size() * sizeof(MeshVertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                             mesh->vertices.data());
    m->indices = hostBuffer(mesh->indices.size() * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                            mesh->indices.data());
    // Each image in the colour spaces its materials read it in (glTF: base colour and
    // emissive are sRGB, the rest linear).
    std::vector<std::array<bool, 2>> used(mesh->images.size(), {false, false});
    for (const MeshPrimitive& p : mesh->primitives) {
        const MeshMaterial& mat = p.material;
        for (const MeshTexture* t : {&mat.baseColorTexture, &mat.emissiveTexture})
            if (t->present()) used.at(size_t(t->image))[1] = true;
        for (const MeshTexture* t : {&mat.metallicRoughnessTexture, &mat.normalTexture, &mat.occlusionTexture})
            if (t->present()) used.at(size_t(t->image))[0] = true;
    }
    m->textures.resize(mesh->images.size());
    const std::string model = "model " + std::to_string(++modelsPrepared_) + " ";
    for (size_t i = 0; i < mesh->images.size(); ++i) {
        const MeshImage& image = mesh->images[i];
        for (size_t srgb = 0; srgb < 2; ++srgb) {
            if (!used[i][srgb]) continue;
            const SampledImageShape shape{model + image.name + (srgb ? " (sRGB)" : ""),
                                          *findFormat(srgb ? "R8G8B8A8_SRGB" : "R8G8B8A8_UNORM"), image.width,
                                          image.height};
            m->staging.push_back(hostBuffer(image.rgba.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, image.rgba.data()));
            m->textures[i][srgb] = texture(shape);
            fills.push_back({shape, m->textures[i][srgb].image.get(), m->staging.back().buffer.get()});
        }
    }
    models_.push_back(std::move(m));
    return *models_.back();
}

const ModelResources::Model* ModelResources::find(const TriangleMesh& mesh) const {
    for (const auto& m : models_)
        if (m->mesh.get() == &mesh) return m.get();
    return nullptr;
}

void ModelResources::releaseUnused(uint64_t frame) {
    std::erase_if(models_, [&](const auto& m) { return frame > m->lastFrame + 16; });
    for (auto& m : models_)
        if (frame > m->filledFrame + 16) m->staging.clear();
}

VkDescriptorImageInfo ModelResources::defaultBinding() const {
    return {sampler(MeshWrap::Repeat, MeshWrap::Repeat), white_.view.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
}

VkDescriptorImageInfo ModelResources::binding(const Model* model, const MeshTexture& texture, bool srgb) const {
    if (!model || !texture.present()) return defaultBinding();
    const OwnedTexture& t = model->textures.at(size_t(texture.image))[srgb ? 1 : 0];
    return {sampler(texture.wrapS, texture.wrapT), t.view.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
}

}  // namespace skygraph::passes
