// Errors about graph files. Every message names where it comes from, so that a user editing
// JSON by hand can go straight to the line that is wrong.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace skygraph {

/// One problem found in a graph file or while compiling it.
struct Diagnostic {
    std::string file;      ///< Path of the graph file, or "<memory>".
    std::string jsonPath;  ///< e.g. "passes[2].uses.hdr_color"; empty for whole-file errors.
    std::string pass;      ///< Pass name, when one is involved.
    std::string resource;  ///< Resource name, when one is involved.
    std::string message;   ///< What is wrong and, where possible, what was expected.
    int line = 0;          ///< 1-based, for malformed JSON only; 0 when unknown.
    int column = 0;

    /// "file:line:col: passes[2].uses.x: pass 'p', resource 'x': message", one line: control
    /// characters in any part (a glTF file's name, a key) show escaped as JSON writes them.
    [[nodiscard]] std::string format() const;
};

/// Collects every problem instead of stopping at the first (docs/graph-format.md, "Errors").
class Diagnostics {
public:
    void add(Diagnostic d) { items_.push_back(std::move(d)); }
    [[nodiscard]] bool empty() const noexcept { return items_.empty(); }
    [[nodiscard]] size_t size() const noexcept { return items_.size(); }
    /// Valid until the next add() or until this is destroyed or assigned to.
    [[nodiscard]] const std::vector<Diagnostic>& items() const noexcept { return items_; }
    /// One formatted line per diagnostic.
    [[nodiscard]] std::string format() const;

private:
    std::vector<Diagnostic> items_;
};

/// Thrown by the loader and the compiler when a graph cannot be used. Carries all diagnostics.
class GraphError : public std::runtime_error {
public:
    /// Keeps `d`; what() is its format(), one line per diagnostic.
    explicit GraphError(Diagnostics d);
    /// Valid while this exception object lives.
    [[nodiscard]] const Diagnostics& diagnostics() const noexcept { return diagnostics_; }

private:
    Diagnostics diagnostics_;
};

}  // namespace skygraph
