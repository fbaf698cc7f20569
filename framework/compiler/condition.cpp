#include <skygraph/condition.hpp>

#include <algorithm>
#include <cctype>
#include <unordered_set>

namespace skygraph {
namespace {

bool isDigit(char c) { return c >= '0' && c <= '9'; }
bool isNameCharacter(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || isDigit(c); }

}  // namespace

bool Condition::isFeatureName(std::string_view name) noexcept {
    return !name.empty() && !isDigit(name[0]) && std::all_of(name.begin(), name.end(), isNameCharacter) &&
           name != "true" && name != "false";
}

// And/Or are n-ary: a chain such as `a && b && c && ...` is one node with many children, so
// the tree's depth grows only with parentheses and `!`, which the parser limits. That keeps
// parsing, evaluation and destruction (all recursive) within a small, fixed stack depth.
struct Condition::Node {
    enum class Kind { True, Feature, Not, And, Or } kind = Kind::True;
    std::string feature;
    std::vector<std::shared_ptr<const Node>> children;  ///< One for Not, two or more for And/Or.
};

namespace {

using NodePtr = std::shared_ptr<const Condition::Node>;
using Kind = Condition::Node::Kind;

/// Deepest nesting of `(` and `!` accepted. Real conditions nest a few levels; the limit only
/// keeps generated or hostile input from exhausting the stack.
constexpr int kMaxNesting = 256;

// Recursive descent over: or := and ('||' and)* ; and := unary ('&&' unary)* ;
// unary := '!' unary | '(' or ')' | name | 'true' | 'false'.
class Parser {
public:
    explicit Parser(const std::string& text) : text_(text) {}

    NodePtr parseAll(std::string& error) {
        NodePtr root = parseOr();
        skipSpace();
        if (error_.empty() && pos_ != text_.size()) fail("unexpected '" + rest() + "'");
        error = error_;
        return error_.empty() ? root : nullptr;
    }
    std::vector<std::string> names;

private:
    NodePtr parseOr() { return parseChain(Kind::Or, "||"); }
    NodePtr parseAnd() { return parseChain(Kind::And, "&&"); }

    NodePtr parseChain(Kind kind, std::string_view op) {
        NodePtr first = kind == Kind::Or ? parseAnd() : parseUnary();
        if (!error_.empty() || !peek(op)) return first;
        auto n = std::make_shared<Condition::Node>();
        n->kind = kind;
        n->children.push_back(std::move(first));
        while (error_.empty() && consume(op))
            n->children.push_back(kind == Kind::Or ? parseAnd() : parseUnary());
        return n;
    }

    NodePtr parseUnary() {
        skipSpace();
        if (!error_.empty()) return nullptr;
        if (peek("!") || peek("(")) {
            if (depth_ >= kMaxNesting) {
                fail("nested deeper than " + std::to_string(kMaxNesting) + " levels");
                return nullptr;
            }
            ++depth_;
            NodePtr out;
            if (consume("!")) {
                auto n = std::make_shared<Condition::Node>();
                n->kind = Kind::Not;
                n->children.push_back(parseUnary());
                out = std::move(n);
            } else {
                consume("(");
                out = parseOr();
                if (error_.empty() && !consume(")")) fail("expected ')'");
            }
            --depth_;
            return out;
        }
        size_t start = pos_;
        while (pos_ < text_.size() && isNameCharacter(text_[pos_])) ++pos_;
        if (start == pos_ || isDigit(text_[start])) {
            pos_ = start;
            fail(pos_ == text_.size() ? "expected a feature name at the end"
                                      : "expected a feature name, found '" + rest() + "'");
            return nullptr;
        }
        std::string name = text_.substr(start, pos_ - start);
        auto n = std::make_shared<Condition::Node>();
        if (name == "true") return n;
        if (name == "false") {
            n->kind = Kind::Not;
            n->children.push_back(std::make_shared<Condition::Node>());
            return n;
        }
        n->kind = Kind::Feature;
        n->feature = name;
        if (seen_.insert(name).second) names.push_back(name);
        return n;
    }
    bool peek(std::string_view token) {
        skipSpace();
        return text_.compare(pos_, token.size(), token) == 0;
    }
    bool consume(std::string_view token) {
        if (!peek(token)) return false;
        pos_ += token.size();
        return true;
    }
    void skipSpace() {
        while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    }
    // Errors quote and count characters, not bytes: a cut UTF-8 sequence is not text.
    static bool continuationByte(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }
    std::string rest() const {
        size_t end = pos_;
        for (size_t chars = 0; end < text_.size() && chars < 8; ++chars)
            do ++end;
            while (end < text_.size() && continuationByte(text_[end]));
        return text_.substr(pos_, end - pos_);
    }
    void fail(const std::string& what) {
        const auto column = 1 + std::count_if(text_.begin(), text_.begin() + static_cast<std::ptrdiff_t>(pos_),
                                              [](char c) { return !continuationByte(c); });
        if (error_.empty()) error_ = "column " + std::to_string(column) + ": " + what;
    }

    const std::string& text_;
    size_t pos_ = 0;
    int depth_ = 0;
    std::unordered_set<std::string> seen_;
    std::string error_;
};

bool eval(const Condition::Node& n, const FeatureValues& values) {
    switch (n.kind) {
        case Kind::True: return true;
        case Kind::Feature: {
            auto it = values.find(n.feature);
            return it != values.end() && it->second;
        }
        case Kind::Not: return !eval(*n.children.front(), values);
        case Kind::And:
            return std::all_of(n.children.begin(), n.children.end(),
                               [&](const NodePtr& c) { return eval(*c, values); });
        case Kind::Or:
            return std::any_of(n.children.begin(), n.children.end(),
                               [&](const NodePtr& c) { return eval(*c, values); });
    }
    return false;
}

}  // namespace

// The always-true condition needs no tree: evaluate() answers it from its empty text.
Condition::Condition() = default;

std::optional<Condition> Condition::parse(const std::string& text, std::string& error) {
    Parser parser(text);
    NodePtr root = parser.parseAll(error);
    if (!root) return std::nullopt;
    Condition c;
    c.root_ = std::move(root);
    c.text_ = text;
    c.names_ = std::move(parser.names);
    return c;
}

bool Condition::evaluate(const FeatureValues& values) const noexcept {
    // The always-true condition of a pass with no `if` (the only one without text) needs no
    // walk of its tree: the compiler evaluates every pass's condition on every compile.
    return text_.empty() || eval(*root_, values);
}

}  // namespace skygraph
