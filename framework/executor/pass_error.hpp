// How the executor's errors name what they are about: "pass 'P', resource 'R': what".
#pragma once

#include <skygraph/plan.hpp>

#include <string>
#include <string_view>

namespace skygraph::detail {

/// "pass 'P', resource 'R': what" (", resource" only when `resource` is set).
inline std::string passError(std::string_view pass, const std::string& resource, const std::string& what) {
    std::string s = "pass '" + std::string(pass) + "'";
    if (!resource.empty()) s += ", resource '" + resource + "'";
    return s + ": " + what;
}

inline std::string passError(const PlannedPass& pass, const std::string& resource, const std::string& what) {
    return passError(pass.name, resource, what);
}

}  // namespace skygraph::detail
