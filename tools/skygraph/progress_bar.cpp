#include "progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>

namespace skygraph::cli {
namespace {

std::atomic<ProgressMode> gMode{ProgressMode::Auto};

constexpr int kBarWidth = 30;
constexpr auto kRedrawInterval = std::chrono::milliseconds(100);

}  // namespace

void ProgressBar::setMode(ProgressMode mode) noexcept { gMode = mode; }
ProgressMode ProgressBar::mode() noexcept { return gMode; }

ProgressBar::ProgressBar(std::string label, uint64_t total, std::string unit)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(std::max<uint64_t>(total, 1)),
      visible_(gMode == ProgressMode::Always || (gMode == ProgressMode::Auto && ::isatty(STDERR_FILENO))),
      start_(std::chrono::steady_clock::now()),
      lastDraw_(start_) {
    draw();
}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::advance(uint64_t units) {
    done_ = std::min(total_, done_ + units);
    const auto now = std::chrono::steady_clock::now();
    if (done_ == total_ || now - lastDraw_ >= kRedrawInterval) draw();
}

void ProgressBar::finish() {
    if (finished_) return;
    finished_ = true;
    if (!visible_) return;
    if (drawnDone_ != done_) draw();
    std::fputc('\n', stderr);
    std::fflush(stderr);
}

void ProgressBar::draw() {
    if (!visible_) return;
    lastDraw_ = std::chrono::steady_clock::now();
    drawnDone_ = done_;
    const double seconds = std::chrono::duration<double>(lastDraw_ - start_).count();
    const int filled = static_cast<int>(done_ * kBarWidth / total_);
    std::string bar(static_cast<size_t>(filled), '#');
    bar.append(static_cast<size_t>(kBarWidth - filled), '.');
    // \r and "erase line" redraw in place on a terminal; in a file each state is still legible.
    std::fprintf(stderr, "\r\033[2K%s [%s] %llu/%llu%s%s %5.1fs", label_.c_str(), bar.c_str(),
                 static_cast<unsigned long long>(done_), static_cast<unsigned long long>(total_),
                 unit_.empty() ? "" : " ", unit_.c_str(), seconds);
    std::fflush(stderr);
}

}  // namespace skygraph::cli
