// Tables from Vulkan 1.3 chapter 7: "Pipeline Stages" (the meta stages, the pipelines'
// logical order), "Access Types" (the aliases, the supported-access table).
#include "sync_tables.hpp"

#include <skygraph/plan_format.hpp>
#include <skygraph/usage.hpp>

#include <initializer_list>
#include <string_view>

namespace skygraph::verifier {
namespace {

constexpr StageSet stages(std::initializer_list<Stage> list) {
    StageSet s;
    for (Stage x : list) s.bits |= 1u << static_cast<uint32_t>(x);
    return s;
}
constexpr AccessSet accesses(std::initializer_list<AccessType> list) {
    AccessSet s;
    for (AccessType x : list) s.bits |= 1u << static_cast<uint32_t>(x);
    return s;
}

using enum Stage;
using enum AccessType;

constexpr StageSet kShaderStages = stages({VertexShader, TessellationControlShader, TessellationEvaluationShader,
                                           GeometryShader, FragmentShader, ComputeShader});
constexpr StageSet kTransferStages = stages({Copy, Blit, Resolve, Clear});
// ALL_GRAPHICS: every stage of the graphics primitive pipeline.
constexpr StageSet kGraphicsStages =
    stages({DrawIndirect, IndexInput, VertexAttributeInput, VertexShader, TessellationControlShader,
            TessellationEvaluationShader, GeometryShader, EarlyFragmentTests, FragmentShader, LateFragmentTests,
            ColorAttachmentOutput});
constexpr StageSet kDeviceStages = {kGraphicsStages.bits | stages({ComputeShader}).bits | kTransferStages.bits};

/// The pipelines of "Pipeline Stages" in their logical order. Transfer commands each execute
/// one stage (a copy never blits), so each is a pipeline of its own; so is the host.
constexpr Stage kGraphicsOrder[] = {DrawIndirect,
                                    IndexInput,
                                    VertexAttributeInput,
                                    VertexShader,
                                    TessellationControlShader,
                                    TessellationEvaluationShader,
                                    GeometryShader,
                                    EarlyFragmentTests,
                                    FragmentShader,
                                    LateFragmentTests,
                                    ColorAttachmentOutput};
constexpr Stage kComputeOrder[] = {DrawIndirect, ComputeShader};

/// One named bit of VkPipelineStageFlags2 and the stages it stands for (TOP and BOTTOM apart).
struct StageBit {
    VkPipelineStageFlags2 bit;
    StageSet stages;
};
constexpr StageBit kStageBits[] = {
    {VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, stages({DrawIndirect})},
    {VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, stages({IndexInput, VertexAttributeInput})},
    {VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, stages({IndexInput})},
    {VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, stages({VertexAttributeInput})},
    {VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, stages({VertexShader})},
    {VK_PIPELINE_STAGE_2_TESSELLATION_CONTROL_SHADER_BIT, stages({TessellationControlShader})},
    {VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT, stages({TessellationEvaluationShader})},
    {VK_PIPELINE_STAGE_2_GEOMETRY_SHADER_BIT, stages({GeometryShader})},
    {VK_PIPELINE_STAGE_2_PRE_RASTERIZATION_SHADERS_BIT,
     stages({VertexShader, TessellationControlShader, TessellationEvaluationShader, GeometryShader})},
    {VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, stages({FragmentShader})},
    {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT, stages({EarlyFragmentTests})},
    {VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, stages({LateFragmentTests})},
    {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, stages({ColorAttachmentOutput})},
    {VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, stages({ComputeShader})},
    {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, kTransferStages},
    {VK_PIPELINE_STAGE_2_COPY_BIT, stages({Copy})},
    {VK_PIPELINE_STAGE_2_BLIT_BIT, stages({Blit})},
    {VK_PIPELINE_STAGE_2_RESOLVE_BIT, stages({Resolve})},
    {VK_PIPELINE_STAGE_2_CLEAR_BIT, stages({Clear})},
    {VK_PIPELINE_STAGE_2_HOST_BIT, stages({Host})},
    {VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT, kGraphicsStages},
    {VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, kDeviceStages},
};

constexpr AccessSet kReads =
    accesses({IndirectCommandRead, IndexRead, VertexAttributeRead, UniformRead, InputAttachmentRead, ShaderSampledRead,
              ShaderStorageRead, ColorAttachmentRead, DepthStencilAttachmentRead, TransferRead, HostRead});
constexpr AccessSet kWrites =
    accesses({ShaderStorageWrite, ColorAttachmentWrite, DepthStencilAttachmentWrite, TransferWrite, HostWrite});

/// One named bit of VkAccessFlags2 and the access types it stands for.
struct AccessBit {
    VkAccessFlags2 bit;
    AccessSet types;
};
constexpr AccessBit kAccessBits[] = {
    {VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT, accesses({IndirectCommandRead})},
    {VK_ACCESS_2_INDEX_READ_BIT, accesses({IndexRead})},
    {VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT, accesses({VertexAttributeRead})},
    {VK_ACCESS_2_UNIFORM_READ_BIT, accesses({UniformRead})},
    {VK_ACCESS_2_INPUT_ATTACHMENT_READ_BIT, accesses({InputAttachmentRead})},
    // SHADER_READ is SHADER_SAMPLED_READ | SHADER_STORAGE_READ (and the binding table read of
    // ray tracing, which is not modelled); SHADER_WRITE is SHADER_STORAGE_WRITE.
    {VK_ACCESS_2_SHADER_READ_BIT, accesses({ShaderSampledRead, ShaderStorageRead})},
    {VK_ACCESS_2_SHADER_WRITE_BIT, accesses({ShaderStorageWrite})},
    {VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT, accesses({ColorAttachmentRead})},
    {VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, accesses({ColorAttachmentWrite})},
    {VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, accesses({DepthStencilAttachmentRead})},
    {VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, accesses({DepthStencilAttachmentWrite})},
    {VK_ACCESS_2_TRANSFER_READ_BIT, accesses({TransferRead})},
    {VK_ACCESS_2_TRANSFER_WRITE_BIT, accesses({TransferWrite})},
    {VK_ACCESS_2_HOST_READ_BIT, accesses({HostRead})},
    {VK_ACCESS_2_HOST_WRITE_BIT, accesses({HostWrite})},
    {VK_ACCESS_2_MEMORY_READ_BIT, kReads},
    {VK_ACCESS_2_MEMORY_WRITE_BIT, kWrites},
    {VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, accesses({ShaderSampledRead})},
    {VK_ACCESS_2_SHADER_STORAGE_READ_BIT, accesses({ShaderStorageRead})},
    {VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, accesses({ShaderStorageWrite})},
};

/// "Supported access types": the stages that can perform each access type (core 1.3 stages
/// only; the fragment shader's attachment reads come with shader tile image, listed as the
/// specification's table lists them).
StageSet supportingStages(AccessType a) {
    switch (a) {
        case IndirectCommandRead: return stages({DrawIndirect});
        case IndexRead: return stages({IndexInput});
        case VertexAttributeRead: return stages({VertexAttributeInput});
        case UniformRead:
        case ShaderSampledRead:
        case ShaderStorageRead:
        case ShaderStorageWrite: return kShaderStages;
        case InputAttachmentRead: return stages({FragmentShader});
        case ColorAttachmentRead: return stages({FragmentShader, ColorAttachmentOutput});
        case ColorAttachmentWrite: return stages({ColorAttachmentOutput});
        case DepthStencilAttachmentRead: return stages({FragmentShader, EarlyFragmentTests, LateFragmentTests});
        case DepthStencilAttachmentWrite: return stages({EarlyFragmentTests, LateFragmentTests});
        case TransferRead: return stages({Copy, Blit, Resolve});
        case TransferWrite: return kTransferStages;
        case HostRead:
        case HostWrite: return stages({Host});
    }
    return {};
}

/// Per stage, the access types it can perform: the supported-access table read by column.
const std::array<uint32_t, kStageCount>& accessTypesAtStage() {
    static const std::array<uint32_t, kStageCount> table = [] {
        std::array<uint32_t, kStageCount> t{};
        for (uint32_t a = 0; a < kAccessTypeCount; ++a) {
            const StageSet s = supportingStages(static_cast<AccessType>(a));
            for (uint32_t st = 0; st < kStageCount; ++st)
                if (s.bits >> st & 1u) t[st] |= 1u << a;
        }
        return t;
    }();
    return table;
}

/// The named stages of a mask, TOP_OF_PIPE and BOTTOM_OF_PIPE apart.
StageSet namedStages(VkPipelineStageFlags2 mask) {
    StageSet s;
    for (const StageBit& b : kStageBits)
        if (mask & b.bit) s |= b.stages;
    return s;
}

template <size_t N>
void addOrderNeighbours(const Stage (&order)[N], Stage s, ScopeSide side, StageSet& out) {
    for (size_t i = 0; i < N; ++i) {
        if (order[i] != s) continue;
        if (side == ScopeSide::First)
            for (size_t j = 0; j <= i; ++j) out |= only(order[j]);
        else
            for (size_t j = i; j < N; ++j) out |= only(order[j]);
    }
}

std::string shortNames(const std::vector<std::string>& names, std::string_view prefix, std::string_view suffix) {
    std::string out;
    for (std::string n : names) {
        if (n.starts_with(prefix)) n.erase(0, prefix.size());
        if (n.ends_with(suffix)) n.erase(n.size() - suffix.size());
        out += (out.empty() ? "" : "|") + n;
    }
    return out.empty() ? "NONE" : out;
}

}  // namespace

AccessSet writeAccessTypes() noexcept { return kWrites; }

bool AccessScope::empty() const noexcept {
    for (uint32_t a : accessAt)
        if (a) return false;
    return true;
}

bool AccessScope::contains(const AccessScope& o) const noexcept {
    for (uint32_t s = 0; s < kStageCount; ++s)
        if (o.accessAt[s] & ~accessAt[s]) return false;
    return true;
}

AccessScope AccessScope::writesOnly() const noexcept {
    AccessScope w = *this;
    for (uint32_t& a : w.accessAt) a &= kWrites.bits;
    return w;
}

AccessScope& AccessScope::operator|=(const AccessScope& o) noexcept {
    for (uint32_t s = 0; s < kStageCount; ++s) accessAt[s] |= o.accessAt[s];
    return *this;
}

AccessScope AccessScope::allDeviceAccess() noexcept {
    AccessScope all;
    const auto& table = accessTypesAtStage();
    for (uint32_t s = 0; s < kStageCount; ++s)
        if (kDeviceStages.bits >> s & 1u) all.accessAt[s] = table[s];
    return all;
}

StageSet allDeviceStages() noexcept { return kDeviceStages; }

StageSet synchronizationScope(VkPipelineStageFlags2 mask, ScopeSide side) noexcept {
    StageSet named = namedStages(mask);
    // TOP_OF_PIPE: NONE in a first scope, ALL_COMMANDS in a second; BOTTOM_OF_PIPE the reverse.
    if (mask & VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT && side == ScopeSide::Second) named |= kDeviceStages;
    if (mask & VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT && side == ScopeSide::First) named |= kDeviceStages;
    StageSet scope = named;
    for (uint32_t s = 0; s < kStageCount; ++s) {
        if (!(named.bits >> s & 1u)) continue;
        const auto stage = static_cast<Stage>(s);
        addOrderNeighbours(kGraphicsOrder, stage, side, scope);
        addOrderNeighbours(kComputeOrder, stage, side, scope);
    }
    return scope;
}

StageSet accessScopeStages(VkPipelineStageFlags2 mask) noexcept { return namedStages(mask); }

AccessSet accessTypes(VkAccessFlags2 mask) noexcept {
    AccessSet s;
    for (const AccessBit& b : kAccessBits)
        if (mask & b.bit) s.bits |= b.types.bits;
    return s;
}

AccessScope accessScope(VkPipelineStageFlags2 stageMask, VkAccessFlags2 accessMask) noexcept {
    AccessScope scope;
    const StageSet st = accessScopeStages(stageMask);
    const AccessSet types = accessTypes(accessMask);
    const auto& table = accessTypesAtStage();
    for (uint32_t s = 0; s < kStageCount; ++s)
        if (st.bits >> s & 1u) scope.accessAt[s] = types.bits & table[s];
    return scope;
}

VkPipelineStageFlags2 unmodelledStages(VkPipelineStageFlags2 mask) noexcept {
    VkPipelineStageFlags2 known = VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT | VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT;
    for (const StageBit& b : kStageBits) known |= b.bit;
    return mask & ~known;
}

VkAccessFlags2 unmodelledAccess(VkAccessFlags2 mask) noexcept {
    VkAccessFlags2 known = 0;
    for (const AccessBit& b : kAccessBits) known |= b.bit;
    return mask & ~known;
}

VkAccessFlags2 accessUnsupportedByStages(VkPipelineStageFlags2 stageMask, VkAccessFlags2 accessMask) noexcept {
    const StageSet st = accessScopeStages(stageMask);
    VkAccessFlags2 unsupported = 0;
    for (const AccessBit& b : kAccessBits) {
        if (!(accessMask & b.bit)) continue;
        if (b.bit == VK_ACCESS_2_MEMORY_READ_BIT || b.bit == VK_ACCESS_2_MEMORY_WRITE_BIT) continue;
        bool supported = false;
        for (uint32_t a = 0; a < kAccessTypeCount; ++a)
            if (b.types.bits >> a & 1u) supported |= supportingStages(static_cast<AccessType>(a)).intersects(st);
        if (!supported) unsupported |= b.bit;
    }
    return unsupported;
}

RequiredScope requiredScope(const PlannedUsage& usage, bool image) noexcept {
    const UsageMode& mode = usage.usage;
    const bool reads = readsContents(mode.access), writes = writesContents(mode.access);
    RequiredScope r;
    const auto attachment = [&](VkPipelineStageFlags2 stage, VkAccessFlags2 read, VkAccessFlags2 write) {
        r.stages = stage;
        r.access = (reads ? read : 0) | (writes ? write : 0);
        r.access |= usage.load == LoadOp::Load ? read : write;  // LOAD reads; CLEAR and DONT_CARE write
        if (usage.store != StoreOp::None) r.access |= write;    // STORE and DONT_CARE write
    };
    switch (mode.stage) {
        case skygraph::Stage::ColorAttachment:
            attachment(VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT,
                       VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
            break;
        case skygraph::Stage::DepthAttachment:
            attachment(VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
            break;
        case skygraph::Stage::Vertex:
        case skygraph::Stage::Fragment:
        case skygraph::Stage::Compute: {
            r.stages = mode.stage == skygraph::Stage::Vertex     ? VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT
                       : mode.stage == skygraph::Stage::Fragment ? VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT
                                                                 : VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
            switch (resolvedBinding(mode, image)) {
                case BindAs::Sampled: r.access = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT; break;
                case BindAs::Uniform: r.access = VK_ACCESS_2_UNIFORM_READ_BIT; break;
                case BindAs::Storage:
                    r.access = (reads ? VK_ACCESS_2_SHADER_STORAGE_READ_BIT : 0) |
                               (writes ? VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT : 0);
                    break;
                default: break;
            }
            break;
        }
        case skygraph::Stage::Transfer:
            r.stages = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
            r.access = (reads ? VK_ACCESS_2_TRANSFER_READ_BIT : 0) | (writes ? VK_ACCESS_2_TRANSFER_WRITE_BIT : 0);
            break;
        case skygraph::Stage::VertexInput:
            if (mode.as == BindAs::Index) {
                r.stages = VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT;
                r.access = VK_ACCESS_2_INDEX_READ_BIT;
            } else {
                r.stages = VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT;
                r.access = VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT;
            }
            break;
        case skygraph::Stage::Indirect:
            r.stages = VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT;
            r.access = VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT;
            break;
    }
    return r;
}

std::string stageNames(VkPipelineStageFlags2 mask) {
    return shortNames(stageMaskNames(mask), "VK_PIPELINE_STAGE_2_", "_BIT");
}

std::string accessNames(VkAccessFlags2 mask) { return shortNames(accessMaskNames(mask), "VK_ACCESS_2_", "_BIT"); }

std::string layoutNameShort(VkImageLayout layout) {
    std::string n = layoutName(layout);
    if (n.starts_with("VK_IMAGE_LAYOUT_")) n.erase(0, 16);
    return n;
}

VkPipelineStageFlags2 stagesOfQueue(QueueKind queue) noexcept {
    constexpr VkPipelineStageFlags2 everyQueue = VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT | VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT |
                                                 VK_PIPELINE_STAGE_2_HOST_BIT | VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT |
                                                 VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT;
    switch (queue) {
        case QueueKind::Graphics: return ~VkPipelineStageFlags2(0);
        case QueueKind::Compute:
            return everyQueue | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT |
                   VK_PIPELINE_STAGE_2_CLEAR_BIT;
        case QueueKind::Transfer: return everyQueue;
    }
    return everyQueue;
}

}  // namespace skygraph::verifier
