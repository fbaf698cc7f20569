// Building blocks of the built-in pass types' declarations: a slot in one call, and params
// validators from (key, check) rules. Each pass's *_type.cpp declares its type with them.
#pragma once

#include <skygraph/pass_registry.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace skygraph::passes {

[[nodiscard]] SlotDecl slot(std::string name, Stage stage, std::vector<Access> accesses, BindAs as, std::string doc,
                            bool optional = false, bool repeated = false);
/// `decl`, bound only by name (SlotDecl::byNameOnly).
[[nodiscard]] SlotDecl byNameOnly(SlotDecl decl);
/// `decl`, filled only by resources of `types` (SlotDecl::types).
[[nodiscard]] SlotDecl ofTypes(SlotDecl decl, std::vector<ResourceType> types);

/// Checks one parameter's value: an empty string when it is fine, else what is wrong.
using ParamCheck = std::function<std::string(const nlohmann::json&)>;

/// One known parameter of a pass type and the check of its value.
struct ParamRule {
    std::string key;
    ParamCheck check;
};

/// A validator accepting exactly the keys of `list`, each checked by its rule; any other key
/// is an error listing the known ones.
[[nodiscard]] ParamValidator rules(std::vector<ParamRule> list);

/// A string out of `values`.
[[nodiscard]] ParamCheck oneOf(std::vector<std::string> values);
/// A number in [lo, hi].
[[nodiscard]] ParamCheck numberIn(double lo, double hi);
/// An integer in [lo, hi].
[[nodiscard]] ParamCheck integerIn(int64_t lo, int64_t hi);

}  // namespace skygraph::passes
