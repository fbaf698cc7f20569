#include <skygraph/condition.hpp>

#include <algorithm>
#include <cctype>

namespace skygraph {

struct Condition::Node {
    enum class Kind { True, Feature, Not, And, Or } kind = Kind::True;
    std::string feature;
    std::shared_ptr<const Node> lhs, rhs;
};

namespace {

using NodePtr = std::shared_ptr<const Condition::Node>;
using Kind = Condition::Node::Kind;

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
    NodePtr parseOr() {
        NodePtr lhs = parseAnd();
        while (error_.empty() && consume("||")) lhs = binary(Kind::Or, lhs, parseAnd());
        return lhs;
    }
    NodePtr parseAnd() {
        NodePtr lhs = parseUnary();
        while (error_.empty() && consume("&&")) lhs = binary(Kind::And, lhs, parseUnary());
        return lhs;
    }
    NodePtr parseUnary() {
        skipSpace();
        if (!error_.empty()) return nullptr;
        if (consume("!")) {
            auto n = std::make_shared<Condition::Node>();
            n->kind = Kind::Not;
            n->lhs = parseUnary();
            return n;
        }
        if (consume("(")) {
            NodePtr inner = parseOr();
            if (error_.empty() && !consume(")")) fail("expected ')'");
            return inner;
        }
        size_t start = pos_;
        while (pos_ < text_.size() &&
               (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_'))
            ++pos_;
        if (start == pos_ || std::isdigit(static_cast<unsigned char>(text_[start]))) {
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
            n->lhs = std::make_shared<Condition::Node>();
            return n;
        }
        n->kind = Kind::Feature;
        n->feature = name;
        if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
        return n;
    }
    static NodePtr binary(Kind k, NodePtr l, NodePtr r) {
        auto n = std::make_shared<Condition::Node>();
        n->kind = k;
        n->lhs = std::move(l);
        n->rhs = std::move(r);
        return n;
    }
    bool consume(std::string_view token) {
        skipSpace();
        if (text_.compare(pos_, token.size(), token) != 0) return false;
        pos_ += token.size();
        return true;
    }
    void skipSpace() {
        while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    }
    std::string rest() const { return text_.substr(pos_, 8); }
    void fail(const std::string& what) {
        if (error_.empty()) error_ = "column " + std::to_string(pos_ + 1) + ": " + what;
    }

    const std::string& text_;
    size_t pos_ = 0;
    std::string error_;
};

bool eval(const Condition::Node& n, const FeatureValues& values) {
    switch (n.kind) {
        case Kind::True: return true;
        case Kind::Feature: {
            auto it = values.find(n.feature);
            return it != values.end() && it->second;
        }
        case Kind::Not: return !eval(*n.lhs, values);
        case Kind::And: return eval(*n.lhs, values) && eval(*n.rhs, values);
        case Kind::Or: return eval(*n.lhs, values) || eval(*n.rhs, values);
    }
    return false;
}

}  // namespace

Condition::Condition() : root_(std::make_shared<Node>()) {}

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

bool Condition::evaluate(const FeatureValues& values) const { return eval(*root_, values); }

}  // namespace skygraph
