// PathTracePass: progressive path tracing into the `accumulation` image (rgb: the running
// mean, alpha: the sample count), see shaders/passes/pathtrace.comp. The scene's analytic
// objects go to the shader through a small host-visible storage buffer, one per frame in a
// ring so that no frame in flight reads a buffer the host is rewriting; its glTF models as one
// BVH over their triangles and their textures' texels (trace_geometry.hpp), built once per
// set of models. Accumulation starts over whenever the scene, the output
// extent, the environment image's contents or the plan changes.
#include "builtin_passes.hpp"
#include "model_resources.hpp"  // makeHostBuffer
#include "scene_camera.hpp"
#include "trace_geometry.hpp"
#include "vk_util.hpp"

#include <skygraph/pipeline_builder.hpp>

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

namespace skygraph::passes {
namespace {

/// Frames a buffer of the ring waits before it is rewritten: more than any framesInFlight
/// the executor allows, so the frame that last read it has finished (renderFrame waits for
/// its slot before recording).
constexpr uint32_t kRingSize = 8;
/// Objects the shader sees; more are refused with the pass named, not silently dropped.
constexpr uint32_t kMaxObjects = 256;

struct GpuObject {  // matches `Object` in pathtrace.comp (std430)
    float originSize[4];
    float normalKind[4];
    float baseColorMetallic[4];
    float roughnessAo[4];
};

/// Everything a sample depends on, to notice when accumulation must start over: the scene,
/// the extent, and the environment image's contents (`environment`, when bound).
std::vector<double> sceneKey(const Scene* scene, VkExtent2D extent, const BoundResource* environment) {
    std::vector<double> k{double(extent.width), double(extent.height)};
    if (environment && environment->contentsReplaced) k.push_back(double(*environment->contentsReplaced));
    if (!scene) return k;
    const auto& c = scene->camera;
    k.insert(k.end(), {c.position[0], c.position[1], c.position[2], c.yawDeg, c.pitchDeg, c.rollDeg, c.fovYDeg});
    k.push_back(scene->environment ? 1.0 + scene->environment->rotationDeg : -1.0);
    if (scene->environment) {
        k.push_back(scene->environment->procedural ? 1.0 : 0.0);
        k.insert(k.end(), scene->environment->sunDirection.begin(), scene->environment->sunDirection.end());
    }
    for (const SceneObject& o : scene->objects) {
        if (const auto* s = std::get_if<Sphere>(&o.shape)) {
            k.insert(k.end(), {0.0, s->center[0], s->center[1], s->center[2], s->radius});
        } else if (const auto* model = std::get_if<GltfModel>(&o.shape)) {
            k.push_back(double(reinterpret_cast<uintptr_t>(model->mesh.get())));
        } else {
            const auto& p = std::get<Plane>(o.shape);
            k.insert(k.end(), {1.0, p.point[0], p.point[1], p.point[2], p.normal[0], p.normal[1], p.normal[2],
                               p.halfExtent.value_or(-1.0)});
        }
        const auto& m = o.material;
        k.insert(k.end(), {m.baseColor[0], m.baseColor[1], m.baseColor[2], m.metallic, m.roughness});
    }
    return k;
}

class PathTracePass final : public PassImplementation {
public:
    explicit PathTracePass(const PassDesc& desc)
        : samplesPerFrame_(desc.params.value("samples_per_frame", 1)),
          maxBounces_(desc.params.value("max_bounces", 4)),
          seed_(uint32_t(std::hash<std::string>{}(desc.name))) {}

