#include "check_report.hpp"
#include "printable_name.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>

namespace skygraph::app {
namespace {

std::string seconds(double s) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f", s);
    return text;
}

std::string goldenCell(const CheckCase& c) {
    if (c.goldenWritten) return "written";
    if (!c.golden) return "-";
    return std::string(toString(c.golden->status));
}

std::string pad(const std::string& s, size_t width) { return s.size() >= width ? s : s + std::string(width - s.size(), ' '); }

/// The length of the valid UTF-8 sequence at s[i], or 0.
size_t utf8Length(const std::string& s, size_t i) {
    const auto byte = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char b = byte(i);
    const size_t n = b < 0x80 ? 1 : (b >> 5) == 0x6 ? 2 : (b >> 4) == 0xE ? 3 : (b >> 3) == 0x1E ? 4 : 0;
    if (n == 0 || i + n > s.size()) return 0;
    for (size_t k = 1; k < n; ++k)
        if ((byte(i + k) & 0xC0) != 0x80) return 0;
    return n;
}

/// Text for XML 1.0: markup escaped, line ends kept as character references in attributes,
/// control characters and bytes that are not UTF-8 (a message can quote anything) as '?'.
std::string xmlEscape(const std::string& s, bool attribute = false) {
    std::string out;
    for (size_t i = 0; i < s.size();) {
        const char ch = s[i];
        const size_t n = utf8Length(s, i);
        if (n == 0) {
            out += '?';
            ++i;
            continue;
        }
        if (n > 1) {
            out.append(s, i, n);
            i += n;
            continue;
        }
        switch (ch) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\n': out += attribute ? "&#10;" : "\n"; break;
            case '\t': out += attribute ? "&#9;" : "\t"; break;
            default: out += static_cast<unsigned char>(ch) < 0x20 ? '?' : ch;
        }
        ++i;
    }
    return out;
}

/// At most `most` bytes of `s`, not cutting a UTF-8 sequence.
std::string prefix(const std::string& s, size_t most) {
    if (s.size() <= most) return s;
    size_t end = most;
    while (end > 0 && (static_cast<unsigned char>(s[end]) & 0xC0) == 0x80) --end;
    return s.substr(0, end);
}

/// `text` line by line through printableName(): a golden file may hold anything, and its
/// diff goes to a terminal, where an escape sequence in it would be obeyed rather than shown.
std::string printableLines(const std::string& text) {
    std::string out;
    for (size_t start = 0; start < text.size();) {
        const size_t end = std::min(text.find('\n', start), text.size());
        out += printableName(std::string_view(text).substr(start, end - start));
        if (end < text.size()) out += '\n';
        start = end + 1;
    }
    return out;
}

}  // namespace

