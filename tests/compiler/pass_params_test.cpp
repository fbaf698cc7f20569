// PassParams: a pass's params object, owned by its PassDesc, read the way pass
// implementations read it (value with a fallback) and usable wherever a JSON object is.
#include <skygraph/graph.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace skygraph {
namespace {

TEST(PassParams, EmptyObjectByDefault) {
    const PassParams params;
    EXPECT_TRUE(params.empty());
    EXPECT_TRUE(params.json().is_object());
    EXPECT_EQ(params.value("samples", 3), 3);
    const PassDesc desc;
    EXPECT_TRUE(desc.params.json().is_object());
}

TEST(PassParams, ValuesWithFallbacks) {
    const PassParams params(nlohmann::json{{"samples", 64}, {"operator", "aces"}, {"color", {1, 2, 3, 4}}});
    EXPECT_FALSE(params.empty());
    EXPECT_EQ(params.value("samples", 1), 64);
    EXPECT_EQ(params.value("operator", std::string("none")), "aces");
    EXPECT_EQ(params.value("missing", "fallback"), "fallback");
    EXPECT_EQ(params.value("color", std::vector<float>{}), (std::vector<float>{1, 2, 3, 4}));
    EXPECT_THROW((void)params.value("operator", 0), nlohmann::json::type_error);
}

TEST(PassParams, OnlyAnObject) {
    EXPECT_THROW((void)PassParams(nlohmann::json::array()), std::invalid_argument);
    EXPECT_THROW((void)PassParams(nlohmann::json(5)), std::invalid_argument);
    EXPECT_NO_THROW((void)PassParams(nlohmann::json::object()));
}

TEST(PassParams, CopiesOwnTheirObject) {
    PassDesc a;
    a.params = PassParams(nlohmann::json{{"samples", 8}});
    PassDesc b = a;
    b.params["samples"] = 16;
    EXPECT_EQ(a.params.value("samples", 0), 8);
    EXPECT_EQ(b.params.value("samples", 0), 16);
    PassDesc c = std::move(b);
    EXPECT_EQ(c.params.value("samples", 0), 16);
    a = c;
    EXPECT_EQ(a.params.value("samples", 0), 16);
}

TEST(PassParams, ReadsAsItsObject) {
    PassDesc desc;
    desc.params["exposure_ev"] = 2.5;
    const nlohmann::json& object = desc.params;
    EXPECT_EQ(object.at("exposure_ev").get<double>(), 2.5);
    nlohmann::json copy = nlohmann::json::object();
    copy = desc.params;
    EXPECT_EQ(copy, (nlohmann::json{{"exposure_ev", 2.5}}));
    desc.params.edit().erase("exposure_ev");
    EXPECT_TRUE(desc.params.empty());
}

}  // namespace
}  // namespace skygraph
