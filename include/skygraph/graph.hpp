// A graph file after loading: validated, with every usage bound to a slot of its pass type.
#pragma once

#include <skygraph/condition.hpp>
#include <skygraph/format.hpp>
#include <skygraph/usage.hpp>

#include <nlohmann/json_fwd.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

enum class ResourceType : uint8_t { Image2D, Cube, Image2DArray, Buffer };
/// Its name in graph files: "image2d", "cube", "image2d_array", "buffer".
[[nodiscard]] std::string_view toString(ResourceType type) noexcept;

/// The state a resource arrives in (`initial`) or is left in (`final`): docs/graph-format.md,
/// "External, initial and final".
enum class ExternalState : uint8_t { None, Present, TransferSrc, ShaderRead, General };
/// Its name in graph files ("ShaderRead"); "None" for None.
[[nodiscard]] std::string_view toString(ExternalState state) noexcept;

/// The kind of queue a pass runs on (a pass's `"queue"`). The executor maps each kind to a
/// queue of a family that supports it, and to fewer queues where the device has fewer.
enum class QueueKind : uint8_t { Graphics, Compute, Transfer };
inline constexpr size_t kQueueKinds = 3;
/// "graphics", "compute" or "transfer", as graph files spell them; a view of static storage.
[[nodiscard]] std::string_view toString(QueueKind queue) noexcept;
/// Whether a queue of this kind can perform a usage at `stage`: graphics every stage, compute
/// compute shaders, indirect arguments and copies, transfer copies only.
[[nodiscard]] constexpr bool queueSupports(QueueKind queue, Stage stage) noexcept {
    switch (queue) {
        case QueueKind::Graphics: return true;
        case QueueKind::Compute: return stage == Stage::Compute || stage == Stage::Transfer || stage == Stage::Indirect;
        case QueueKind::Transfer: return stage == Stage::Transfer;
    }
    return false;
}
/// The inverse of toString; nullopt for an unknown name. `s` is read during the call only.
[[nodiscard]] std::optional<QueueKind> parseQueueKind(std::string_view s) noexcept;

/// How a resource used on queues of different families is shared between them (a resource's
/// `"sharing"`): docs/queues.md, "Ownership".
enum class Sharing : uint8_t {
    /// The compiler's choice: Concurrent for buffers, Exclusive for images.
    Auto,
    /// VK_SHARING_MODE_EXCLUSIVE: a queue family owns it, and the plan moves it between
    /// families with release/acquire barrier pairs where its contents must survive.
    Exclusive,
    /// VK_SHARING_MODE_CONCURRENT over the families that use it: no ownership transfers.
    Concurrent,
};
/// "auto", "exclusive" or "concurrent"; a view of static storage.
[[nodiscard]] std::string_view toString(Sharing sharing) noexcept;
[[nodiscard]] std::optional<Sharing> parseSharing(std::string_view s) noexcept;

/// `"output"`, `"output/N"` or `[w, h]`.
struct Extent {
    bool relativeToOutput = true;
    uint32_t divisor = 1;  ///< For output-relative extents.
    uint32_t width = 0;    ///< For fixed extents.
    uint32_t height = 0;

    /// Width and height for a given output size; never below 1 for an extent within the
    /// format's limits (a divisor 1..4096, a fixed size 1..16384 each way), which the loader
    /// and compile() enforce. A divisor of 0 is not one: do not resolve it.
    [[nodiscard]] std::array<uint32_t, 2> resolve(uint32_t outputWidth, uint32_t outputHeight) const noexcept {
        if (!relativeToOutput) return {width, height};
        return {std::max(1u, outputWidth / divisor), std::max(1u, outputHeight / divisor)};
    }
};

struct ClearValue {
    bool isDepth = false;
    std::array<float, 4> color{0, 0, 0, 0};
    float depth = 0.0f;
    uint32_t stencil = 0;
};

