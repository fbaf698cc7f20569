// Temporaries that a stopped process would leave behind. A write in progress has a hidden
// temporary beside its target (replace_file.hpp); a SIGINT or SIGTERM that ends the process
// before the rename would leave it there. An application's handler for such signals calls
// removePendingTemporaries() before it ends the process.
#pragma once

#include <filesystem>

namespace skygraph::files {

/// Names `path` as a temporary being written for as long as this object lives; it does not
/// create or remove the file. Not copyable or movable: the registration is this object's.
/// At most kMostPendingTemporaries are named at once (further ones are not removed by a
/// signal), and paths longer than PATH_MAX are not named.
class PendingTemporary {
public:
    explicit PendingTemporary(const std::filesystem::path& path) noexcept;
    ~PendingTemporary();
    PendingTemporary(const PendingTemporary&) = delete;
    PendingTemporary& operator=(const PendingTemporary&) = delete;

private:
    int slot_ = -1;
};

inline constexpr int kMostPendingTemporaries = 64;

/// Removes every file a live PendingTemporary names. Async-signal-safe: meant for a signal
/// handler that ends the process afterwards (the objects still name files that are gone).
void removePendingTemporaries() noexcept;

}  // namespace skygraph::files
