// Notices when a file is saved, for `skygraph compile --watch` and `skygraph view`.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace skygraph::app {

/// Remembers a file's contents and reports when they differ. Compares contents rather than
/// modification times so that editors which save by rename, and saves within one timestamp
/// tick, are both seen; graph files are small. Owns only the copy of the contents.
class FileWatcher {
public:
    /// Reads the file's current contents (none if it cannot be read yet).
    explicit FileWatcher(std::filesystem::path file);

    /// True when the file can be read and its contents differ from the last time this
    /// returned true (or from construction). A file that is briefly missing or empty mid-save
    /// (saved by rename, or truncated and then written in place) is not a change, so a save
    /// is one change; no graph or scene file is empty.
    [[nodiscard]] bool changed();

    [[nodiscard]] const std::filesystem::path& file() const noexcept { return file_; }

private:
    std::filesystem::path file_;
    std::optional<std::string> contents_;
};

}  // namespace skygraph::app
