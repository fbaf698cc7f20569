// Engines write `using namespace skygraph;` beside GoogleTest (namespace `testing`) and
// Vulkan-Hpp (namespace `vk`). No namespace of the public headers may take either name, or
// every unqualified `testing::Test` and `vk::Device` below becomes ambiguous: this file then
// does not compile.
#include <skygraph/compiler.hpp>
#include <skygraph/executor.hpp>
#include <skygraph/feature_combinations.hpp>
#include <skygraph/golden.hpp>
#include <skygraph/ktx2.hpp>
#include <skygraph/pipeline_builder.hpp>
#include <skygraph/plan_format.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/shader_compiler.hpp>
#include <skygraph/shading_math.hpp>
#include <skygraph/transfer_plans.hpp>
#include <skygraph/triangle_mesh.hpp>
#include <skygraph/verifier.hpp>
#include <skygraph/testing/assertions.hpp>
#include <skygraph/testing/barrier_matchers.hpp>
#include <skygraph/vk_handles.hpp>

#include <gtest/gtest.h>

namespace vk {  // as Vulkan-Hpp declares it
struct Device {
    int id = 7;
};
}  // namespace vk

using namespace skygraph;

namespace {

class UnderUsingNamespaceSkygraph : public testing::Test {};

TEST_F(UnderUsingNamespaceSkygraph, GoogleTestAndVulkanHppNamesStayUnambiguous) {
    const vk::Device device;
    EXPECT_EQ(device.id, 7);
    const owned::Pipeline none;
    EXPECT_FALSE(none);
    using Verdict = decltype(testkit::verifies(Plan{}, GraphDesc{}));
    EXPECT_TRUE((testing::StaticAssertTypeEq<Verdict, testing::AssertionResult>()));
}

}  // namespace
