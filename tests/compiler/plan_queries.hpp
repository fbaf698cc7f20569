// What the compiler's rule tests share: the built-in pass types to load graphs with, a
// scheduled pass by name, and the barriers before it on one resource.
#pragma once

#include <skygraph/pass_registry.hpp>
#include <skygraph/plan.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace skygraph::test {

/// The built-in pass types, made once.
inline const PassRegistry& registry() {
    static const PassRegistry r = PassRegistry::withBuiltins();
    return r;
}

/// The scheduled pass called `name`; throws std::runtime_error when there is none.
inline const PlannedPass& pass(const Plan& plan, const std::string& name) {
    for (const auto& p : plan.passes())
        if (p.name == name) return p;
    throw std::runtime_error("no scheduled pass " + name);
}

/// The barriers of one pass that touch one resource, in batch order (copies).
inline std::vector<Barrier> barriersOf(const Plan& plan, const std::string& passName, const std::string& resource) {
    std::vector<Barrier> out;
    for (const auto& b : pass(plan, passName).barriers)
        if (plan.resources()[b.resource].name == resource) out.push_back(b);
    return out;
}

}  // namespace skygraph::test
