// A one-line progress bar on stderr for long subcommand work (`render --frames N`, the
// cubemap and IBL products). Reusable by any subcommand: construct it with the amount of
// work, call advance() as units finish, and finish() (or let it go out of scope).
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace skygraph::cli {

/// When progress bars draw: `Auto` only if stderr is a terminal (so logs and CI output stay
/// clean), `Always` also into files and pipes, `Never` not at all. Set once by main() from
/// --progress and -q.
enum class ProgressMode : uint8_t { Auto, Always, Never };

/// Draws "label [#####.....] done/total unit  elapsed" on one stderr line, redrawn in place at
/// most ten times a second and always at the end. Owns nothing but its counters; not
/// thread-safe (call advance() from the thread that does the work).
class ProgressBar {
public:
    /// `total` units of work named `unit` (e.g. "frames"). Draws the empty bar at once.
    ProgressBar(std::string label, uint64_t total, std::string unit = {});
    /// Calls finish().
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    /// Marks `units` more as done (clamped to the total) and redraws if due.
    void advance(uint64_t units = 1);
    /// Draws the final state and ends the line. Idempotent.
    void finish();

    [[nodiscard]] uint64_t done() const noexcept { return done_; }
    /// Whether this bar writes anything (from the process-wide mode and stderr).
    [[nodiscard]] bool visible() const noexcept { return visible_; }

    /// The process-wide mode; main() sets it after parsing the command line.
    static void setMode(ProgressMode mode) noexcept;
    [[nodiscard]] static ProgressMode mode() noexcept;

private:
    void draw();

    std::string label_;
    std::string unit_;
    uint64_t total_;
    uint64_t done_ = 0;
    uint64_t drawnDone_ = UINT64_MAX;  ///< What the line shows now; the final state is drawn once.
    bool visible_;
    bool finished_ = false;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point lastDraw_;
};

}  // namespace skygraph::cli
