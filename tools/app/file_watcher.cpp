#include "file_watcher.hpp"

#include "read_file.hpp"

namespace skygraph::app {

FileWatcher::FileWatcher(std::filesystem::path file) : file_(std::move(file)), contents_(files::readFile(file_)) {}

bool FileWatcher::changed() {
    std::optional<std::string> now = files::readFile(file_);
    // Empty: truncated by a save in place (a shell's `>`, many editors) and not written yet.
    if (!now || now->empty() || now == contents_) return false;
    contents_ = std::move(now);
    return true;
}

}  // namespace skygraph::app
