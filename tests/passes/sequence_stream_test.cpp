// An environment sequence's streaming: SequenceStream decodes ahead on its own thread, holds
// no more than its lookahead, and stages its frames in host-visible memory when given a device; SequencePlayer says which frame is due and
// counts late and dropped ones. Frames are time-lapses of the procedural sky written here.
#include "app/procedural_environment.hpp"
#include "app/sequence_player.hpp"
#include "executor_test_util.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

namespace skygraph::test {
namespace {

namespace fs = std::filesystem;

/// `frames` frames of the procedural sky at 32 x 16 in a folder of their own.
EnvironmentSequence writeSequence(const std::string& name, uint32_t frames, double fps = 10.0) {
    const fs::path dir = fs::temp_directory_path() / ("skygraph-sequence-" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    EnvironmentSequence s;
    s.pattern = (dir / "sky_%03d.exr").string();
    s.fps = fps;
    s.count = frames;
    app::writeProceduralSkySequence(s.pattern, frames, 32);
    return s;
}

/// Asks for frame `index` until it comes (the stream decodes on its own thread), for 20 s at most.
template <class Ask>
auto waitFor(Ask ask) -> decltype(ask()) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    for (;;) {
        if (auto got = ask()) return got;
        if (std::chrono::steady_clock::now() > until) return {};
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

/// The bytes of file `f`.
std::string bytesOf(const fs::path& f) {
    std::ifstream in(f, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A sequence cut short is no sequence: a frame that cannot be written (here a link into a
// folder that does not exist) leaves the frames before it as they were, not replaced.
TEST(ProceduralSkySequence, AFailureLeavesEveryFrameAsItWas) {
    const EnvironmentSequence s = writeSequence("all-or-none", 3);
    const std::string first = bytesOf(s.frame(0)), second = bytesOf(s.frame(1));
    ASSERT_FALSE(first.empty());
    fs::remove(s.frame(2));
    fs::create_symlink(s.frame(2).parent_path() / "missing" / "sky.exr", s.frame(2));
    EXPECT_THROW(app::writeProceduralSkySequence(s.pattern, 3, 64), ImageError);
    EXPECT_TRUE(bytesOf(s.frame(0)) == first) << "frame 0 was replaced";
    EXPECT_TRUE(bytesOf(s.frame(1)) == second) << "frame 1 was replaced";
    EXPECT_TRUE(fs::is_symlink(s.frame(2)));
    for (const auto& entry : fs::directory_iterator(s.frame(0).parent_path()))
        EXPECT_EQ(entry.path().filename().string().rfind("sky_", 0), 0u) << "left behind: " << entry.path();

    // A frame that is a link to another is refused as an ImageError too, before anything is drawn.
    fs::remove(s.frame(2));
    fs::create_symlink(s.frame(0), s.frame(2));
    EXPECT_THROW(app::writeProceduralSkySequence(s.pattern, 3, 64), ImageError);
    EXPECT_TRUE(bytesOf(s.frame(0)) == first) << "frame 0 was replaced";
}

TEST(SequenceStream, DecodesEveryFrameInOrderAndHoldsNoMoreThanItsLookahead) {
    const EnvironmentSequence s = writeSequence("in-order", 5);
    app::SequenceStream stream(s, 32, 16, 0, 2);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // time to decode all, were it unbounded
    for (uint32_t i = 0; i < 7; ++i) {  // past the end: the stream loops
        const auto frame = waitFor([&] { return stream.takeNewest(i % 5, 1); });
        ASSERT_TRUE(frame) << i;
        EXPECT_EQ(frame->index, i % 5);
        EXPECT_EQ(frame->error, "");
        EXPECT_EQ(frame->file, s.frame(i % 5).string());
        EXPECT_EQ(frame->pixels.rgba, loadHdrImage(s.frame(i % 5)).rgba) << "frame " << i % 5 << " as its file holds it";
    }
    EXPECT_LE(stream.mostFramesHeld(), 2u);
    EXPECT_GE(stream.mostFramesHeld(), 1u);
}

TEST(SequenceStream, StagesEachFrameOnItsThreadAndReusesTheBuffersNothingHolds) {
    const EnvironmentSequence s = writeSequence("staged", 6);
    app::SequenceStream stream(s, 32, 16, 0, 2, &sharedDevice());
    for (uint32_t i = 0; i < 12; ++i) {
        const auto frame = waitFor([&] { return stream.takeNewest(i % 6, 1); });
        ASSERT_TRUE(frame) << i;
        ASSERT_TRUE(frame->staged) << frame->error;
        EXPECT_TRUE(frame->pixels.rgba.empty()) << "the host copy is dropped once staged";
        const HdrImage file = loadHdrImage(s.frame(i % 6));
        ASSERT_EQ(frame->staged->size(), file.rgba.size() * sizeof(float));
        EXPECT_EQ(std::memcmp(frame->staged->bytes().data(), file.rgba.data(), file.rgba.size() * sizeof(float)), 0)
            << "frame " << i % 6 << " as its file holds it";
    }
    // Two waiting, one decoding, one taken: a buffer is reused once the frame holding it goes.
    EXPECT_LE(stream.stagingBuffers(), 4u);
    EXPECT_GE(stream.stagingBuffers(), 2u);
}

TEST(SequenceStream, SkipsAheadToTheFramePlaybackAsksFor) {
    const EnvironmentSequence s = writeSequence("skip", 40);
    app::SequenceStream stream(s, 32, 16, 0, 2);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // frames 0 and 1 wait, taken by nobody
    const auto frame = waitFor([&] { return stream.takeNewest(30, 1); });
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->index, 30u);
    EXPECT_LT(stream.decodeTimesMs().size(), 20u) << "it decoded its way through the frames before 30";
    const auto next = waitFor([&] { return stream.takeNewest(31, 1); });
    ASSERT_TRUE(next);
    EXPECT_EQ(next->index, 31u);
}

TEST(SequenceStream, AFrameOfAnotherSizeIsResampledAndAnUnreadableOneNamesItsFile) {
    const EnvironmentSequence s = writeSequence("odd-frames", 3);
    saveHdrImage(s.frame(1), app::proceduralSkyEquirect({0.0, 1.0, 0.0}, 64));
    std::ofstream(s.frame(2), std::ios::binary) << "not an EXR";
    app::SequenceStream stream(s, 32, 16, 1, 2);
    const auto resized = waitFor([&] { return stream.takeNewest(1, 1); });
    ASSERT_TRUE(resized);
    EXPECT_EQ(resized->pixels.width, 32u);
    EXPECT_EQ(resized->pixels.height, 16u);
    const auto broken = waitFor([&] { return stream.takeNewest(2, 1); });
    ASSERT_TRUE(broken);
    EXPECT_TRUE(broken->pixels.rgba.empty());
    EXPECT_NE(broken->error.find(s.frame(2).string()), std::string::npos) << broken->error;
}

TEST(SequencePlayer, HoldsFramesUntilDueAndCountsLateAndDroppedOnes) {
    const EnvironmentSequence s = writeSequence("player", 6, 10.0);
    app::SequencePlayer player(s, 32, 16);
    EXPECT_EQ(player.stats().current, 0u) << "frame 0 was baked before playback";
    EXPECT_FALSE(player.frameToBake(0.05)) << "frame 0 is on screen until 0.1 s";

    auto frame = waitFor([&] { return player.frameToBake(0.1); });
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->index, 1u);
    EXPECT_FALSE(player.frameToBake(0.12)) << "frame 1 is started: nothing more until frame 2 is due";
    player.swappedIn(0.15);
    EXPECT_EQ(player.stats().shown, 2u);
    EXPECT_EQ(player.stats().late, 0u);
    EXPECT_EQ(player.stats().current, 1u);

    // Frames 2 and 3 wait decoded (waited for, not slept for: a loaded machine decodes slowly).
    ASSERT_TRUE(waitFor([&] { return player.stream().decodeTimesMs().size() >= 3; }));
    frame = waitFor([&] { return player.frameToBake(0.45); });   // tick 4: 4 is not decoded
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->index, 3u) << "the newest decoded frame whose time has come";
    EXPECT_EQ(player.stats().dropped, 1u) << "frame 2, passed over";
    player.swappedIn(0.51);  // after frame 3's time
    EXPECT_EQ(player.stats().late, 1u);
    EXPECT_EQ(player.stats().current, 3u);

    ASSERT_TRUE(waitFor([&] { return player.stream().decodeTimesMs().size() >= 5; }));  // 4 and 5 wait
    frame = waitFor([&] { return player.frameToBake(0.62); });   // tick 6, the loop's frame 0
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->index, 5u) << "frame 0's time has come too, but it is not decoded";
    EXPECT_EQ(player.stats().dropped, 2u) << "frame 4";
    EXPECT_EQ(player.tick(0.62), 6);
    EXPECT_FALSE(player.frameToBake(0.62)) << "frame 5 is being baked: nothing else until it is swapped in, "
                                              "though frame 0's time has come and it may be decoded by now";
}

// A player that takes over from another (a rebuild) goes on where that one stood: the frame
// being baked counts as on screen, the next one is due at its own time, and the stats carry on.
TEST(SequencePlayer, GoesOnFromWherePlaybackStood) {
    const EnvironmentSequence s = writeSequence("resume", 6, 10.0);
    app::SequencePlayer before(s, 32, 16);
    EXPECT_EQ(before.position().tick, 0);
    auto frame = waitFor([&] { return before.frameToBake(0.1); });
    ASSERT_TRUE(frame);
    ASSERT_EQ(frame->index, 1u);
    before.swappedIn(0.1);
    EXPECT_EQ(before.position().tick, 1);
    frame = waitFor([&] { return before.frameToBake(0.25); });
    ASSERT_TRUE(frame);
    ASSERT_EQ(frame->index, 2u);  // being baked
    const app::SequencePosition at = before.position();
    EXPECT_EQ(at.tick, 2);
    EXPECT_EQ(at.stats.shown, 3u) << "the frame being baked is baked by whoever goes on";
    EXPECT_EQ(at.stats.current, 2u);
    EXPECT_EQ(before.stats().shown, 2u) << "position() changes nothing";

    app::SequencePlayer after(s, 32, 16, nullptr, at);
    EXPECT_EQ(after.stats().current, 2u);
    EXPECT_EQ(after.stats().shown, 3u);
    EXPECT_FALSE(after.frameToBake(0.29)) << "frame 2 is on screen until 0.3 s";
    frame = waitFor([&] { return after.frameToBake(0.3); });
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->index, 3u) << "the stream decodes from the frame after the one on screen";
    after.swappedIn(0.3);
    EXPECT_EQ(after.stats().shown, 4u);
    EXPECT_EQ(after.stats().dropped, 0u);
    EXPECT_EQ(after.stats().current, 3u);
}

// A frame that failed before the rebuild is counted once: the player that goes on starts after
// it, not at the frame on screen.
TEST(SequencePlayer, GoesOnPastAFrameThatFailed) {
    const EnvironmentSequence s = writeSequence("resume-failed", 6, 10.0);
    std::ofstream(s.frame(2), std::ios::binary | std::ios::trunc) << "not an EXR";
    app::SequencePlayer before(s, 32, 16);
    auto frame = waitFor([&] { return before.frameToBake(0.1); });
    ASSERT_TRUE(frame);
    before.swappedIn(0.1);
    frame = waitFor([&] { return before.frameToBake(0.2); });
    ASSERT_TRUE(frame);
    ASSERT_FALSE(frame->error.empty()) << "frame 2 is unreadable";
    const app::SequencePosition at = before.position();
    EXPECT_EQ(at.tick, 1);
    EXPECT_EQ(at.lastStarted, 2);
    EXPECT_EQ(at.stats.failed, 1u);

    app::SequencePlayer after(s, 32, 16, nullptr, at);
    EXPECT_EQ(after.stats().current, 1u);
    EXPECT_FALSE(after.frameToBake(0.25)) << "frame 2 was handed out already";
    frame = waitFor([&] { return after.frameToBake(0.3); });
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->index, 3u);
    EXPECT_TRUE(frame->error.empty()) << frame->error;
    EXPECT_EQ(after.stats().failed, 1u) << "frame 2 counted again";
    EXPECT_EQ(after.stats().dropped, 1u);
}

// Playback that moves on faster than frames decode (here five frames' time between two asks)
// still shows frames: the newest decoded one whose time has come, not only the frame due,
// which is never decoded by the time it is asked for.
TEST(SequencePlayer, ShowsTheNewestDecodedFrameWhenDecodingFallsBehind) {
    const EnvironmentSequence s = writeSequence("player-behind", 40, 10.0);
    app::SequencePlayer player(s, 32, 16);
    double seconds = 0.0;
    int64_t lastTaken = 0;
    for (int i = 0; i < 60; ++i) {
        seconds += 0.5;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));  // the stream decodes meanwhile
        const auto frame = player.frameToBake(seconds);
        if (!frame) continue;
        ASSERT_EQ(frame->error, "");
        const int64_t due = player.tick(seconds);
        const int64_t taken = due - (uint32_t(due % 40) + 40 - frame->index) % 40;
        EXPECT_GT(taken, lastTaken) << "a frame whose time came after the last one taken";
        lastTaken = taken;
        player.swappedIn(seconds);
    }
    const app::SequenceStats& stats = player.stats();
    EXPECT_GE(stats.shown, 30u) << "playback froze: only the frame due was ever asked for";
    EXPECT_GT(stats.dropped, 0u);
    EXPECT_LE(stats.shown + stats.dropped, uint32_t(player.tick(seconds)) + 1) << "no tick counted twice";
}

