// What happens in a folder, seen through inotify: the files made in it, renamed into it and
// closed after writing, by name. For tests that count writes (an output written once, renamed
// into place once), which the folder's contents afterwards cannot show.
#pragma once

#include <sys/inotify.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace skygraph::test {

class FolderEvents {
public:
    /// Events by file name: how many times each happened.
    struct Counts {
        std::map<std::string, int> created;    ///< IN_CREATE: a new file (or link) by that name
        std::map<std::string, int> renamedTo;  ///< IN_MOVED_TO: a file renamed to that name
        std::map<std::string, int> written;    ///< IN_CLOSE_WRITE: closed after it was opened to write
    };

    /// Watches `folder` (not its subfolders) from now on. Throws std::runtime_error when it cannot.
    explicit FolderEvents(const std::filesystem::path& folder) : fd_(::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) {
        if (fd_ < 0 || ::inotify_add_watch(fd_, folder.c_str(), IN_CREATE | IN_MOVED_TO | IN_CLOSE_WRITE) < 0) {
            if (fd_ >= 0) ::close(fd_);
            throw std::runtime_error("inotify cannot watch " + folder.string());
        }
    }
    ~FolderEvents() { ::close(fd_); }
    FolderEvents(const FolderEvents&) = delete;
    FolderEvents& operator=(const FolderEvents&) = delete;

    /// The events since construction or the last call: the kernel queues each as its system
    /// call returns, so a command that has ended has had all of its counted. Throws
    /// std::runtime_error when the queue overflowed and events were lost.
    Counts take() {
        alignas(inotify_event) char buffer[1 << 16];
        for (ssize_t n; (n = ::read(fd_, buffer, sizeof buffer)) > 0;)
            for (const char* at = buffer; at < buffer + n;) {
                const auto* event = reinterpret_cast<const inotify_event*>(at);
                if (event->mask & IN_Q_OVERFLOW) throw std::runtime_error("inotify's queue overflowed");
                const std::string name = event->len ? event->name : "";
                if (event->mask & IN_CREATE) ++counts_.created[name];
                if (event->mask & IN_MOVED_TO) ++counts_.renamedTo[name];
                if (event->mask & IN_CLOSE_WRITE) ++counts_.written[name];
                at += sizeof(inotify_event) + event->len;
            }
        return std::exchange(counts_, {});
    }

private:
    int fd_;
    Counts counts_;
};

}  // namespace skygraph::test
