// The compiler's public headers name nlohmann::json without defining it (json_fwd.hpp): an
// embedder that includes them does not compile all of nlohmann/json. This file includes
// nothing that defines it, and asks.
#include <skygraph/compiler.hpp>

#include <gtest/gtest.h>

#include <type_traits>

namespace skygraph {
namespace {

template <typename T, typename = void>
struct IsComplete : std::false_type {};
template <typename T>
struct IsComplete<T, std::void_t<decltype(sizeof(T))>> : std::true_type {};

TEST(PublicHeaders, CompilerHeadersDoNotDefineNlohmannJson) {
    EXPECT_FALSE(IsComplete<nlohmann::json>::value)
        << "a header under <skygraph/compiler.hpp> includes <nlohmann/json.hpp>";
    // What they do give: a pass's params, without the definition.
    EXPECT_TRUE(PassDesc().params.empty());
}

}  // namespace
}  // namespace skygraph
