// How `skygraph check` reports: a table for people, the failures spelled out under it, and
// JUnit XML for CI systems.
#pragma once

#include "check.hpp"

#include <string>
#include <vector>

namespace skygraph::app {

/// One row per case (graph file as given, combination, passes, culled, barriers, validation
/// messages, performance warnings, golden, verifier, time, result), then each failing case's
/// reasons, its golden diff and its first messages, then a summary line.
[[nodiscard]] std::string checkTable(const std::vector<CheckCase>& cases, bool warningsAsErrors);

/// JUnit XML: a <testsuite> per graph file, a <testcase> per combination (its classname the
/// file, as in the table), a <failure> with the reasons and the diff when it fails, the
/// messages in <system-out>.
[[nodiscard]] std::string checkJUnit(const std::vector<CheckCase>& cases, bool warningsAsErrors);

}  // namespace skygraph::app
