// ForwardPass: the scene's spheres, planes and glTF meshes, metal/rough GGX, into hdr_color
// and a reverse-Z depth buffer (GREATER test). The pass clears nothing itself: its depth starts
// from the resource's load-op clear (0) or an earlier pass's depth (forward_type.cpp refuses
// a Write of a depth resource without `clear`). The debug view is the scene's.
#include "builtin_passes.hpp"
#include "model_resources.hpp"
#include "scene_camera.hpp"
#include "vk_util.hpp"

#include <skygraph/pipeline_builder.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace skygraph::passes {
namespace {

using Vertex = MeshVertex;  // glTF meshes are drawn from their loaded vertices as they are

/// A unit UV sphere followed by a unit square in the XZ plane (normal +Y).
struct Meshes {
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices;
    uint32_t sphereIndexCount = 0, planeFirstIndex = 0, planeIndexCount = 0;
};

Meshes buildMeshes() {
    constexpr uint32_t kSlices = 64, kStacks = 32;
    Meshes m;
    for (uint32_t i = 0; i <= kStacks; ++i) {
        const double theta = math::kPi<double> * i / kStacks;
        for (uint32_t j = 0; j <= kSlices; ++j) {
            const double phi = 2.0 * math::kPi<double> * j / kSlices;
            const float x = float(std::sin(theta) * std::cos(phi)), y = float(std::cos(theta)),
                        z = float(std::sin(theta) * std::sin(phi));
            // Untextured: the UVs and tangents are never sampled, only well-formed.
            const float tx = float(-std::sin(phi)), tz = float(std::cos(phi));
            m.vertices.push_back({{x, y, z}, {x, y, z}, {float(j) / kSlices, float(i) / kStacks}, {tx, 0, tz, 1}});
        }
    }
    for (uint32_t i = 0; i < kStacks; ++i)
        for (uint32_t j = 0; j < kSlices; ++j) {
            const uint32_t a = i * (kSlices + 1) + j, b = a + kSlices + 1;
            m.indices.insert(m.indices.end(), {a, a + 1, b, a + 1, b + 1, b});
        }
    m.sphereIndexCount = static_cast<uint32_t>(m.indices.size());
    m.planeFirstIndex = m.sphereIndexCount;
    const auto base = static_cast<uint32_t>(m.vertices.size());
    for (float x : {-1.0f, 1.0f})
        for (float z : {-1.0f, 1.0f}) m.vertices.push_back({{x, 0, z}, {0, 1, 0}, {0, 0}, {1, 0, 0, 1}});
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base + 1, base + 3, base + 2});
    m.planeIndexCount = 6;
    return m;
}

int debugViewIndex(DebugView v) {
    switch (v) {
        case DebugView::None: return 0;
        case DebugView::Normal: return 1;
        case DebugView::Metallic: return 2;
        case DebugView::Roughness: return 3;
        case DebugView::Ao: return 4;
    }
    return 0;
}

/// Half size used for planes without a half extent: far beyond anything the scene shows, and
/// centred under the camera, so the plane reads as infinite.
constexpr double kInfinitePlaneHalfSize = 1e5;

class ForwardPass final : public PassImplementation {
public:
    explicit ForwardPass(const PassDesc&) {}

