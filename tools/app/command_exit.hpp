// How `render` and `view` end: the exit code, and the line on stderr that says why.
#pragma once

#include <skygraph/device.hpp>
#include <skygraph/diagnostics.hpp>

#include <exception>
#include <iostream>
#include <string_view>

namespace skygraph::app {

/// 1, with a line naming `command`, when validation ran on `device` and counted a message.
inline int validationExit(const Device& device, std::string_view command) {
    if (!device.validationEnabled() || device.messageCount() == 0) return 0;
    std::cerr << command << ": validation reported " << device.messageCount() << " message(s)\n";
    return 1;
}

/// For a `catch (...)` in a command: a GraphError prints its diagnostics (file, JSON path,
/// pass, resource), any other std::exception "COMMAND: what"; 1 either way. Other exceptions
/// propagate.
inline int exitForCurrentException(std::string_view command) {
    try {
        throw;
    } catch (const GraphError& e) {
        // As `skygraph compile` prints them: one "error: " line per diagnostic.
        for (const auto& d : e.diagnostics().items()) std::cerr << "error: " << d.format() << "\n";
    } catch (const std::exception& e) {
        std::cerr << command << ": " << e.what() << "\n";
    }
    return 1;
}

}  // namespace skygraph::app
