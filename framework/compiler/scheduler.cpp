#include "scheduler.hpp"

#include "subresources.hpp"

#include <algorithm>
#include <map>
#include <span>

namespace skygraph {
namespace {

std::string onOff(bool v) { return v ? "on" : "off"; }

/// Whether a write of a pass (`uses`) reaches a subresource that is live (`liveFrom`: flat,
/// per subresource, non-zero when live).
bool writesLive(const GraphIndex& index, std::span<const IndexedUsage> uses, const std::vector<uint32_t>& liveFrom) {
    for (const auto& u : uses) {
        if (!writesContents(u.usage.access)) continue;
        bool anyLive = false;
        index.forEachCell(u, [&](size_t i) { anyLive |= liveFrom[i] != 0; });
        if (anyLive) return true;
    }
    return false;
}

/// Why a pass whose writes nobody reads is culled, naming what it writes.
std::string unreadWritesReason(const GraphDesc& graph, const PassDesc& pass) {
    std::vector<const std::string*> names;
    for (const auto& u : pass.uses) {
        if (!writesContents(u.usage.access)) continue;
        const std::string& name = graph.resources[u.resource].name;
        if (std::find_if(names.begin(), names.end(), [&](const std::string* n) { return *n == name; }) ==
            names.end())
            names.push_back(&name);
    }
    if (names.empty()) return "it writes nothing (mark it never_cull if it has side effects)";
    // An exported resource is live at the end: what this pass wrote of it, a later pass
    // wrote over before anything read it.
    std::string unread, overwritten;
    for (const std::string* n : names) {
        std::string& list = graph.findResource(*n)->isExported() ? overwritten : unread;
        list += (list.empty() ? "'" : ", '") + *n + "'";
    }
    std::string reason = "nothing reads what it writes: ";
    if (!unread.empty()) reason += "no later pass that runs reads " + unread + " and none of it is exported";
    if (!unread.empty() && !overwritten.empty()) reason += "; ";
    if (!overwritten.empty())
        reason += "a later pass that runs writes over what it writes of " + overwritten + " before anything reads it";
    return reason;
}

/// Culling: backwards liveness per subresource. Contents are live if an exported resource
/// holds them at the end or a kept pass reads them later; a pass that writes nothing live
/// (and is not never_cull) is removed: marked in `culled`, its reason in `reasons`.
void cullUnreadPasses(const GraphIndex& index, std::vector<uint8_t>& culled, std::map<size_t, std::string>& reasons) {
    const GraphDesc& graph = index.graph();
    // Per subresource, why its contents are live here: 0 they are not, 1 they are exported,
    // p + 2 kept pass p reads them. A kept pass's writes end liveness and its reads begin it,
    // the reads winning where both touch a subresource; the stamp lets one loop over its
    // usages do both, whichever order they come in.
    const std::vector<uint8_t>& atEnd = index.liveAtEnd();
    std::vector<uint32_t> liveFrom(atEnd.begin(), atEnd.end());
    for (size_t p = index.passes(); p-- > 0;) {
        if (!index.active(p)) continue;
        const auto uses = index.usesOf(p);
        if (!index.neverCull(p) && !writesLive(index, uses, liveFrom)) {
            culled[p] = 1;
            reasons[p] = unreadWritesReason(graph, graph.passes[p]);
            continue;
        }
        const auto stamp = static_cast<uint32_t>(p + 2);
        for (const auto& u : uses) {
            if (readsContents(u.usage.access))
                index.forEachCell(u, [&](size_t i) { liveFrom[i] = stamp; });
            else  // a Write
                index.forEachCell(u, [&](size_t i) { if (liveFrom[i] != stamp) liveFrom[i] = 0; });
        }
    }
}

}  // namespace

std::string conditionReason(const Condition& c, const FeatureValues& features) {
    auto value = [&](const std::string& f) {
        auto it = features.find(f);
        return it != features.end() && it->second;
    };
    if (c.features().size() == 1 && c.text().find_first_of("!&|()") == std::string::npos)
        return "feature '" + c.features().front() + "' is off";
    if (c.features().empty()) return "condition '" + c.text() + "' is always false";
    std::string values;
    for (const auto& f : c.features()) values += (values.empty() ? "" : ", ") + f + "=" + onOff(value(f));
    return "condition '" + c.text() + "' is false (" + values + ")";
}

Schedule schedulePasses(const GraphIndex& index, const FeatureValues& features, bool cull) {
    const GraphDesc& graph = index.graph();
    // Culled passes are usually few: their reasons are kept apart, not one string per pass.
    std::vector<uint8_t> culled(index.passes());
    std::map<size_t, std::string> reasons;
    for (size_t p = 0; p < index.passes(); ++p)
        if (!index.active(p)) {
            culled[p] = 1;
            reasons[p] = conditionReason(graph.passes[p].condition, features);
        }
    if (cull) cullUnreadPasses(index, culled, reasons);

    Schedule s;
    s.passes.reserve(index.passes() - reasons.size());
    for (size_t p = 0; p < index.passes(); ++p) {
        if (!culled[p]) {
            s.passes.push_back(static_cast<uint32_t>(p));
            s.usages += index.usesOf(p).size();
        }
    }
    for (auto& [p, reason] : reasons) s.culled.push_back({graph.passes[p].name, std::move(reason)});  // file order
    return s;
}

}  // namespace skygraph
