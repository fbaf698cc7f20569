#include "file_watcher.hpp"

#include <fstream>
#include <sstream>

namespace skygraph::app {

FileWatcher::FileWatcher(std::filesystem::path file) : file_(std::move(file)), contents_(read()) {}

bool FileWatcher::changed() {
    std::optional<std::string> now = read();
    // Empty: truncated by a save in place (a shell's `>`, many editors) and not written yet.
    if (!now || now->empty() || now == contents_) return false;
    contents_ = std::move(now);
    return true;
}

std::optional<std::string> FileWatcher::read() const {
    std::ifstream in(file_, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace skygraph::app
