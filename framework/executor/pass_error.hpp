// How the executor's errors name what they are about: "pass 'P', resource 'R': what".
#pragma once

#include <skygraph/plan.hpp>

#include <exception>
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

/// The message of `e`, thrown by a pass's own code while the renderer was `doing` something
/// for `pass`, naming the pass unless it already does.
inline std::string passError(const PlannedPass& pass, const std::string& doing, const std::exception& e) {
    const std::string what = e.what();
    if (what.starts_with("pass '" + std::string(pass.name) + "'")) return what;
    return passError(pass, "", doing + ": " + what);
}

}  // namespace skygraph::detail
