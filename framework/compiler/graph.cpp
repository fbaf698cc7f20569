#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include "json_path.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

// Layout, for the compiler's sweeps (graph.hpp documents the API only): a UsageDecl is 32
// bytes of plain data, since the compiler reads every one; that is why its slot is an id into
// the graph's names and its JSON path is derived, neither stored as text. PassDesc's members
// that the compiler reads of every pass (name, type, the flags, uses, the condition's root)
// come first, within its first two cache lines; the condition's text and names, the params
// and the path follow.

namespace skygraph {

std::string_view toString(ResourceType type) noexcept {
    switch (type) {
        case ResourceType::Image2D: return "image2d";
        case ResourceType::Cube: return "cube";
        case ResourceType::Image2DArray: return "image2d_array";
        case ResourceType::Buffer: return "buffer";
    }
    return "?";
}

std::string_view toString(ExternalState state) noexcept {
    switch (state) {
        case ExternalState::None: return "None";
        case ExternalState::Present: return "Present";
        case ExternalState::TransferSrc: return "TransferSrc";
        case ExternalState::ShaderRead: return "ShaderRead";
        case ExternalState::General: return "General";
    }
    return "?";
}

PassParams::PassParams() noexcept = default;
PassParams::PassParams(nlohmann::json object) {
    if (!object.is_object()) throw std::invalid_argument("PassParams: params must be a JSON object");
    if (!object.empty()) object_ = std::make_unique<nlohmann::json>(std::move(object));
}
PassParams::PassParams(const PassParams& other)
    : object_(other.object_ ? std::make_unique<nlohmann::json>(*other.object_) : nullptr) {}
PassParams::PassParams(PassParams&& other) noexcept = default;
PassParams& PassParams::operator=(const PassParams& other) {
    if (this != &other) *this = PassParams(other);
    return *this;
}
PassParams& PassParams::operator=(PassParams&& other) noexcept = default;
PassParams::~PassParams() = default;

const nlohmann::json& PassParams::json() const noexcept {
    static const nlohmann::json empty = nlohmann::json::object();
    return object_ ? *object_ : empty;
}

nlohmann::json& PassParams::edit() {
    if (!object_) object_ = std::make_unique<nlohmann::json>(nlohmann::json::object());
    return *object_;
}

nlohmann::json& PassParams::operator[](std::string_view key) { return edit()[std::string(key)]; }

bool PassParams::empty() const noexcept { return !object_ || object_->empty(); }

std::string_view toString(LayoutPolicy policy) noexcept {
    return policy == LayoutPolicy::Optimal ? "optimal" : "fewest-barriers";
}

std::optional<LayoutPolicy> parseLayoutPolicy(std::string_view s) noexcept {
    if (s == "fewest-barriers") return LayoutPolicy::FewestBarriers;
    if (s == "optimal") return LayoutPolicy::Optimal;
    return std::nullopt;
}

std::string_view toString(QueueKind queue) noexcept {
    switch (queue) {
        case QueueKind::Compute: return "compute";
        case QueueKind::Transfer: return "transfer";
        case QueueKind::Graphics: break;
    }
    return "graphics";
}

std::optional<QueueKind> parseQueueKind(std::string_view s) noexcept {
    if (s == "graphics") return QueueKind::Graphics;
    if (s == "compute") return QueueKind::Compute;
    if (s == "transfer") return QueueKind::Transfer;
    return std::nullopt;
}

std::string_view toString(Sharing sharing) noexcept {
    switch (sharing) {
        case Sharing::Exclusive: return "exclusive";
        case Sharing::Concurrent: return "concurrent";
        case Sharing::Auto: break;
    }
    return "auto";
}

std::optional<Sharing> parseSharing(std::string_view s) noexcept {
    if (s == "auto") return Sharing::Auto;
    if (s == "exclusive") return Sharing::Exclusive;
    if (s == "concurrent") return Sharing::Concurrent;
    return std::nullopt;
}

uint32_t ResourceDesc::mipCount(uint32_t outputWidth, uint32_t outputHeight) const noexcept {
    if (mips != 0) return mips;
    auto [w, h] = extent.resolve(outputWidth, outputHeight);
    return static_cast<uint32_t>(std::bit_width(std::max(w, h)));
}

FeatureValues GraphDesc::defaultFeatures() const {
    FeatureValues out;
    for (const auto& f : features) out[f.name] = f.defaultValue;
    return out;
}

const ResourceDesc* GraphDesc::findResource(std::string_view n) const noexcept {
    for (const auto& r : resources)
        if (r.name == n) return &r;
    return nullptr;
}

SlotId GraphDesc::internSlot(std::string_view slot) {
    if (slot.empty()) return 0;
    // A graph has a few slot names (its pass types'), so a search beats a map.
    const auto it = std::find(slotNames.begin(), slotNames.end(), slot);
    if (it != slotNames.end()) return static_cast<SlotId>(it - slotNames.begin()) + 1;
    slotNames.emplace_back(slot);
    return static_cast<SlotId>(slotNames.size());
}

std::string ResourceDesc::jsonPath() const { return jsonPathMember("resources", name); }

std::string GraphDesc::usageJsonPath(size_t pass, size_t use) const {
    const PassDesc& p = passes.at(pass);
    std::string path = p.jsonPath.empty() ? "passes[" + std::to_string(pass) + "]" : p.jsonPath;
    const uint32_t r = p.uses.at(use).resource;
    // A GraphDesc built in code may name a resource that is not there (compile() reports it).
    if (p.usesByName && r < resources.size()) return jsonPathMember(path + ".uses", resources[r].name);
    return path + ".uses[" + std::to_string(use) + "]";
}

}  // namespace skygraph
