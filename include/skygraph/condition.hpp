// Feature-flag conditions: the `if` of a pass (docs/graph-format.md, "Features and conditions").
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

/// Feature name -> on/off. Ordered so that printed plans are stable.
using FeatureValues = std::map<std::string, bool>;

/// A parsed boolean expression over feature names with `!`, `&&`, `||` and parentheses.
/// Immutable and cheap to copy (the tree is shared). References from text() and features()
/// are valid while this Condition lives and is not assigned to.
class Condition {
public:
    /// The always-true condition of a pass with no `if`.
    Condition();

    /// Parses `text` (the result keeps its own copy). On failure returns nullopt and sets
    /// `error` to a message that names the column; on success `error` is cleared. Bad text does
    /// not throw. Names are not checked here; see `features()`.
    [[nodiscard]] static std::optional<Condition> parse(const std::string& text, std::string& error);

    /// Whether `name` is a name a condition can hold: ASCII letters, digits and `_`, not
    /// starting with a digit, and neither `true` nor `false`.
    [[nodiscard]] static bool isFeatureName(std::string_view name) noexcept;

    /// A feature that `values` does not name counts as off.
    [[nodiscard]] bool evaluate(const FeatureValues& values) const noexcept;
    /// The source text, or empty for the always-true condition.
    [[nodiscard]] const std::string& text() const noexcept { return text_; }
    /// Every feature name the expression mentions, in order of appearance, without repeats.
    [[nodiscard]] const std::vector<std::string>& features() const noexcept { return names_; }

    struct Node;

private:
    std::shared_ptr<const Node> root_;
    std::string text_;
    std::vector<std::string> names_;
};

}  // namespace skygraph