struct ResourceDesc {
    std::string name;
    ResourceType type = ResourceType::Image2D;
    FormatInfo format;        ///< Unset (UNDEFINED) for buffers.
    Extent extent;
    uint32_t mips = 1;        ///< 0 means "full": resolved against the extent.
    uint32_t layers = 1;      ///< 6 for cubes.
    uint64_t sizeBytes = 0;   ///< Buffers only.
    std::optional<ClearValue> clear;
    bool external = false;
    ExternalState initial = ExternalState::None;  ///< Meaningful for external resources.
    ExternalState final = ExternalState::None;    ///< None: not exported.
    /// Whether a transient resource may share memory with others (`"alias": false` says not).
    bool alias = true;
    /// How queues of different families share it (`"sharing"`).
    Sharing sharing = Sharing::Auto;

    /// Where a graph file declares it, for messages: `resources.<name>`, or `resources["<name>"]`
    /// for a name that holds a dot, a bracket, a quote, a backslash or white space.
    [[nodiscard]] std::string jsonPath() const;

    [[nodiscard]] bool isImage() const noexcept { return type != ResourceType::Buffer; }
    /// Exported resources are the graph's outputs; passes writing them are never culled.
    [[nodiscard]] bool isExported() const noexcept { return final != ExternalState::None; }
    /// Mip count with "full" resolved for a given output size.
    [[nodiscard]] uint32_t mipCount(uint32_t outputWidth, uint32_t outputHeight) const noexcept;
};

/// A slot name interned in its graph (GraphDesc::internSlot); 0 names no slot.
using SlotId = uint32_t;

/// One entry of a pass's `uses`, bound to a slot of its pass type. Its slot is an id into the
/// graph's slot names, and its JSON path is derived (GraphDesc::usageJsonPath).
struct UsageDecl {
    uint32_t resource = 0;  ///< Index into GraphDesc::resources.
    Usage usage;
    /// The slot it fills (GraphDesc::slotName); 0 for Generic. Ids belong to one graph: a
    /// usage copied into another graph takes its slot's id there (GraphDesc::internSlot).
    SlotId slot = 0;
};

/// A pass's `params`: the JSON object its pass type reads its settings from, e.g.
/// `desc.params.value("exposure_ev", 0.0)`. Owns the object (copying a PassDesc copies it);
/// empty when the file gives none. This header names nlohmann::json only: reading or changing
/// the values needs <nlohmann/json.hpp>.
class PassParams {
public:
    /// An empty object.
    PassParams() noexcept;
    /// Takes `object`. Throws std::invalid_argument if it is not a JSON object.
    explicit PassParams(nlohmann::json object);
    PassParams(const PassParams& other);
    PassParams(PassParams&& other) noexcept;
    PassParams& operator=(const PassParams& other);
    PassParams& operator=(PassParams&& other) noexcept;
    ~PassParams();

    /// The object; an empty one when there are no params. The reference is valid until this
    /// PassParams is changed, assigned to or destroyed.
    [[nodiscard]] const nlohmann::json& json() const noexcept;
    /// The object, to change (e.g. a tool raising a pass's sample count). Keep it an object:
    /// value() of anything else throws nlohmann::json::type_error. The reference is valid until
    /// this PassParams is assigned to, moved from or destroyed.
    [[nodiscard]] nlohmann::json& edit();
    /// A PassParams reads as its object wherever a const nlohmann::json& is wanted.
    operator const nlohmann::json&() const noexcept { return json(); }

    /// The value at `key` converted to T, or `fallback` when there is none; as
    /// nlohmann::json::value (which throws nlohmann::json::type_error for a value that does
    /// not convert to T).
    template <typename T, typename Json = nlohmann::json>
    [[nodiscard]] T value(std::string_view key, const T& fallback) const {
        const Json& object = json();
        return object.value(key, fallback);
    }
    template <typename Json = nlohmann::json>
    [[nodiscard]] std::string value(std::string_view key, const char* fallback) const {
        const Json& object = json();
        return object.value(key, std::string(fallback));
    }
    /// The value at `key`, added as null if there is none (edit()[key]). The reference is
    /// valid until the object loses that key, or this PassParams is assigned to, moved from or
    /// destroyed.
    nlohmann::json& operator[](std::string_view key);

