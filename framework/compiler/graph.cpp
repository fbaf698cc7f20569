#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

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

std::array<uint32_t, 2> Extent::resolve(uint32_t outputWidth,
                                        uint32_t outputHeight) const noexcept {
    if (!relativeToOutput) return {width, height};
    return {std::max(1u, outputWidth / divisor), std::max(1u, outputHeight / divisor)};
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

std::string GraphDesc::usageJsonPath(size_t pass, size_t use) const {
    const PassDesc& p = passes.at(pass);
    std::string path = p.jsonPath.empty() ? "passes[" + std::to_string(pass) + "]" : p.jsonPath;
    const uint32_t r = p.uses.at(use).resource;
    // A GraphDesc built in code may name a resource that is not there (compile() reports it).
    if (p.usesByName && r < resources.size()) return path + ".uses." + resources[r].name;
    return path + ".uses[" + std::to_string(use) + "]";
}

int32_t Plan::resourceIndex(std::string_view n) const noexcept {
    for (size_t i = 0; i < resources.size(); ++i)
        if (resources[i].name == n) return static_cast<int32_t>(i);
    return -1;
}

namespace {
/// `view`, which points into `from`, moved to the same place in `to`.
template <class T, class U>
std::span<T> rebased(std::span<T> view, const std::vector<U>& from, std::vector<U>& to) {
    if (view.empty()) return {};
    return {to.data() + (view.data() - from.data()), view.size()};
}
}  // namespace

Plan::Plan(const Plan& other)
    : graph(other.graph), features(other.features), outputWidth(other.outputWidth),
      outputHeight(other.outputHeight), resources(other.resources), passes(other.passes),
      finalBarriers(other.finalBarriers), inPassBarriers(other.inPassBarriers), culled(other.culled),
      usages_(other.usages_),
      barriers_(other.barriers_), nameTables_(other.nameTables_) {
    for (PlannedPass& p : passes) {
        p.usages = rebased(p.usages, other.usages_, usages_);
        p.barriers = rebased(p.barriers, other.barriers_, barriers_);
    }
}

Plan& Plan::operator=(const Plan& other) {
    if (this != &other) *this = Plan(other);
    return *this;
}

std::span<Barrier> Plan::barriersOf(size_t pass) {
    const std::span<const Barrier> b = passes.at(pass).barriers;
    if (b.empty()) return {};
    return {barriers_.data() + (b.data() - barriers_.data()), b.size()};
}

void Plan::eraseBarrier(size_t pass, size_t i) {
    const std::span<const Barrier> b = passes.at(pass).barriers;
    if (i >= b.size()) throw std::out_of_range("Plan::eraseBarrier: no such barrier");
    const auto at = b.data() - barriers_.data() + static_cast<std::ptrdiff_t>(i);
    barriers_.erase(barriers_.begin() + at);  // no reallocation: earlier views stay put
    passes[pass].barriers = b.size() == 1 ? std::span<const Barrier>{} : std::span<const Barrier>(b.data(), b.size() - 1);
    for (size_t p = pass + 1; p < passes.size(); ++p)
        if (!passes[p].barriers.empty())
            passes[p].barriers = {passes[p].barriers.data() - 1, passes[p].barriers.size()};
}

}  // namespace skygraph
