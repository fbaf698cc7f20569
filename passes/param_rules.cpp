#include "param_rules.hpp"

#include "integer_hint.hpp"

#include <algorithm>

namespace skygraph::passes {

using nlohmann::json;

SlotDecl slot(std::string name, Stage stage, std::vector<Access> accesses, BindAs as, std::string doc,
              bool optional, bool repeated) {
    return SlotDecl{std::move(name), stage, std::move(accesses), as, optional, repeated, std::move(doc)};
}

SlotDecl byNameOnly(SlotDecl decl) {
    decl.byNameOnly = true;
    return decl;
}

SlotDecl ofTypes(SlotDecl decl, std::vector<ResourceType> types) {
    decl.types = std::move(types);
    return decl;
}

ParamValidator rules(std::vector<ParamRule> list) {
    return [list = std::move(list)](const json& params) {
        std::vector<ParamError> errors;
        for (const auto& item : params.items()) {
            // Named copies, not structured bindings: clang 14 (the fuzz build) cannot capture those.
            const std::string& key = item.key();
            const json& value = item.value();
            auto it = std::find_if(list.begin(), list.end(), [&](const ParamRule& r) { return r.key == key; });
            if (it == list.end()) {
                std::string known;
                for (const auto& r : list) known += (known.empty() ? "" : ", ") + r.key;
                errors.push_back(ParamError::forKey(key, "unknown parameter; expected " + (known.empty() ? "none" : known)));
                continue;
            }
            if (std::string problem = it->check(value); !problem.empty())
                errors.push_back(ParamError::forKey(key, std::move(problem)));
        }
        return errors;
    };
}

ParamCheck oneOf(std::vector<std::string> values) {
    return [values = std::move(values)](const json& v) -> std::string {
        if (v.is_string() && std::find(values.begin(), values.end(), v.get<std::string>()) != values.end())
            return {};
        std::string list;
        for (const auto& s : values) list += (list.empty() ? "" : ", ") + s;
        return "expected one of " + list + ", got " + v.dump();
    };
}

ParamCheck numberIn(double lo, double hi) {
    return [lo, hi](const json& v) -> std::string {
        if (v.is_number() && v.get<double>() >= lo && v.get<double>() <= hi) return {};
        return "expected a number in [" + json(lo).dump() + ", " + json(hi).dump() + "], got " + v.dump();
    };
}

ParamCheck integerIn(int64_t lo, int64_t hi) {
    return [lo, hi](const json& v) -> std::string {
        if (v.is_number_integer() && v.get<int64_t>() >= lo && v.get<int64_t>() <= hi) return {};
        return "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + v.dump() +
               (v.is_number_float() ? integerHint(v.get<double>(), double(lo), double(hi)) : "");
    };
}

}  // namespace skygraph::passes
