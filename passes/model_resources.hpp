// What the forward pass and the path tracer keep on the device per glTF model: its vertices
// and indices, and its textures with their full mip chains, filled by the compiler's upload
// steps in the frame that first draws the model. Models the scene no longer draws are freed once no frame in flight
// can read them.
#pragma once

#include <skygraph/pass.hpp>
#include <skygraph/triangle_mesh.hpp>
#include <skygraph/vk_handles.hpp>

#include <array>
#include <memory>
#include <vector>

namespace skygraph::passes {

/// A sampled image owned here: the image, its memory and a view of every mip.
struct OwnedTexture {
    owned::Memory memory;
    owned::Image image;
    owned::ImageView view;
};

/// A host-visible buffer filled once.
struct HostBuffer {
    owned::Memory memory;
    owned::Buffer buffer;
};

/// A host-visible, host-coherent buffer of `size` bytes, filled with `data`: written before
/// any frame that reads it is submitted (the submit makes host writes visible to the device).
[[nodiscard]] HostBuffer makeHostBuffer(VkDevice device, VkPhysicalDevice physicalDevice, VkDeviceSize size,
                                        VkBufferUsageFlags usage, const void* data);

/// A material's five textures as the forward shader binds them (3 + TextureSlot).
enum TextureSlot : uint32_t { BaseColor, MetallicRoughness, Normal, Occlusion, Emissive, kTextureSlots };

class ModelResources {
public:
    /// `device` and `physicalDevice` outlive this.
    ModelResources(VkDevice device, VkPhysicalDevice physicalDevice);
    ModelResources(const ModelResources&) = delete;
    ModelResources& operator=(const ModelResources&) = delete;

    /// One model on the device.
    struct Model {
        std::shared_ptr<const TriangleMesh> mesh;  ///< keeps its address from being reused
        HostBuffer vertices, indices;
        /// Per TriangleMesh::images entry, and per colour space (0 linear, 1 sRGB) when used so.
        std::vector<std::array<OwnedTexture, 2>> textures;
        std::vector<HostBuffer> staging;  ///< freed once the frame that filled them is done
        uint64_t filledFrame = 0, lastFrame = 0;
    };

    /// Creates what `mesh` needs on its first use in frame `frame` and appends the fills of its
    /// textures (and, once, of the default texture) to `fills`, for
    /// RecordContext::fillSampledImages. The reference is valid until the next call.
    Model& prepare(const std::shared_ptr<const TriangleMesh>& mesh, uint64_t frame, std::vector<SampledImageFill>& fills);
    /// The model of `mesh` prepared before, or nullptr.
    [[nodiscard]] const Model* find(const TriangleMesh& mesh) const;
    /// Prepares the 1x1 white texture that stands for absent ones (a no-op once done).
    void prepareDefault(std::vector<SampledImageFill>& fills);
    /// Frees the models unused for 16 frames and staging buffers of fills 16 frames old: a
    /// frame slot is recorded again only after its previous frame finished, and there are at
    /// most 8 slots.
    void releaseUnused(uint64_t frame);

    /// What a material texture binds: its view and a sampler of its wrap modes, or the white
    /// default with a repeating sampler.
    [[nodiscard]] VkDescriptorImageInfo binding(const Model* model, const MeshTexture& texture, bool srgb) const;
    [[nodiscard]] VkDescriptorImageInfo defaultBinding() const;

private:
    HostBuffer hostBuffer(VkDeviceSize size, VkBufferUsageFlags usage, const void* data) const {
        return makeHostBuffer(device_, physicalDevice_, size, usage, data);
    }
    OwnedTexture texture(const SampledImageShape& shape) const;
    VkSampler sampler(MeshWrap s, MeshWrap t) const { return samplers_[size_t(s) * 3 + size_t(t)].get(); }

    VkDevice device_;
    VkPhysicalDevice physicalDevice_;
    std::array<owned::Sampler, 9> samplers_;
    OwnedTexture white_;
    HostBuffer whiteStaging_;
    std::vector<std::unique_ptr<Model>> models_;
    /// Models prepared so far: each one's number keeps its images' upload names apart from
    /// another model's (every glTF file names its images "images[i]").
    uint64_t modelsPrepared_ = 0;
};

}  // namespace skygraph::passes
