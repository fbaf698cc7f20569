#include <skygraph/diagnostics.hpp>

#include "printable_name.hpp"

namespace skygraph {

std::string Diagnostic::format() const {
    std::string out = file.empty() ? "<memory>" : printableName(file);
    if (line > 0) out += ":" + std::to_string(line) + ":" + std::to_string(column);
    out += ": ";
    if (!jsonPath.empty()) out += printableName(jsonPath) + ": ";
    if (!pass.empty()) out += "pass '" + printableName(pass) + "'" + (resource.empty() ? ": " : ", ");
    if (!resource.empty()) out += "resource '" + printableName(resource) + "': ";
    out += printableName(message);
    return out;
}

std::string Diagnostics::format() const {
    std::string out;
    for (const auto& d : items_) out += d.format() + "\n";
    return out;
}

GraphError::GraphError(Diagnostics d)
    : std::runtime_error(d.format()), diagnostics_(std::move(d)) {}

}  // namespace skygraph
