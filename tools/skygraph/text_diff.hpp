// Line diffs of plan texts for `skygraph compile --watch`, in the unified format people read
// in code review. The diff itself is Debian's dtl (diff template library).
#pragma once

#include <string>
#include <string_view>

namespace skygraph::cli {

/// A unified diff ("--- before", "+++ after", "@@ -a,b +c,d @@" hunks with three lines of
/// context) turning `before` into `after`, compared line by line. Empty when they are equal.
[[nodiscard]] std::string unifiedDiff(const std::string& before, const std::string& after,
                                      std::string_view beforeName, std::string_view afterName);

}  // namespace skygraph::cli
