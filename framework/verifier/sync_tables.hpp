// The verifier's own reading of Vulkan 1.3, chapter 7 "Synchronization and Cache Control":
// pipeline stages and their logical order, access types and the stages that can perform them,
// the meta stages and access aliases, and what each graph usage does in Vulkan terms. Written
// from the specification text (and its machine-readable <sync> section of vk.xml); it shares
// nothing with the compiler's tables on purpose, so that the two can disagree.
#pragma once

#include <skygraph/plan.hpp>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <string>

namespace skygraph::verifier {

/// The stages a Vulkan 1.3 command can execute, with every meta stage (ALL_COMMANDS,
/// ALL_GRAPHICS, ALL_TRANSFER, VERTEX_INPUT, PRE_RASTERIZATION_SHADERS) broken into these.
enum class Stage : uint8_t {
    DrawIndirect,
    IndexInput,
    VertexAttributeInput,
    VertexShader,
    TessellationControlShader,
    TessellationEvaluationShader,
    GeometryShader,
    EarlyFragmentTests,
    FragmentShader,
    LateFragmentTests,
    ColorAttachmentOutput,
    ComputeShader,
    Copy,
    Blit,
    Resolve,
    Clear,
    Host,
};
inline constexpr uint32_t kStageCount = 17;

/// The access types of Vulkan 1.3 with every alias (SHADER_READ, SHADER_WRITE, MEMORY_READ,
/// MEMORY_WRITE) broken into these.
enum class AccessType : uint8_t {
    IndirectCommandRead,
    IndexRead,
    VertexAttributeRead,
    UniformRead,
    InputAttachmentRead,
    ShaderSampledRead,
    ShaderStorageRead,
    ShaderStorageWrite,
    ColorAttachmentRead,
    ColorAttachmentWrite,
    DepthStencilAttachmentRead,
    DepthStencilAttachmentWrite,
    TransferRead,
    TransferWrite,
    HostRead,
    HostWrite,
};
inline constexpr uint32_t kAccessTypeCount = 16;

/// A set of Stage values.
struct StageSet {
    uint32_t bits = 0;
    [[nodiscard]] bool has(Stage s) const noexcept { return bits >> static_cast<uint32_t>(s) & 1u; }
    [[nodiscard]] bool empty() const noexcept { return bits == 0; }
    [[nodiscard]] bool intersects(StageSet o) const noexcept { return (bits & o.bits) != 0; }
    [[nodiscard]] bool within(StageSet o) const noexcept { return (bits & ~o.bits) == 0; }
    StageSet& operator|=(StageSet o) noexcept {
        bits |= o.bits;
        return *this;
    }
    friend bool operator==(StageSet, StageSet) = default;
};
[[nodiscard]] constexpr StageSet only(Stage s) noexcept { return {1u << static_cast<uint32_t>(s)}; }

/// A set of AccessType values.
struct AccessSet {
    uint32_t bits = 0;
    [[nodiscard]] bool has(AccessType a) const noexcept { return bits >> static_cast<uint32_t>(a) & 1u; }
    [[nodiscard]] bool empty() const noexcept { return bits == 0; }
    friend bool operator==(AccessSet, AccessSet) = default;
};

/// Every access type that writes memory.
[[nodiscard]] AccessSet writeAccessTypes() noexcept;

/// A set of (stage, access type) pairs: an access scope, or what one access performs. Only
/// pairs where the stage can perform the access type are ever present.
struct AccessScope {
    std::array<uint32_t, kStageCount> accessAt{};  ///< Per Stage: AccessSet bits.

    [[nodiscard]] bool empty() const noexcept;
    [[nodiscard]] bool contains(const AccessScope& o) const noexcept;
    /// The pairs of this scope whose access type writes.
    [[nodiscard]] AccessScope writesOnly() const noexcept;
    AccessScope& operator|=(const AccessScope& o) noexcept;
    /// Every pair (used for semaphores and fences, whose access scopes are all device access).
    [[nodiscard]] static AccessScope allDeviceAccess() noexcept;
};

/// What one side of a synchronization command's stage mask means.
enum class ScopeSide : uint8_t { First, Second };

/// The first (or second) synchronization scope of a stage mask: the stages named, meta stages
/// broken up, plus every logically earlier (later) stage of each pipeline a named stage is in.
/// TOP_OF_PIPE is nothing in a first scope and every stage in a second one; BOTTOM_OF_PIPE the
/// reverse. ALL_COMMANDS is every stage a queue executes (not HOST).
[[nodiscard]] StageSet synchronizationScope(VkPipelineStageFlags2 mask, ScopeSide side) noexcept;
/// The stages an access scope names: meta stages broken up, never expanded by logical order
/// (the spec's "access scopes do not interact with the logically earlier or later stages").
[[nodiscard]] StageSet accessScopeStages(VkPipelineStageFlags2 mask) noexcept;
/// Every stage a queue executes: ALL_COMMANDS.
[[nodiscard]] StageSet allDeviceStages() noexcept;
/// The stage bits a queue of this kind supports (Vulkan 1.3, "Supported pipeline stage
/// flags"): every one on graphics; compute shaders, indirect reads, copies and clears on
/// compute; copies on transfer; and the stages every queue has (top, bottom, host, all commands).
[[nodiscard]] VkPipelineStageFlags2 stagesOfQueue(QueueKind queue) noexcept;

/// The access types of a mask with its aliases broken up.
[[nodiscard]] AccessSet accessTypes(VkAccessFlags2 mask) noexcept;
/// The access scope of a (stage mask, access mask) pair, as a barrier's source or destination
/// side defines it: each named stage with the named access types it can perform.
[[nodiscard]] AccessScope accessScope(VkPipelineStageFlags2 stages, VkAccessFlags2 access) noexcept;

/// Bits of a mask that the verifier does not model (extension stages or accesses).
[[nodiscard]] VkPipelineStageFlags2 unmodelledStages(VkPipelineStageFlags2 mask) noexcept;
[[nodiscard]] VkAccessFlags2 unmodelledAccess(VkAccessFlags2 mask) noexcept;
/// The access bits of `access` that no stage of `stages` can perform (a mask the spec's valid
/// usage rules forbid). MEMORY_READ/WRITE never count: they mean "whatever is valid here".
[[nodiscard]] VkAccessFlags2 accessUnsupportedByStages(VkPipelineStageFlags2 stages, VkAccessFlags2 access) noexcept;

/// The stages and access types a usage performs, from the graph vocabulary alone (docs:
/// "Usages"): e.g. Write@Compute as storage is COMPUTE_SHADER with SHADER_STORAGE_WRITE. Render
/// pass load and store operations of attachments add theirs (LOAD reads; CLEAR and DONT_CARE
/// write; STORE and DONT_CARE store by writing, NONE touches nothing). A transfer needs the
/// whole transfer stage: the verifier does not know which transfer command records it.
struct RequiredScope {
    VkPipelineStageFlags2 stages = 0;
    VkAccessFlags2 access = 0;
};
[[nodiscard]] RequiredScope requiredScope(const PlannedUsage& usage, bool image) noexcept;

/// "COMPUTE_SHADER|FRAGMENT_SHADER", "SHADER_STORAGE_WRITE", for messages.
[[nodiscard]] std::string stageNames(VkPipelineStageFlags2 mask);
[[nodiscard]] std::string accessNames(VkAccessFlags2 mask);
[[nodiscard]] std::string layoutNameShort(VkImageLayout layout);

}  // namespace skygraph::verifier