    void createPipelines(const PipelineContext& ctx) override {
        GraphicsPipelineRecipe recipe;
        recipe.vertex = compileShader(*ctx.shaders, VK_SHADER_STAGE_VERTEX_BIT, "passes/forward.vert");
        // Lit by the environment pipeline's products when the graph binds all three (split-sum
        // IBL); otherwise by a sun and an ambient term.
        ibl_ = true;
        for (const char* slot : kIblSlots) {
            bool bound = false;
            for (const auto& r : ctx.resources) bound = bound || (r.usage && r.usage->slot == slot);
            ibl_ = ibl_ && bound;
        }
        recipe.fragment = compileShader(*ctx.shaders, VK_SHADER_STAGE_FRAGMENT_BIT, "passes/forward.frag",
                                        {{"FORWARD_IBL", ibl_ ? "1" : "0"}});
        // Bindings 0-2: the IBL products; 3-7: a material's textures (TextureSlot).
        for (uint32_t b = ibl_ ? 0 : kFirstTextureBinding; b < kFirstTextureBinding + kTextureSlots; ++b)
            recipe.bindings.push_back({b, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr});
        pushDescriptors_ = pushDescriptorFunction(ctx.device);
        recipe.renderPass = ctx.renderPass;
        recipe.depthTest = true;
        recipe.depthWrite = true;
        recipe.depthCompare = VK_COMPARE_OP_GREATER;  // reverse-Z: nearer is larger
        recipe.vertexBindings = {{0, sizeof(Vertex), VK_VERTEX_INPUT_RATE_VERTEX}};
        recipe.vertexAttributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
                                   {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
                                   {2, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv)},
                                   {3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(Vertex, tangent)}};
        recipe.pushConstantBytes = sizeof(Push);
        GraphicsPipeline pipeline = createGraphicsPipeline(ctx.device, recipe);
        device_ = ctx.device;
        physicalDevice_ = ctx.physicalDevice;
        if (!vertices_.buffer) createMeshBuffer();
        if (!models_) models_ = std::make_unique<ModelResources>(ctx.device, ctx.physicalDevice);
        pipeline_ = std::move(pipeline);
    }

    /// The textures of models drawn for the first time, filled by the compiler's upload steps
    /// before the render pass begins.
    void recordBeforeRenderPass(const RecordContext& ctx) override {
        std::vector<SampledImageFill> fills;
        models_->prepareDefault(fills);
        if (const Scene* scene = ctx.frame ? ctx.frame->get<Scene>() : nullptr)
            for (const SceneObject& object : scene->objects)
                if (const auto* model = std::get_if<GltfModel>(&object.shape))
                    models_->prepare(model->mesh, ctx.frameIndex, fills);
        if (!fills.empty()) ctx.fillSampledImages(fills);
    }

    /// Every handle comes from the RecordContext (push descriptors): an imported image's swap
    /// keeps this implementation.
    [[nodiscard]] bool keepsSlotHandles() const noexcept override { return false; }

    void record(const RecordContext& ctx) override {
        const Scene* scene = ctx.frame ? ctx.frame->get<Scene>() : nullptr;
        if (!scene) return;  // nothing to draw; the render pass still clears
        const CameraView view = cameraView(scene, ctx.renderArea);
        // Camera at the origin: only the rotation enters the matrix.
        const math::Mat4<double> viewProj =
            math::reverseZInfiniteProjection(view.fovYDeg, view.aspect, view.nearPlane) *
            math::viewMatrix(math::Vec3<double>(0.0), view.cameraToWorld);

        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
        setViewportAndScissor(ctx.cmd, ctx.renderArea);
        const VkDeviceSize offset = 0;
        const VkBuffer vb = vertices_.buffer.get();
        vkCmdBindVertexBuffers(ctx.cmd, 0, 1, &vb, &offset);
        vkCmdBindIndexBuffer(ctx.cmd, indices_.buffer.get(), 0, VK_INDEX_TYPE_UINT32);
        if (ibl_) {
            VkDescriptorImageInfo images[3];
            VkWriteDescriptorSet writes[3];
            for (uint32_t b = 0; b < 3; ++b) {
                const BoundResource* r = ctx.slot(kIblSlots[b]);
                images[b] = {ctx.linearSampler, r->view, r->usage->layout};
                writes[b] = sampledImageWrite(b, &images[b]);
            }
            pushDescriptors_(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.layout.get(), 0, 3, writes);
        }
        bindMaterialTextures(ctx, nullptr, nullptr);  // the analytic objects: white, flat
        // The environment's rotation about +Y, as the skybox applies it (radians).
        const float rotation = scene->environment ? float(math::radians(scene->environment->rotationDeg)) : 0.0f;
        for (const SceneObject& object : scene->objects) {
            Push push{};
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) push.viewProjection[c][r] = float(viewProj[c][r]);
            const auto& mat = object.material;
            for (int i = 0; i < 3; ++i) push.baseColorMetallic[i] = float(mat.baseColor[i]);
            push.baseColorMetallic[3] = float(mat.metallic);
            push.planeNormalRoughness[3] = float(mat.roughness);
            push.aoViewKind[0] = float(mat.ao);
            push.aoViewKind[1] = kNeverDiscard;
            push.aoViewKind[2] = kindAndView(0, scene->debugView);
            push.aoViewKind[3] = rotation;
            if (const auto* model = std::get_if<GltfModel>(&object.shape)) {
                drawModel(ctx, *model, push, view.position, scene->debugView);
                continue;
            }
            uint32_t first = 0, count = meshes_.sphereIndexCount;
            if (const auto* sphere = std::get_if<Sphere>(&object.shape)) {
                for (int i = 0; i < 3; ++i) push.originAndScale[i] = float(sphere->center[i] - view.position[i]);
                push.originAndScale[3] = float(sphere->radius);
            } else {
                const auto& plane = std::get<Plane>(object.shape);
                const math::Vec3<double> n(plane.normal[0], plane.normal[1], plane.normal[2]);
                const math::Vec3<double> p(plane.point[0], plane.point[1], plane.point[2]);
                // Bounded planes sit on their point; infinite ones under the camera. So does a
                // bounded one whose extent holds the infinite one's square around the camera's
                // foot (within the disc its own square holds): rasterizers lose a square as
                // large as 1e9 (lavapipe drew none), and beyond 1e5 it looks no different.
                const math::Vec3<double> underCamera = -n * glm::dot(view.position - p, n);
                const bool drawnAsInfinite =
                    !plane.halfExtent || glm::length(view.position + underCamera - p) +
                                                 kInfinitePlaneHalfSize * std::sqrt(2.0) <=
                                             *plane.halfExtent;
                const math::Vec3<double> origin = drawnAsInfinite ? underCamera : p - view.position;
                for (int i = 0; i < 3; ++i) {
                    push.originAndScale[i] = float(origin[i]);
                    push.planeNormalRoughness[i] = float(n[i]);
                }
                push.originAndScale[3] = float(drawnAsInfinite ? kInfinitePlaneHalfSize : *plane.halfExtent);
                push.aoViewKind[2] = kindAndView(1, scene->debugView);
                first = meshes_.planeFirstIndex;
                count = meshes_.planeIndexCount;
            }
            vkCmdPushConstants(ctx.cmd, pipeline_.layout.get(),
                               VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(push), &push);
            vkCmdDrawIndexed(ctx.cmd, count, 1, first, 0, 0);
        }
        models_->releaseUnused(ctx.frameIndex);
    }