    void createPipelines(const PipelineContext& ctx) override {
        bool environmentBound = false;
        for (const auto& r : ctx.resources) environmentBound = environmentBound || (r.usage && r.usage->slot == "environment");
        ComputePipelineRecipe recipe;
        recipe.compute = compileShader(*ctx.shaders, VK_SHADER_STAGE_COMPUTE_BIT, "passes/pathtrace.comp",
                                       {{"ENV_EQUIRECT", environmentBound ? "1" : "0"}});
        recipe.bindings = {{0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
                           {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
        if (environmentBound)
            recipe.bindings.push_back({2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
        // 3-8: the meshes' BVH nodes, triangles, vertices, materials, texture table and texels.
        for (uint32_t b = kNodesBinding; b < kNodesBinding + kMeshBuffers; ++b)
            recipe.bindings.push_back({b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
        recipe.pushConstantBytes = sizeof(Push);
        ComputePipeline pipeline = createComputePipeline(ctx.device, recipe);  // throws before anything changes
        pipeline_ = std::move(pipeline);
        pushDescriptors_ = pushDescriptorFunction(ctx.device);
        environmentBound_ = environmentBound;
        device_ = ctx.device;
        physicalDevice_ = ctx.physicalDevice;
        if (ring_.empty()) createRing(ctx);
        if (!noMeshes_.buffer) {
            const uint8_t zeros[64] = {};
            noMeshes_ = makeHostBuffer(ctx.device, ctx.physicalDevice, sizeof zeros, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, zeros);
        }
        samplesSoFar_ = 0;  // a new plan or new shaders: start over
    }

    /// Every handle comes from the RecordContext (push descriptors): an imported image's swap
    /// keeps this implementation.
    [[nodiscard]] bool keepsSlotHandles() const noexcept override { return false; }

    void record(const RecordContext& ctx) override {
        const Scene* scene = ctx.frame ? ctx.frame->get<Scene>() : nullptr;
        const BoundResource* accumulation = ctx.slot("accumulation");
        const VkExtent2D extent{accumulation->extent.width, accumulation->extent.height};
        std::vector<double> key = sceneKey(scene, extent, environmentBound_ ? ctx.slot("environment") : nullptr);
        if (key != lastKey_) {
            samplesSoFar_ = 0;
            lastKey_ = std::move(key);
        }
        const CameraView view = cameraView(scene, extent);
        RingBuffer& objects = ring_[ctx.frameIndex % kRingSize];
        const uint32_t count = writeObjects(scene, view, objects);
        const MeshBuffers* meshes = meshBuffersOf(scene, ctx.frameIndex);

        Push push{};
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) push.cameraToWorld[c][r] = float(view.cameraToWorld[c][r]);
        const double tanHalf = std::tan(math::radians(view.fovYDeg) / 2.0);
        const double rotation = math::radians(scene && scene->environment ? scene->environment->rotationDeg : 0.0);
        push.projection[0] = float(view.aspect * tanHalf);
        push.projection[1] = float(tanHalf);
        push.projection[2] = float(std::sin(rotation));
        push.projection[3] = float(std::cos(rotation));
        push.frame[0] = int32_t(samplesSoFar_);
        push.frame[1] = samplesPerFrame_;
        push.frame[2] = maxBounces_;
        push.frame[3] = int32_t(seed_);
        const auto sun = scene && scene->environment ? scene->environment->sunDirection
                                                     : SceneEnvironment{}.sunDirection;
        for (int i = 0; i < 3; ++i) push.sun[i] = float(sun[size_t(i)]);
        // Meshes are in world space: the shader moves its camera-relative rays there.
        for (int i = 0; i < 3; ++i) push.cameraPosition[i] = float(view.position[i]);
        push.cameraPosition[3] = meshes && !meshes->geometry.nodes.empty() ? 1.0f : 0.0f;

        vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.pipeline.get());
        const VkDescriptorImageInfo image{VK_NULL_HANDLE, accumulation->view, accumulation->usage->layout};
        const VkDescriptorBufferInfo buffer{objects.buffer.get(), 0, bufferBytes()};
        VkWriteDescriptorSet writes[3 + kMeshBuffers]{};
        writes[0] = sampledImageWrite(0, &image);
        writes[0].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        writes[1] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        writes[1].dstBinding = 1;
        writes[1].descriptorCount = 1;
        writes[1].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[1].pBufferInfo = &buffer;
        uint32_t writeCount = 2;
        VkDescriptorImageInfo env{};
        if (environmentBound_) {
            const BoundResource* e = ctx.slot("environment");
            env = {ctx.repeatSampler, e->view, e->usage->layout};
            writes[writeCount++] = sampledImageWrite(2, &env);
        }
        VkDescriptorBufferInfo meshInfos[kMeshBuffers];
        for (uint32_t b = 0; b < kMeshBuffers; ++b) {
            meshInfos[b] = {meshes ? meshes->buffers[b].buffer.get() : noMeshes_.buffer.get(), 0, VK_WHOLE_SIZE};
            VkWriteDescriptorSet& w = writes[writeCount++];
            w = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            w.dstBinding = kNodesBinding + b;
            w.descriptorCount = 1;
            w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            w.pBufferInfo = &meshInfos[b];
        }
        pushDescriptors_(ctx.cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.layout.get(), 0, writeCount, writes);
        vkCmdPushConstants(ctx.cmd, pipeline_.layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
        vkCmdDispatch(ctx.cmd, (extent.width + 7) / 8, (extent.height + 7) / 8, 1);
        samplesSoFar_ += uint32_t(samplesPerFrame_);
        (void)count;
        std::erase_if(meshBuffers_, [&](const auto& m) { return ctx.frameIndex > m->lastFrame + 16; });
    }

private:
    static constexpr uint32_t kNodesBinding = 3, kMeshBuffers = 6;

    struct Push {  // matches `Params` in pathtrace.comp
        float cameraToWorld[3][4];
        float projection[4];
        int32_t frame[4];
        float sun[4];
        float cameraPosition[4];
    };

    /// The scene's models on the device, for as long as a frame in flight may read them.
    struct MeshBuffers {
        TraceGeometry geometry;
        std::array<HostBuffer, kMeshBuffers> buffers;  ///< bindings 3-8, in order
        uint64_t lastFrame = 0;
    };

    /// The geometry of the scene's glTF models, built when their set changes; nullptr when
    /// the scene has none.
    const MeshBuffers* meshBuffersOf(const Scene* scene, uint64_t frame) {
        std::vector<std::shared_ptr<const TriangleMesh>> models;
        if (scene)
            for (const SceneObject& o : scene->objects)
                if (const auto* model = std::get_if<GltfModel>(&o.shape)) models.push_back(model->mesh);
        if (models.empty()) return nullptr;
        for (auto& b : meshBuffers_)
            if (b->geometry.models == models) return b->lastFrame = frame, b.get();
        auto b = std::make_unique<MeshBuffers>();
        try {
            b->geometry = buildTraceGeometry(std::move(models));
        } catch (const std::length_error& e) {
            throw ExecutorError(std::string("PathTracePass: ") + e.what());
        }
        const auto buffer = [&](const auto& v) {
            return makeHostBuffer(device_, physicalDevice_, v.size() * sizeof(v[0]), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  v.data());
        };
        const TraceGeometry& g = b->geometry;
        b->buffers = {buffer(g.nodes), buffer(g.triangles), buffer(g.vertices), buffer(g.materials),
                      buffer(g.textures), buffer(g.texels)};
        b->lastFrame = frame;
        meshBuffers_.push_back(std::move(b));
        return meshBuffers_.back().get();
    }

    struct RingBuffer {
        owned::Memory memory;
        owned::Buffer buffer;
        void* mapped = nullptr;
    };

    static VkDeviceSize bufferBytes() { return 16 + VkDeviceSize(kMaxObjects) * sizeof(GpuObject); }

    void createRing(const PipelineContext& ctx) {
        ring_.resize(kRingSize);
        for (RingBuffer& r : ring_) {
            VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
            bi.size = bufferBytes();
            bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
            VkBuffer b;
            vk::check(vkCreateBuffer(ctx.device, &bi, nullptr, &b), "vkCreateBuffer");
            r.buffer = owned::Buffer(ctx.device, b);
            VkMemoryRequirements req;
            vkGetBufferMemoryRequirements(ctx.device, b, &req);
            VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
            ai.allocationSize = req.size;
            ai.memoryTypeIndex = vk::findMemoryType(ctx.physicalDevice, req.memoryTypeBits,
                                                    VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
            VkDeviceMemory mem;
            vk::check(vkAllocateMemory(ctx.device, &ai, nullptr, &mem), "vkAllocateMemory");
            r.memory = owned::Memory(ctx.device, mem);
            vk::check(vkBindBufferMemory(ctx.device, b, mem, 0), "vkBindBufferMemory");
            vk::check(vkMapMemory(ctx.device, mem, 0, VK_WHOLE_SIZE, 0, &r.mapped), "vkMapMemory");
        }
    }

    /// Camera-relative objects (subtracted in double, as the forward pass does) into `out`.
    static uint32_t writeObjects(const Scene* scene, const CameraView& view, RingBuffer& out) {
        std::vector<GpuObject> objects;
        if (scene) {
            if (scene->objects.size() > kMaxObjects)
                throw ExecutorError("PathTracePass: the scene has " + std::to_string(scene->objects.size()) +
                                    " objects, more than the " + std::to_string(kMaxObjects) + " it traces");
            for (size_t index = 0; index < scene->objects.size(); ++index) {
                const SceneObject& o = scene->objects[index];
                if (std::holds_alternative<GltfModel>(o.shape)) continue;  // traced through the BVH
                GpuObject g{};
                if (const auto* s = std::get_if<Sphere>(&o.shape)) {
                    for (int i = 0; i < 3; ++i) g.originSize[i] = float(s->center[i] - view.position[i]);
                    g.originSize[3] = float(s->radius);
                } else {
                    const auto& p = std::get<Plane>(o.shape);
                    const math::Vec3<double> n = glm::normalize(math::Vec3<double>(p.normal[0], p.normal[1], p.normal[2]));
                    const math::Vec3<double> point(p.point[0], p.point[1], p.point[2]);
                    // Bounded planes sit on their point; infinite ones under the camera (exact
                    // far from the origin, as the forward pass places them).
                    const math::Vec3<double> origin =
                        p.halfExtent ? point - view.position : -n * glm::dot(view.position - point, n);
                    for (int i = 0; i < 3; ++i) {
                        g.originSize[i] = float(origin[i]);
                        g.normalKind[i] = float(n[i]);
                    }
                    g.originSize[3] = float(p.halfExtent.value_or(0.0));
                    g.normalKind[3] = 1.0f;
                }
                for (int i = 0; i < 3; ++i) g.baseColorMetallic[i] = float(o.material.baseColor[i]);
                g.baseColorMetallic[3] = float(o.material.metallic);
                g.roughnessAo[0] = float(o.material.roughness);
                g.roughnessAo[1] = float(o.material.ao);
                objects.push_back(g);
            }
        }
        const int32_t header[4] = {int32_t(objects.size()), 0, 0, 0};
        std::memcpy(out.mapped, header, sizeof header);
        if (!objects.empty())
            std::memcpy(static_cast<char*>(out.mapped) + 16, objects.data(), objects.size() * sizeof(GpuObject));
        return uint32_t(objects.size());
    }

    int samplesPerFrame_;
    int maxBounces_;
    /// From the pass's name: deterministic, and two passes (a sweep and its reference) draw
    /// independent samples.
    uint32_t seed_;
    bool environmentBound_ = false;
    uint32_t samplesSoFar_ = 0;
    std::vector<double> lastKey_;
    std::vector<RingBuffer> ring_;
    VkDevice device_ = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
    HostBuffer noMeshes_;  ///< bound in place of the mesh buffers when the scene has no models
    std::vector<std::unique_ptr<MeshBuffers>> meshBuffers_;
    ComputePipeline pipeline_;
    PFN_vkCmdPushDescriptorSetKHR pushDescriptors_ = nullptr;
};

}  // namespace

std::unique_ptr<PassImplementation> makePathTracePass(const PassDesc& desc) {
    return std::make_unique<PathTracePass>(desc);
}

}  // namespace skygraph::passes
