// AfterGeneric, the base of test passes that add to what Generic records, and a pass type
// whose recording code throws on request: what the tests of a frame that fails
// while it is recorded render with. It records as Generic does, then throws when the
// renderer's FrameData asks it to, so that the frame's command buffer holds work (inside a
// render pass, for a graphics pass) that must never run.
#pragma once

#include <skygraph/pass.hpp>

#include <atomic>
#include <memory>
#include <stdexcept>
#include <utility>

namespace skygraph::test {

/// Set in the renderer's FrameData: every ThrowingPass throws PassThrew while the frames
/// recorded with `now` set are recorded.
struct ThrowWhileRecording {
    bool now = false;
};

struct PassThrew : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Generic's recording code, and then `afterGeneric`: the base of the test passes that do
/// something of their own once Generic has recorded.
class AfterGeneric : public PassImplementation {
public:
    explicit AfterGeneric(std::unique_ptr<PassImplementation> generic) : generic_(std::move(generic)) {}
    void createPipelines(const PipelineContext& context) override { generic_->createPipelines(context); }
    void recordBeforeRenderPass(const RecordContext& context) override { generic_->recordBeforeRenderPass(context); }
    void record(const RecordContext& context) final {
        generic_->record(context);
        afterGeneric(context);
    }
    [[nodiscard]] bool keepsSlotHandles() const noexcept override { return generic_->keepsSlotHandles(); }

protected:
    virtual void afterGeneric(const RecordContext& context) = 0;

private:
    std::unique_ptr<PassImplementation> generic_;
};

/// Generic's recording code, throwing after it has recorded when ThrowWhileRecording says so.
class ThrowingPass : public AfterGeneric {
public:
    explicit ThrowingPass(std::unique_ptr<PassImplementation> generic) : AfterGeneric(std::move(generic)) { ++made(); }
    /// ThrowingPass implementations made so far, in the whole test binary.
    static std::atomic<int>& made() {
        static std::atomic<int> count{0};
        return count;
    }

protected:
    void afterGeneric(const RecordContext& context) override {
        if (const auto* request = context.frame->get<ThrowWhileRecording>(); request && request->now)
            throw PassThrew("pass '" + std::string(context.pass->name) + "' throws as asked");
    }
};

/// Generic alone (every other type runs as Generic) plus "ThrowingPass", which takes any
/// usages as Generic does.
inline PassLibrary throwingPassLibrary() {
    PassLibrary library = PassLibrary::genericOnly();
    PassTypeInfo info;
    info.name = "ThrowingPass";
    info.acceptsAnyUsage = true;
    library.add(std::move(info), [](const PassDesc& desc) {
        return std::make_unique<ThrowingPass>((*PassLibrary::genericOnly().factory("Generic"))(desc));
    });
    return library;
}

}  // namespace skygraph::test