private:
    struct Push;

    /// Alpha-mask threshold that no texel's alpha falls below.
    static constexpr float kNeverDiscard = -1.0f;
    static constexpr uint32_t kFirstTextureBinding = 3;

    /// The shader's object kind (0 sphere, 1 plane, 2 mesh) and debug view in one float.
    static float kindAndView(int kind, DebugView view) { return float(kind + 8 * debugViewIndex(view)); }

    /// Pushes bindings 3-7: `material`'s textures of `model`, or white for each it lacks.
    void bindMaterialTextures(const RecordContext& ctx, const ModelResources::Model* model, const MeshMaterial* material) {
        VkDescriptorImageInfo images[kTextureSlots];
        if (!material) {
            for (auto& image : images) image = models_->defaultBinding();
        } else {
            images[BaseColor] = models_->binding(model, material->baseColorTexture, true);
            images[MetallicRoughness] = models_->binding(model, material->metallicRoughnessTexture, false);
            images[Normal] = models_->binding(model, material->normalTexture, false);
            images[Occlusion] = models_->binding(model, material->occlusionTexture, false);
            images[Emissive] = models_->binding(model, material->emissiveTexture, true);
        }
        VkWriteDescriptorSet writes[kTextureSlots];
        for (uint32_t t = 0; t < kTextureSlots; ++t) writes[t] = sampledImageWrite(kFirstTextureBinding + t, &images[t]);
        pushDescriptors_(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.layout.get(), 0, kTextureSlots, writes);
    }

    void drawModel(const RecordContext& ctx, const GltfModel& model, Push push, const math::Vec3<double>& eye,
                   DebugView debugView) {
        const ModelResources::Model* gpu = models_->find(*model.mesh);
        if (!gpu) return;  // recordBeforeRenderPass prepares every model of the scene
        const VkDeviceSize offset = 0;
        const VkBuffer vb = gpu->vertices.buffer.get();
        vkCmdBindVertexBuffers(ctx.cmd, 0, 1, &vb, &offset);
        vkCmdBindIndexBuffer(ctx.cmd, gpu->indices.buffer.get(), 0, VK_INDEX_TYPE_UINT32);
        // World-space vertices, placed camera-relative by the shader's origin (-eye, in double
        // here). Kind 2 reads the push constants its own way (shaders/passes/forward.frag).
        for (int i = 0; i < 3; ++i) push.originAndScale[i] = float(-eye[i]);
        push.aoViewKind[2] = kindAndView(2, debugView);
        for (const MeshPrimitive& primitive : model.mesh->primitives) {
            const MeshMaterial& m = primitive.material;
            for (int i = 0; i < 3; ++i) {
                push.baseColorMetallic[i] = float(m.baseColor[size_t(i)]);
                push.planeNormalRoughness[i] = float(m.emissive[size_t(i)]);
            }
            push.baseColorMetallic[3] = float(m.metallic);
            push.planeNormalRoughness[3] = float(m.roughness);
            // Without a normal texture the white default must not tilt the normal: scale 0.
            push.originAndScale[3] = m.normalTexture.present() ? float(m.normalScale) : 0.0f;
            push.aoViewKind[0] = float(m.occlusionStrength);
            // Mask: discard where texture alpha * factor alpha < cutoff.
            push.aoViewKind[1] = m.alphaMode != MeshAlphaMode::Mask ? kNeverDiscard
                                 : m.baseColor[3] > 0.0 ? float(m.alphaCutoff / m.baseColor[3])
                                                        : 2.0f;  // above every alpha: all discarded
            bindMaterialTextures(ctx, gpu, &m);
            vkCmdPushConstants(ctx.cmd, pipeline_.layout.get(),
                               VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(push), &push);
            vkCmdDrawIndexed(ctx.cmd, primitive.indexCount, 1, primitive.firstIndex, 0, 0);
        }
        // The next analytic object binds the built-in meshes and the default textures again.
        const VkBuffer builtin = vertices_.buffer.get();
        vkCmdBindVertexBuffers(ctx.cmd, 0, 1, &builtin, &offset);
        vkCmdBindIndexBuffer(ctx.cmd, indices_.buffer.get(), 0, VK_INDEX_TYPE_UINT32);
        bindMaterialTextures(ctx, nullptr, nullptr);
    }

    struct Push {  // matches `Draw` in shaders/passes/forward.{vert,frag}
        float viewProjection[4][4];
        float originAndScale[4];
        float baseColorMetallic[4];
        float planeNormalRoughness[4];
        float aoViewKind[4];
    };
    static_assert(sizeof(Push) == 128, "the push constant budget every device guarantees");

    void createMeshBuffer() {
        meshes_ = buildMeshes();
        vertices_ = makeHostBuffer(device_, physicalDevice_, meshes_.vertices.size() * sizeof(Vertex),
                                   VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, meshes_.vertices.data());
        indices_ = makeHostBuffer(device_, physicalDevice_, meshes_.indices.size() * sizeof(uint32_t),
                                  VK_BUFFER_USAGE_INDEX_BUFFER_BIT, meshes_.indices.data());
    }

    static constexpr const char* kIblSlots[3] = {"irradiance", "prefiltered", "brdf_lut"};
    bool ibl_ = false;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors_ = nullptr;
    VkDevice device_ = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
    Meshes meshes_;
    HostBuffer vertices_, indices_;  ///< the built-in meshes
    std::unique_ptr<ModelResources> models_;
    GraphicsPipeline pipeline_;
};

}  // namespace

std::unique_ptr<PassImplementation> makeForwardPass(const PassDesc& desc) {
    return std::make_unique<ForwardPass>(desc);
}

}  // namespace skygraph::passes
