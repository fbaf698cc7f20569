// Collecting findings: a cap on their number, and one finding per problem however many
// subresources or frames show it.
#pragma once

#include <skygraph/verifier.hpp>

#include <set>
#include <string>
#include <tuple>

namespace skygraph::verifier {

class Reporter {
public:
    explicit Reporter(size_t maxFindings) : max_(maxFindings) {}

    /// Adds `f` unless one of the same kind at the same two sites is already there.
    void add(Finding f);
    /// Adds a finding at one site, naming plan resource `resource` when it is one (-1: none).
    void addAt(FindingKind kind, FindingSite site, std::string reason, const Plan& plan, int64_t resource = -1);
    [[nodiscard]] bool full() const noexcept { return report_.truncated; }
    [[nodiscard]] VerificationReport& report() noexcept { return report_; }

private:
    size_t max_;
    VerificationReport report_;
    std::set<std::tuple<FindingKind, std::string, std::string, std::string>> seen_;
};

}  // namespace skygraph::verifier
