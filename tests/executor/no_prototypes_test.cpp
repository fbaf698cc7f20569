// Every public header includes under VK_NO_PROTOTYPES, as an application that loads Vulkan
// itself (volk) compiles them; this file is compiled with that definition, so it fails to
// build when a header calls a Vulkan function inline.
#include <skygraph/compiled_graph.hpp>
#include <skygraph/compiler.hpp>
#include <skygraph/condition.hpp>
#include <skygraph/device.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/executor.hpp>
#include <skygraph/feature_combinations.hpp>
#include <skygraph/format.hpp>
#include <skygraph/golden.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/hdr_image.hpp>
#include <skygraph/hot_reload.hpp>
#include <skygraph/image_data.hpp>
#include <skygraph/ktx2.hpp>
#include <skygraph/memory.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/pass_registry.hpp>
#include <skygraph/pipeline_builder.hpp>
#include <skygraph/plan.hpp>
#include <skygraph/plan_format.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/shader_compiler.hpp>
#include <skygraph/shading_math.hpp>
#include <skygraph/shared_image.hpp>
#include <skygraph/staging_buffer.hpp>
#include <skygraph/swapchain.hpp>
#include <skygraph/transfer_plans.hpp>
#include <skygraph/triangle_mesh.hpp>
#include <skygraph/usage.hpp>
#include <skygraph/verifier.hpp>
#include <skygraph/vk_handles.hpp>

#include <gtest/gtest.h>

#include <utility>

#ifndef VK_NO_PROTOTYPES
#error "this test is compiled with VK_NO_PROTOTYPES"
#endif

namespace skygraph {
namespace {

TEST(PublicHeaders, IncludeWithoutVulkanPrototypes) {
    owned::Image image;
    owned::Image moved = std::move(image);
    moved.reset();  // holds nothing: destroys nothing
    EXPECT_FALSE(moved);
    EXPECT_EQ(moved.get(), VkImage(VK_NULL_HANDLE));
}

}  // namespace
}  // namespace skygraph