// A frame takes many asks to decode (each ask a tick later): the thread still finishes the
// frames it starts, so playback shows frames rather than restarting the decode at every ask.
TEST(SequencePlayer, KeepsShowingFramesWhenOneDecodeSpansManyTicks) {
    EnvironmentSequence s = writeSequence("player-slow", 2, 10.0);
    const fs::path dir = fs::path(s.pattern).parent_path();
    s.pattern = (dir / "wide_%03d.exr").string();
    s.count = 8;
    app::writeProceduralSkySequence(s.pattern, s.count, 512);  // decoded and resampled: milliseconds
    app::SequencePlayer player(s, 64, 32);
    double seconds = 0.0;
    for (int i = 0; i < 4000; ++i) {
        seconds += 0.1;  // a tick an ask
        std::this_thread::sleep_for(std::chrono::microseconds(100));
        if (const auto frame = player.frameToBake(seconds)) {
            ASSERT_EQ(frame->error, "");
            player.swappedIn(seconds);
        }
    }
    EXPECT_GE(player.stats().shown, 10u) << "the decodes never finished";
}

TEST(SequencePlayer, AnUnreadableFrameIsDroppedAndTheSkyHoldsTheLastOne) {
    const EnvironmentSequence s = writeSequence("player-unreadable", 4, 10.0);
    std::ofstream(s.frame(1), std::ios::binary) << "not an EXR";
    app::SequencePlayer player(s, 32, 16);
    const auto frame = waitFor([&] { return player.frameToBake(0.1); });
    ASSERT_TRUE(frame);
    EXPECT_NE(frame->error, "");
    player.swappedIn(0.12);  // nothing was baked: nothing changes on screen
    EXPECT_EQ(player.stats().current, 0u);
    EXPECT_EQ(player.stats().shown, 1u);
    EXPECT_EQ(player.stats().dropped, 1u);
    EXPECT_EQ(player.stats().failed, 1u);
    const auto next = waitFor([&] { return player.frameToBake(0.2); });
    ASSERT_TRUE(next);
    EXPECT_EQ(next->index, 2u);
    EXPECT_EQ(next->error, "");
}

}  // namespace
}  // namespace skygraph::test
