#include "scheduler.hpp"

#include "subresources.hpp"

#include <algorithm>

namespace skygraph {
namespace {

std::string onOff(bool v) { return v ? "on" : "off"; }

std::string conditionReason(const Condition& c, const FeatureValues& features) {
    auto value = [&](const std::string& f) {
        auto it = features.find(f);
        return it != features.end() && it->second;
    };
    if (c.features().size() == 1 && c.text().find_first_of("!&|()") == std::string::npos)
        return "feature '" + c.features().front() + "' is off";
    std::string values;
    for (const auto& f : c.features()) values += (values.empty() ? "" : ", ") + f + "=" + onOff(value(f));
    return "condition '" + c.text() + "' is false (" + values + ")";
}

std::vector<SubresourceGrid> grids(const GraphDesc& g, uint32_t w, uint32_t h) {
    std::vector<SubresourceGrid> out;
    out.reserve(g.resources.size());
    for (const auto& r : g.resources) out.emplace_back(r, w, h);
    return out;
}

}  // namespace

std::vector<bool> activePasses(const GraphDesc& graph, const std::optional<FeatureValues>& features) {
    std::vector<bool> active(graph.passes.size(), true);
    if (features)
        for (size_t i = 0; i < graph.passes.size(); ++i)
            active[i] = graph.passes[i].condition.evaluate(*features);
    return active;
}

void checkReadsHaveSources(const GraphDesc& graph, const std::optional<FeatureValues>& features,
                           Diagnostics& out, uint32_t outputWidth, uint32_t outputHeight) {
    const auto active = activePasses(graph, features);
    const auto grid = grids(graph, outputWidth, outputHeight);
    std::vector<std::vector<bool>> written(graph.resources.size());
    for (size_t r = 0; r < graph.resources.size(); ++r) {
        const auto& res = graph.resources[r];
        written[r].assign(grid[r].size(), res.clear.has_value() || res.external);
    }
    for (size_t p = 0; p < graph.passes.size(); ++p) {
        if (!active[p]) continue;
        const auto& pass = graph.passes[p];
        for (const auto& u : pass.uses) {
            if (!readsContents(u.usage.access)) continue;
            bool missing = false;
            grid[u.resource].forEach(grid[u.resource].resolve(u.usage),
                                     [&](size_t i) { missing |= !written[u.resource][i]; });
            if (!missing) continue;
            const auto& res = graph.resources[u.resource];
            std::string msg = "reads '" + res.name + "' (" + toString(u.usage) +
                              ") but no earlier pass writes it, and it is neither `clear` nor `external`";
            // Point at the writer that a feature switched off, which is the usual cause.
            for (size_t q = 0; q < p; ++q) {
                if (active[q]) continue;
                for (const auto& w : graph.passes[q].uses)
                    if (w.resource == u.resource && writesContents(w.usage.access) && features) {
                        msg += "; its writer '" + graph.passes[q].name + "' is off: " +
                               conditionReason(graph.passes[q].condition, *features);
                        q = p;
                        break;
                    }
            }
            out.add({graph.file, u.jsonPath, pass.name, res.name, msg});
        }
        for (const auto& u : pass.uses)
            if (writesContents(u.usage.access))
                grid[u.resource].forEach(grid[u.resource].resolve(u.usage),
                                         [&](size_t i) { written[u.resource][i] = true; });
    }
}

Schedule schedulePasses(const GraphDesc& graph, const FeatureValues& features, bool cull,
                        uint32_t outputWidth, uint32_t outputHeight) {
    const auto active = activePasses(graph, features);
    const auto grid = grids(graph, outputWidth, outputHeight);
    std::vector<std::string> reasons(graph.passes.size());
    for (size_t p = 0; p < graph.passes.size(); ++p)
        if (!active[p]) reasons[p] = conditionReason(graph.passes[p].condition, features);

    if (cull) {
        // Backwards liveness per subresource: contents are live if an exported resource holds
        // them at the end or a kept pass reads them later.
        std::vector<std::vector<bool>> live(graph.resources.size());
        for (size_t r = 0; r < graph.resources.size(); ++r)
            live[r].assign(grid[r].size(), graph.resources[r].isExported());
        for (size_t p = graph.passes.size(); p-- > 0;) {
            if (!active[p]) continue;
            const auto& pass = graph.passes[p];
            bool needed = pass.neverCull;
            std::vector<std::string> deadWrites;
            for (const auto& u : pass.uses) {
                if (!writesContents(u.usage.access)) continue;
                bool anyLive = false;
                grid[u.resource].forEach(grid[u.resource].resolve(u.usage),
                                         [&](size_t i) { anyLive |= live[u.resource][i]; });
                needed |= anyLive;
                const auto& name = graph.resources[u.resource].name;
                if (std::find(deadWrites.begin(), deadWrites.end(), name) == deadWrites.end())
                    deadWrites.push_back(name);
            }
            if (!needed) {
                if (deadWrites.empty()) {
                    reasons[p] = "it writes nothing (mark it never_cull if it has side effects)";
                } else {
                    std::string list;
                    for (const auto& n : deadWrites) list += (list.empty() ? "'" : ", '") + n + "'";
                    reasons[p] = "nothing reads what it writes: no later pass reads " + list +
                                 " and none of it is exported";
                }
                continue;
            }
            for (const auto& u : pass.uses)
                if (u.usage.access == Access::Write)
                    grid[u.resource].forEach(grid[u.resource].resolve(u.usage),
                                             [&](size_t i) { live[u.resource][i] = false; });
            for (const auto& u : pass.uses)
                if (readsContents(u.usage.access))
                    grid[u.resource].forEach(grid[u.resource].resolve(u.usage),
                                             [&](size_t i) { live[u.resource][i] = true; });
        }
    }

    Schedule s;
    for (size_t p = 0; p < graph.passes.size(); ++p) {
        if (reasons[p].empty()) s.passes.push_back(static_cast<uint32_t>(p));
        else s.culled.push_back({graph.passes[p].name, reasons[p]});
    }
    return s;
}

}  // namespace skygraph
