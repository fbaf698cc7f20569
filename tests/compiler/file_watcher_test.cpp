// app::FileWatcher, which `compile --watch` and `view` poll: one change per save, however the
// save is made.
#include "file_watcher.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using skygraph::app::FileWatcher;

class FileWatcherTest : public ::testing::Test {
protected:
    void SetUp() override {
        file_ = fs::temp_directory_path() / ("skygraph-watched-" + std::to_string(::getpid()) + ".json");
        save("{\"version\": 1}");
    }
    void TearDown() override {
        std::error_code ignored;
        fs::remove(file_, ignored);
    }
    void save(const std::string& text) const { std::ofstream(file_, std::ios::trunc) << text; }

    fs::path file_;
};

TEST_F(FileWatcherTest, ASaveIsOneChangeAndTheSameTextNone) {
    FileWatcher watcher(file_);
    EXPECT_FALSE(watcher.changed());
    save("{\"version\": 2}");
    EXPECT_TRUE(watcher.changed());
    EXPECT_FALSE(watcher.changed()) << "the same save seen twice";
    save("{\"version\": 2}");
    EXPECT_FALSE(watcher.changed()) << "saved again unchanged";
}

// A save in place truncates, then writes: the empty file between is not a change, so the
// save costs one rebuild, not a failed one for an empty graph first.
TEST_F(FileWatcherTest, TheEmptyFileOfASaveInPlaceIsNotAChange) {
    FileWatcher watcher(file_);
    std::ofstream truncated(file_, std::ios::trunc);
    truncated.flush();
    EXPECT_FALSE(watcher.changed());
    truncated << "{\"version\": 3}";
    truncated.close();
    EXPECT_TRUE(watcher.changed());
    EXPECT_FALSE(watcher.changed());
}

// A save by rename leaves the file missing for a moment: not a change either, and its return
// with other contents is one.
TEST_F(FileWatcherTest, AFileMissingMidSaveIsNotAChange) {
    FileWatcher watcher(file_);
    fs::remove(file_);
    EXPECT_FALSE(watcher.changed());
    save("{\"version\": 4}");
    EXPECT_TRUE(watcher.changed());
}

}  // namespace
