// Pieces every skygraph subcommand shares: feature flags, safe output, error reporting.
#pragma once

#include <skygraph/condition.hpp>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace skygraph::cli {

/// A command-line mistake: exit status 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// "NAME=on|off" strings -> values. Throws UsageError on bad syntax.
[[nodiscard]] FeatureValues parseFeatureFlags(const std::vector<std::string>& flags);

/// Writes `text` to `path` (stdout when empty) through a temporary file and a rename, so a
/// failure never leaves half a file behind.
void writeOutput(const std::string& path, const std::string& text);

/// Runs a subcommand, turning exceptions into the contract's exit statuses and messages.
[[nodiscard]] int runGuarded(const std::function<int()>& body);

}  // namespace skygraph::cli
