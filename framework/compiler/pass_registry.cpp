#include <skygraph/pass_registry.hpp>
#include <skygraph/plan.hpp>

#include "json_path.hpp"
#include "usage_fit.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <utility>

namespace skygraph {
namespace {

/// Whether some resource that `slot` takes can be used as `mode`, by the rules a file's usages
/// are held to (a vertex input is read, a sampled image is not written, ...).
bool someResourceFits(const SlotDecl& slot, const UsageMode& mode) {
    constexpr UsageSubject kBuffer{false, false, false, false};
    constexpr UsageSubject kColorImage{true, false, true, false};
    constexpr UsageSubject kDepthImage{true, true, false, false};
    const bool images = slot.types.empty() || std::any_of(slot.types.begin(), slot.types.end(),
                                                          [](ResourceType t) { return t != ResourceType::Buffer; });
    return (slot.takes(ResourceType::Buffer) && usageMisfit(kBuffer, mode) == UsageMisfit::Fits) ||
           (images && (usageMisfit(kColorImage, mode) == UsageMisfit::Fits ||
                       usageMisfit(kDepthImage, mode) == UsageMisfit::Fits));
}

}  // namespace

std::string SlotDecl::describeUsage() const {
    std::string out;
    for (size_t i = 0; i < accesses.size(); ++i) {
        if (i) out += "|";
        out += toString(accesses[i]);
    }
    out += "@" + std::string(toString(stage));
    if (as != BindAs::Default) out += " as " + std::string(toString(as));
    return out;
}

bool SlotDecl::accepts(const UsageMode& usage) const noexcept {
    return stage == usage.stage && std::find(accesses.begin(), accesses.end(), usage.access) != accesses.end() &&
           (as == BindAs::Default || as == usage.as);
}

bool SlotDecl::takes(ResourceType type) const noexcept {
    return types.empty() || std::find(types.begin(), types.end(), type) != types.end();
}

bool SlotDecl::takesLayers(const ResourceDesc& resource, uint32_t baseLayer, uint32_t layerCount) const noexcept {
    const bool cubeView = resource.type == ResourceType::Cube && !types.empty();
    return !cubeView || (baseLayer == 0 && layerCount == resource.layers);
}

std::string SlotDecl::describeTypes() const {
    std::string out;
    for (size_t i = 0; i < types.size(); ++i) {
        const std::string type(toString(types[i]));
        out += (i == 0 ? "" : " or ") + std::string(type[0] == 'i' ? "an " : "a ") + type;
    }
    return out;
}

ParamError ParamError::forKey(std::string_view key, std::string message) {
    return {memberPath("", key), std::move(message)};
}

std::string ParamError::memberPath(std::string_view parent, std::string_view key) {
    return jsonPathMember(parent, key);
}

std::string ParamError::pathUnder(std::string_view params) const {
    return std::string(params) + (path.empty() || path.starts_with('[') ? "" : ".") + path;
}

void PassRegistry::add(PassTypeInfo info) {
    if (info.name.empty()) throw std::invalid_argument("pass type with an empty name");
    if (types_.count(info.name))
        throw std::invalid_argument("pass type '" + info.name + "' is already registered");
    // The loader binds nothing to the slots of a type that takes any usage: they would be
    // documentation that no graph can fill.
    if (info.acceptsAnyUsage && !info.slots.empty())
        throw std::invalid_argument("pass type '" + info.name +
                                    "': takes any usage and declares slots (a type does one or the other)");
    std::set<std::string, std::less<>> slotNames;
    for (const auto& slot : info.slots) {
        // An empty name is what a usage without a slot (Generic's) has.
        if (slot.name.empty()) throw std::invalid_argument("pass type '" + info.name + "': a slot with an empty name");
        if (slot.accesses.empty())
            throw std::invalid_argument("pass type '" + info.name + "': slot '" + slot.name +
                                        "' allows no access");
        if (!slotNames.insert(slot.name).second)
            throw std::invalid_argument("pass type '" + info.name + "': duplicate slot '" +
                                        slot.name + "'");
        if (slot.as != BindAs::Default && !isShaderStage(slot.stage) &&
            !(slot.as == BindAs::Index && slot.stage == Stage::VertexInput))
            throw std::invalid_argument("pass type '" + info.name + "': slot '" + slot.name +
                                        "' sets `as` on a non-shader stage");
        // A slot no usage can fill fails every graph that uses the type, at the graph.
        for (const Access access : slot.accesses) {
            const UsageMode mode{access, slot.stage, slot.as};
            if (size_t(access) >= kAccesses || size_t(slot.stage) >= kStages || size_t(slot.as) >= kBindings)
                throw std::invalid_argument("pass type '" + info.name + "': slot '" + slot.name +
                                            "' holds an access, stage or binding outside its enum");
            if (!someResourceFits(slot, mode))
                throw std::invalid_argument("pass type '" + info.name + "': slot '" + slot.name + "' declares " +
                                            toString(mode) + ", which no resource " +
                                            (slot.types.empty() ? "" : "of its types ") + "can be used as");
        }
    }
    std::string name = info.name;
    types_.emplace(std::move(name), std::move(info));
}

const PassTypeInfo* PassRegistry::find(std::string_view name) const noexcept {
    auto it = types_.find(name);
    return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> PassRegistry::names() const {
    std::vector<std::string> out;
    for (const auto& [name, _] : types_) out.push_back(name);
    return out;
}

Diagnostics plannedPassProblems(const Plan& plan, const GraphDesc& graph, const PassRegistry& registry) {
    Diagnostics diags;
    for (const PlannedPass& pass : plan.passes()) {
        const auto index = static_cast<size_t>(pass.declIndex);
        if (pass.declIndex < 0 || index >= graph.passes.size()) continue;  // an inserted step
        const PassDesc& desc = graph.passes[index];
        const PassTypeInfo* type = registry.find(desc.type);
        if (!type || !type->validatePlannedPass) continue;
        const std::string passPath = desc.jsonPath.empty() ? "passes[" + std::to_string(index) + "]" : desc.jsonPath;
        std::vector<UsageError> problems;
        try {
            problems = type->validatePlannedPass(pass, plan);
        } catch (const std::exception& e) {  // the application's code, as validateUsages
            diags.add({graph.file, passPath, desc.name, "",
                       "the plan validator of type '" + type->name + "' threw: " + e.what()});
        } catch (...) {
            diags.add({graph.file, passPath, desc.name, "",
                       "the plan validator of type '" + type->name + "' threw something other than a std::exception"});
        }
        for (UsageError& e : problems) {
            // The plan's usages are the pass's, in its order.
            if (e.usage < pass.usages.size() && e.usage < desc.uses.size())
                diags.add({graph.file, graph.usageJsonPath(index, e.usage), desc.name,
                           graph.resources[desc.uses[e.usage].resource].name, std::move(e.message)});
            else
                diags.add({graph.file, passPath, desc.name, "", std::move(e.message)});
        }
    }
    return diags;
}

}  // namespace skygraph
