#include "scheduler.hpp"

#include "printable_name.hpp"
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

/// Why pass p, whose writes nobody reads, is culled, naming what it writes: per resource,
/// whether nothing later reads what it wrote there, or a later pass wrote over it first (what
/// it wrote is read later, by `readLater`, per subresource, or is exported).
std::string unreadWritesReason(const GraphIndex& index, size_t p, const std::vector<uint8_t>& readLater) {
    const GraphDesc& graph = index.graph();
    std::vector<uint32_t> written;  // resources, in the order the pass names them
    std::vector<uint8_t> overwritten;
    for (const IndexedUsage& u : index.usesOf(p)) {
        if (!writesContents(u.usage.access)) continue;
        bool readAfter = graph.resources[u.resource].isExported();
        index.forEachCell(u, [&](size_t i) { readAfter |= readLater[i] != 0; });
        const auto at = std::find(written.begin(), written.end(), u.resource);
        if (at == written.end()) {
            written.push_back(u.resource);
            overwritten.push_back(readAfter);
        } else {
            overwritten[size_t(at - written.begin())] |= readAfter;
        }
    }
    if (written.empty()) return "it writes nothing (mark it never_cull if it has side effects)";
    std::string unread, overwrittenNames;
    for (size_t i = 0; i < written.size(); ++i) {
        std::string& list = overwritten[i] ? overwrittenNames : unread;
        list += (list.empty() ? "'" : ", '") + graph.resources[written[i]].name + "'";
    }
    std::string reason = "nothing reads what it writes: ";
    if (!unread.empty()) reason += "no later pass that runs reads " + unread + " and none of it is exported";
    if (!unread.empty() && !overwrittenNames.empty()) reason += "; ";
    if (!overwrittenNames.empty())
        reason += "a later pass that runs writes over what it writes of " + overwrittenNames + " before anything reads it";
    return reason;
}

/// Culling: backwards liveness per subresource. Contents are live if an exported resource
/// holds them at the end or a kept pass reads them later; a pass that writes nothing live
/// (and is not never_cull) is removed: marked in `culled`, its reason in `reasons`.
void cullUnreadPasses(const GraphIndex& index, std::vector<uint8_t>& culled, std::map<size_t, std::string>& reasons) {
    // Per subresource, why its contents are live here: 0 they are not, 1 they are exported,
    // p + 2 kept pass p reads them. A kept pass's writes end liveness and its reads begin it,
    // the reads winning where both touch a subresource; the stamp lets one loop over its
    // usages do both, whichever order they come in.
    const std::vector<uint8_t>& atEnd = index.liveAtEnd();
    std::vector<uint32_t> liveFrom(atEnd.begin(), atEnd.end());
    // Per subresource, whether a kept pass after this one reads it: what a culled pass's reason
    // tells apart.
    std::vector<uint8_t> readLater(liveFrom.size());
    for (size_t p = index.passes(); p-- > 0;) {
        if (!index.active(p)) continue;
        const auto uses = index.usesOf(p);
        if (!index.neverCull(p) && !writesLive(index, uses, liveFrom)) {
            culled[p] = 1;
            reasons[p] = unreadWritesReason(index, p, readLater);
            continue;
        }
        const auto stamp = static_cast<uint32_t>(p + 2);
        for (const auto& u : uses) {
            if (readsContents(u.usage.access))
                index.forEachCell(u, [&](size_t i) {
                    liveFrom[i] = stamp;
                    readLater[i] = 1;
                });
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
    // One line wherever the reason is shown (a text plan, a DOT label, a log): a condition
    // written over several lines shows its line breaks escaped.
    const std::string text = printableName(c.text());
    if (c.features().empty()) return "condition '" + text + "' is always false";
    std::string values;
    for (const auto& f : c.features()) values += (values.empty() ? "" : ", ") + f + "=" + onOff(value(f));
    return "condition '" + text + "' is false (" + values + ")";
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