std::string checkTable(const std::vector<CheckCase>& cases, bool warningsAsErrors) {
    // Graphs by file, as the command line named them: two files may hold graphs of one name.
    const std::vector<std::string> header{"file", "features", "passes", "culled", "barriers", "validation",
                                          "perf warnings", "golden", "verifier", "time s", "result"};
    std::vector<std::vector<std::string>> rows;
    size_t failed = 0, warnings = 0;
    for (const CheckCase& c : cases) {
        const bool bad = c.failed(warningsAsErrors);
        failed += bad;
        warnings += c.performanceWarnings;
        const bool compiled = c.compiled();
        rows.push_back({printableName(c.file.string()), c.combination, compiled ? std::to_string(c.passes) : "-",
                        compiled ? std::to_string(c.culled) : "-", compiled ? std::to_string(c.barriers) : "-",
                        c.runAttempted ? std::to_string(c.validationMessages) : "-",
                        c.runAttempted ? std::to_string(c.performanceWarnings) : "-", goldenCell(c),
                        compiled ? (c.verifierFindings ? std::to_string(c.verifierFindings) + " findings" : "ok") : "-",
                        seconds(c.seconds), bad ? "FAIL" : "pass"});
    }
    std::vector<size_t> width(header.size());
    for (size_t i = 0; i < header.size(); ++i) width[i] = header[i].size();
    for (const auto& row : rows)
        for (size_t i = 0; i < row.size(); ++i) width[i] = std::max(width[i], row[i].size());
    std::ostringstream out;
    const auto line = [&](const std::vector<std::string>& cells) {
        std::string text;
        for (size_t i = 0; i < cells.size(); ++i) text += (i ? "  " : "") + pad(cells[i], i + 1 < cells.size() ? width[i] : 0);
        out << text << "\n";
    };
    line(header);
    for (const auto& row : rows) line(row);
    for (const CheckCase& c : cases) {
        const std::vector<std::string> reasons = c.failures(warningsAsErrors);
        if (reasons.empty() && c.messages.empty()) continue;
        out << "\n" << (reasons.empty() ? "WARN " : "FAIL ") << printableName(c.file.string()) << " [" << c.combination << "]\n";
        // A golden of another version is quoted by its first line, which may hold anything too.
        for (const std::string& r : reasons) out << "  " << printableLines(r) << "\n";
        if (!c.verifierReport.empty()) out << c.verifierReport;
        if (c.golden && !c.golden->diff.empty()) out << printableLines(c.golden->diff);
        for (const std::string& m : c.messages) out << "  " << m << "\n";
    }
    out << "\n" << cases.size() << " case(s): " << cases.size() - failed << " passed, " << failed << " failed";
    if (warnings) out << "; " << warnings << " performance warning(s)" << (warningsAsErrors ? " (errors)" : "");
    if (std::any_of(cases.begin(), cases.end(), [](const CheckCase& c) { return c.goldenWritten; }))
        out << "; goldens written: review them (git diff) before committing them";
    out << "\n";
    return out.str();
}

std::string checkJUnit(const std::vector<CheckCase>& cases, bool warningsAsErrors) {
    std::map<std::string, std::vector<const CheckCase*>> byFile;
    std::vector<std::string> order;
    for (const CheckCase& c : cases) {
        const std::string file = c.file.string();
        if (!byFile.count(file)) order.push_back(file);
        byFile[file].push_back(&c);
    }
    size_t failures = 0;
    double total = 0;
    for (const CheckCase& c : cases) {
        failures += c.failed(warningsAsErrors);
        total += c.seconds;
    }
    std::ostringstream out;
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out << "<testsuites name=\"skygraph check\" tests=\"" << cases.size() << "\" failures=\"" << failures
        << "\" time=\"" << seconds(total) << "\">\n";
    for (const std::string& file : order) {
        const auto& list = byFile[file];
        size_t suiteFailures = 0;
        double suiteTime = 0;
        for (const CheckCase* c : list) {
            suiteFailures += c->failed(warningsAsErrors);
            suiteTime += c->seconds;
        }
        out << "  <testsuite name=\"" << xmlEscape(file, true) << "\" tests=\"" << list.size() << "\" failures=\""
            << suiteFailures << "\" time=\"" << seconds(suiteTime) << "\">\n";
        for (const CheckCase* c : list) {
            out << "    <testcase classname=\"" << xmlEscape(file, true) << "\" name=\"" << xmlEscape(c->combination, true)
                << "\" time=\"" << seconds(c->seconds) << "\">\n";
            const std::vector<std::string> reasons = c->failures(warningsAsErrors);
            if (!reasons.empty()) {
                std::string body;
                for (const std::string& r : reasons) body += r + "\n";
                body += c->verifierReport;
                if (c->golden) body += c->golden->diff;
                out << "      <failure message=\"" << xmlEscape(prefix(reasons.front(), 200), true) << "\">"
                    << xmlEscape(body) << "</failure>\n";
            }
            std::string system = "passes " + std::to_string(c->passes) + ", culled " + std::to_string(c->culled) +
                                 ", barriers " + std::to_string(c->barriers) + ", validation messages " +
                                 std::to_string(c->validationMessages) + ", performance warnings " +
                                 std::to_string(c->performanceWarnings) + "\n";
            for (const std::string& m : c->messages) system += m + "\n";
            out << "      <system-out>" << xmlEscape(system) << "</system-out>\n";
            out << "    </testcase>\n";
        }
        out << "  </testsuite>\n";
    }
    out << "</testsuites>\n";
    return out.str();
}

}  // namespace skygraph::app
