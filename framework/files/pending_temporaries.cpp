#include "pending_temporaries.hpp"

#include <limits.h>
#include <unistd.h>

#include <atomic>
#include <cstring>

namespace skygraph::files {
namespace {

// A signal handler may run on any thread at any point, so the names live in fixed storage and
// a slot is read only while its state says it is whole. The handler claims a slot before
// reading it, and a claimed slot is never freed: the process is ending.
enum SlotState : int { kFree, kFilling, kNamed, kRemoving };

struct Slot {
    std::atomic<int> state{kFree};
    char path[PATH_MAX];
};

Slot slots[kMostPendingTemporaries];

static_assert(std::atomic<int>::is_always_lock_free, "a signal handler reads the slots' states");

}  // namespace

PendingTemporary::PendingTemporary(const std::filesystem::path& path) noexcept {
    const std::string& name = path.native();
    if (name.size() >= PATH_MAX) return;
    for (int i = 0; i < kMostPendingTemporaries; ++i) {
        int expected = kFree;
        if (!slots[i].state.compare_exchange_strong(expected, kFilling)) continue;
        std::memcpy(slots[i].path, name.c_str(), name.size() + 1);
        slots[i].state.store(kNamed);
        slot_ = i;
        return;
    }
}

PendingTemporary::~PendingTemporary() {
    int named = kNamed;
    if (slot_ >= 0) slots[slot_].state.compare_exchange_strong(named, kFree);
}

void removePendingTemporaries() noexcept {
    for (Slot& slot : slots) {
        int named = kNamed;
        if (slot.state.compare_exchange_strong(named, kRemoving)) ::unlink(slot.path);
    }
}

}  // namespace skygraph::files
