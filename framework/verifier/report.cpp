// Findings as text.
#include "report.hpp"

#include <algorithm>

namespace skygraph::verifier {
namespace {

std::string siteText(const FindingSite& s) {
    std::string t = s.step >= 0 ? "[" + std::to_string(s.step) + "] " + s.pass : s.pass;
    if (s.frame != 1) t += " (frame " + std::to_string(s.frame) + ")";
    if (!s.what.empty()) t += " " + s.what;
    return t;
}

std::string key(const FindingSite& s) { return std::to_string(s.frame) + "/" + std::to_string(s.step) + "/" + s.what; }

}  // namespace

std::string_view toString(FindingKind kind) noexcept {
    switch (kind) {
        case FindingKind::MalformedPlan: return "MalformedPlan";
        case FindingKind::InvalidMask: return "InvalidMask";
        case FindingKind::UsageScope: return "UsageScope";
        case FindingKind::Unordered: return "Unordered";
        case FindingKind::NotAvailable: return "NotAvailable";
        case FindingKind::NotVisible: return "NotVisible";
        case FindingKind::PartialAliasBarrier: return "PartialAliasBarrier";
        case FindingKind::LayoutMismatch: return "LayoutMismatch";
        case FindingKind::LayoutNotAllowed: return "LayoutNotAllowed";
        case FindingKind::BadOldLayout: return "BadOldLayout";
        case FindingKind::UndefinedContents: return "UndefinedContents";
        case FindingKind::AliasNotInitialized: return "AliasNotInitialized";
        case FindingKind::LiveOverlap: return "LiveOverlap";
        case FindingKind::PlacementInvalid: return "PlacementInvalid";
        case FindingKind::PresentLayout: return "PresentLayout";
        case FindingKind::FinalLayout: return "FinalLayout";
        case FindingKind::Ownership: return "Ownership";
        case FindingKind::Semaphore: return "Semaphore";
    }
    return "?";
}

std::string format(const Finding& f) {
    std::string names;
    for (const std::string& n : f.resourceNames) names += (names.empty() ? " " : ", ") + n;
    std::string t = std::string(toString(f.kind)) + names + ": " + siteText(f.earlier);
    if (!f.later.pass.empty()) t += " -> " + siteText(f.later);
    return t + ": " + f.reason;
}

size_t VerificationReport::count(FindingKind kind) const noexcept {
    return static_cast<size_t>(
        std::count_if(findings.begin(), findings.end(), [&](const Finding& f) { return f.kind == kind; }));
}

std::string VerificationReport::summary() const {
    std::string s = (ok() ? "ok: " : std::to_string(findings.size()) + (truncated ? "+" : "") + " findings: ") +
                    std::to_string(accessesChecked) + " accesses, " + std::to_string(pairsChecked) + " pairs";
    for (const Finding& f : findings) s += "\n  " + format(f);
    return s;
}

void Reporter::addAt(FindingKind kind, FindingSite site, std::string reason, const Plan& plan, int64_t resource) {
    Finding f;
    f.kind = kind;
    f.earlier = std::move(site);
    f.reason = std::move(reason);
    if (resource >= 0 && static_cast<size_t>(resource) < plan.resources().size()) {
        f.resources.push_back(static_cast<uint32_t>(resource));
        f.resourceNames.emplace_back(plan.resources()[static_cast<size_t>(resource)].name);
    }
    add(std::move(f));
}

void Reporter::add(Finding f) {
    if (!seen_.insert({f.kind, key(f.earlier), key(f.later), f.resourceNames.empty() ? "" : f.resourceNames[0]}).second)
        return;
    if (report_.findings.size() >= max_) {
        report_.truncated = true;
        return;
    }
    report_.findings.push_back(std::move(f));
}

}  // namespace skygraph::verifier
