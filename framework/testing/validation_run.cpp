#include <skygraph/device.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/testing/assertions.hpp>

namespace skygraph::testkit {

::testing::AssertionResult rendersWithoutValidationMessages(Device& device, const CompiledGraph& compiled,
                                                            const RendererOptions& options, uint32_t frames) {
    if (!device.validationEnabled())
        return ::testing::AssertionFailure() << "device '" << device.name()
                                             << "' was created without validation: nothing would be seen";
    if (frames == 0) return ::testing::AssertionFailure() << "no frame to render: frames is 0";
    device.clearMessages();
    try {
        Renderer renderer(device, compiled, options);
        for (uint32_t i = 0; i < frames; ++i) renderer.renderFrame();
        renderer.waitIdle();
    } catch (const std::exception& e) {
        return ::testing::AssertionFailure() << "graph '" << compiled.graph().name << "' did not render: " << e.what();
    }
    if (device.messageCount() == 0) return ::testing::AssertionSuccess();
    ::testing::AssertionResult failure = ::testing::AssertionFailure();
    failure << "graph '" << compiled.graph().name << "': " << device.messageCount() << " validation message(s) in "
            << frames << " frame(s):";
    for (const ValidationMessage& m : device.messages()) failure << "\n  " << m.idName << ": " << m.message;
    return failure;
}

}  // namespace skygraph::testkit