    [[nodiscard]] bool empty() const noexcept;

private:
    std::unique_ptr<nlohmann::json> object_;  ///< Null for an empty object.
};

struct PassDesc {
    std::string name;
    std::string type;
    bool neverCull = false;
    /// The queue it runs on (`"queue"`). The file's order stays the frame's order.
    QueueKind queue = QueueKind::Graphics;
    /// Whether the file writes `uses` as an object keyed by resource name (each usage's JSON
    /// path ends in ".uses.<resource>") rather than an array (".uses[i]").
    bool usesByName = false;
    std::vector<UsageDecl> uses;
    Condition condition;
    PassParams params;
    std::string jsonPath;  ///< "passes[i]"; empty for a pass built in code (its index is used)
};

/// How the compiler lays out a run of reads of an image, i.e. reads of overlapping subresources
/// with no write between (docs/barriers.md, rule 4). The graph file's `"layouts"` spells them
/// "fewest-barriers" and "optimal".
enum class LayoutPolicy : uint8_t {
    /// The run shares one layout that serves all its readers (GENERAL when no read-only layout
    /// does), so it needs one barrier before its first read however its readers differ.
    FewestBarriers,
    /// Each read finds the image in a layout optimal for it (TRANSFER_SRC_OPTIMAL for a copy,
    /// SHADER_READ_ONLY_OPTIMAL for sampling, GENERAL only for storage): reads share a run only
    /// when one layout is optimal for all of them, and a layout transition separates runs.
    Optimal,
};
/// "fewest-barriers" or "optimal", as graph files spell them; a view of static storage.
[[nodiscard]] std::string_view toString(LayoutPolicy policy) noexcept;
/// The inverse of toString; nullopt for an unknown name. `s` is read during the call only.
[[nodiscard]] std::optional<LayoutPolicy> parseLayoutPolicy(std::string_view s) noexcept;

struct FeatureDecl {
    std::string name;
    bool defaultValue = false;
};

/// A loaded graph file. Plain data; produced by the loader, read by the compiler.
struct GraphDesc {
    std::string file;  ///< For messages: the path it was read from, or "<memory>".
    std::string name;
    std::vector<FeatureDecl> features;
    std::vector<ResourceDesc> resources;
    std::vector<PassDesc> passes;
    /// The file's `"layouts"`; CompileOptions::layouts overrides it when set.
    LayoutPolicy layouts = LayoutPolicy::FewestBarriers;

    /// Defaults from the file's `features`.
    [[nodiscard]] FeatureValues defaultFeatures() const;
    /// The resource named `name`, or null; `name` is read during the call only. The pointer
    /// is into `resources`: valid while this GraphDesc lives, is not assigned to, and
    /// `resources` is not resized or reordered.
    [[nodiscard]] const ResourceDesc* findResource(std::string_view name) const noexcept;
    /// Slot names that usages fill: SlotId i (from 1) is slotNames[i - 1].
    std::vector<std::string> slotNames;

    /// The id of slot name `slot`, added to slotNames if it is new; 0 for an empty name.
    /// Adding a name invalidates the views slotName() returned before.
    SlotId internSlot(std::string_view slot);
    /// The name slot `id` stands for; "" for 0. Throws std::out_of_range for an id the graph
    /// did not hand out. The view is into slotNames: valid until slotNames changes (an
    /// internSlot() of a new name, since a growing vector may move its strings' characters)
    /// or this GraphDesc is destroyed or assigned to. Copy it into a std::string to keep it.
    [[nodiscard]] std::string_view slotName(SlotId id) const {
        return id == 0 ? std::string_view() : std::string_view(slotNames.at(id - 1));
    }
    /// The JSON path of `passes[pass].uses[use]`, for messages: e.g. "passes[1].uses.depth"
    /// (uses written as an object) or "passes[3].uses[2]" (as an array). Both indices must be
    /// in range.
    [[nodiscard]] std::string usageJsonPath(size_t pass, size_t use) const;
};

}  // namespace skygraph
