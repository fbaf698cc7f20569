// Names -> numbers in one flat table (open addressing): what the loader looks every usage's
// resource and every pass's name up in. std::unordered_map allocates a node per name, and on
// a large graph those allocations cost more than the lookups. The names stay where they are,
// found by `NameOf`; a slot keeps a name's length, hash and first 8 bytes, which decide most
// lookups (all of names up to 8 bytes long) without reading the name, often far away in memory.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <functional>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

namespace skygraph {

/// `NameOf` gives the name of a number added (a callable: uint32_t -> std::string_view); the
/// name must not change while the index is used.
template <typename NameOf>
class NameIndex {
public:
    explicit NameIndex(NameOf nameOf) : nameOf_(std::move(nameOf)) {}

    /// What a lookup of a name starts from: worked out once for find() and prefetch().
    struct Key {
        uint32_t tag;     ///< The hash's high 24 bits, the length (up to 255) in the low 8.
        uint64_t prefix;  ///< The first 8 bytes, zeros after a shorter name.
    };

    [[nodiscard]] static Key keyOf(std::string_view name) {
        const auto hash = static_cast<uint32_t>(std::hash<std::string_view>{}(name));
        uint64_t prefix = 0;
        if (!name.empty()) std::memcpy(&prefix, name.data(), std::min<size_t>(name.size(), 8));
        return {(hash & ~0xFFu) | static_cast<uint32_t>(std::min<size_t>(name.size(), 255)), prefix};
    }

    /// Room for `names` names without growing.
    void reserve(size_t names) {
        if (names * 2 > slots_.size()) rehash(std::bit_ceil(std::max<size_t>(16, names * 2)));
    }

    /// Adds `value`, whose name is `name`, unless the name is there: returns the number the
    /// name has and whether it is new.
    std::pair<uint32_t, bool> insert(std::string_view name, uint32_t value) {
        return insert(name, value, keyOf(name));
    }
    /// `key` is keyOf(name).
    std::pair<uint32_t, bool> insert(std::string_view name, uint32_t value, const Key& key) {
        if ((size_ + 1) * 2 > slots_.size()) rehash(std::max<size_t>(16, slots_.size() * 2));
        Slot& s = slots_[probe(name, key)];
        if (s.value != 0) return {s.value - 1, false};
        s = {value + 1, key.tag, key.prefix};
        ++size_;
        return {value, true};
    }

    [[nodiscard]] std::optional<uint32_t> find(std::string_view name) const { return find(name, keyOf(name)); }
    /// `key` is keyOf(name).
    [[nodiscard]] std::optional<uint32_t> find(std::string_view name, const Key& key) const {
        if (slots_.empty()) return std::nullopt;
        const Slot& s = slots_[probe(name, key)];
        if (s.value == 0) return std::nullopt;
        return s.value - 1;
    }

    /// Starts reading the slot where a lookup of `key` begins, for a find() soon after.
    void prefetch(const Key& key) const noexcept {
        if (!slots_.empty()) __builtin_prefetch(&slots_[(key.tag >> 8) & (slots_.size() - 1)]);
    }

private:
    struct Slot {
        uint32_t value = 0;  ///< The number + 1; 0: free.
        uint32_t tag = 0;
        uint64_t prefix = 0;
    };

    /// The slot holding `name`, or the free one where it would go (the table is never full).
    [[nodiscard]] size_t probe(std::string_view name, const Key& key) const {
        const size_t mask = slots_.size() - 1;
        for (size_t i = (key.tag >> 8) & mask;; i = (i + 1) & mask) {
            const Slot& s = slots_[i];
            if (s.value == 0) return i;
            // Equal tags mean equal lengths below 255: such a name of up to 8 bytes is its prefix.
            if (s.tag == key.tag && s.prefix == key.prefix && ((key.tag & 0xFF) <= 8 || nameOf_(s.value - 1) == name))
                return i;
        }
    }

    void rehash(size_t capacity) {
        std::vector<Slot> old = std::exchange(slots_, std::vector<Slot>(capacity));
        const size_t mask = capacity - 1;
        for (const Slot& s : old) {
            if (s.value == 0) continue;
            size_t i = (s.tag >> 8) & mask;
            while (slots_[i].value != 0) i = (i + 1) & mask;
            slots_[i] = s;
        }
    }

    NameOf nameOf_;
    std::vector<Slot> slots_;  ///< A power of two in size, at most half full.
    size_t size_ = 0;
};

}  // namespace skygraph
