// The header defines isShaderStage(), isAttachmentStage(), readsContents() and
// writesContents() inline (constexpr) because the compiler asks them several times per usage
// in every sweep; the name tables below are looked up only when loading and printing.
#include <skygraph/usage.hpp>

#include <array>
#include <utility>

namespace skygraph {
namespace {

template <typename E, size_t N>
std::optional<E> lookup(const std::array<std::pair<std::string_view, E>, N>& table,
                        std::string_view s) noexcept {
    for (const auto& [name, value] : table)
        if (name == s) return value;
    return std::nullopt;
}

template <typename E, size_t N>
std::string_view nameOf(const std::array<std::pair<std::string_view, E>, N>& table,
                        E e) noexcept {
    for (const auto& [name, value] : table)
        if (value == e) return name;
    return "?";
}

constexpr std::array<std::pair<std::string_view, Access>, 3> kAccesses{{
    {"Read", Access::Read}, {"Write", Access::Write}, {"ReadWrite", Access::ReadWrite}}};

constexpr std::array<std::pair<std::string_view, Stage>, 8> kStages{{
    {"ColorAttachment", Stage::ColorAttachment}, {"DepthAttachment", Stage::DepthAttachment},
    {"Vertex", Stage::Vertex}, {"Fragment", Stage::Fragment}, {"Compute", Stage::Compute},
    {"Transfer", Stage::Transfer}, {"VertexInput", Stage::VertexInput},
    {"Indirect", Stage::Indirect}}};

constexpr std::array<std::pair<std::string_view, BindAs>, 5> kBindAs{{
    {"default", BindAs::Default}, {"sampled", BindAs::Sampled}, {"storage", BindAs::Storage},
    {"uniform", BindAs::Uniform}, {"index", BindAs::Index}}};

}  // namespace

std::string_view toString(Access a) noexcept { return nameOf(kAccesses, a); }
std::string_view toString(Stage s) noexcept { return nameOf(kStages, s); }
std::string_view toString(BindAs a) noexcept { return nameOf(kBindAs, a); }
std::optional<Access> parseAccess(std::string_view s) noexcept { return lookup(kAccesses, s); }
std::optional<Stage> parseStage(std::string_view s) noexcept { return lookup(kStages, s); }
std::optional<BindAs> parseBindAs(std::string_view s) noexcept {
    if (s == "default") return std::nullopt;  // not spellable in files
    return lookup(kBindAs, s);
}

std::string toString(const UsageMode& u) {
    std::string out = std::string(toString(u.access)) + "@" + std::string(toString(u.stage));
    if (u.as != BindAs::Default) out += " as " + std::string(toString(u.as));
    return out;
}

}  // namespace skygraph
