// Builds a JsonDocument from nlohmann's SAX events (json_document.cpp). Internal to the JSON
// reader.
#pragma once

#include "json_document.hpp"
#include "json_path.hpp"

#include <algorithm>
#include <bit>
#include <string>
#include <vector>

namespace skygraph {

namespace json_detail {

/// Byte order, as std::string's, with the first bytes compared inline (see sameKey).
inline bool keyLess(std::string_view a, std::string_view b) {
    if (!a.empty() && !b.empty() && a[0] != b[0])
        return static_cast<unsigned char>(a[0]) < static_cast<unsigned char>(b[0]);
    return a < b;
}

}  // namespace json_detail

// The values of each open container wait in `pending_` until it closes; then they move, side
// by side, into the document (sorted by key for objects), so a container's children are always
// contiguous. JSON paths, needed only for errors and repeated keys, are worked out from the
// open containers when asked for.
class JsonDocumentBuilder {
public:
    using Node = JsonValue::Node;
    using Kind = JsonValue::Kind;

    JsonDocumentBuilder(JsonDocument& document, std::string_view text, JsonListener* listener)
        : doc_(document), listener_(listener) {
        doc_.text_ = text;
    }

    std::string error;      ///< Set by a parse error or the depth limit.
    size_t errorByte = 0;   ///< nlohmann's position for parse errors.
    bool tooDeep = false;
    std::string errorPath;

    /// A string of the text, by its offset and length, as the document stores it.
    static uint64_t inText(size_t offset, size_t length) { return offset | (uint64_t(length) << 32); }
    /// `s`, copied to the document's decoded strings.
    uint64_t decoded(std::string_view s) {
        // Decoded strings are never longer than their text, and all of them are in the text
        // after the last event's end: room for that much, made before the first, keeps the
        // buffer (and views of its strings) in place while it is filled. (Not capacity() == 0:
        // an empty std::string already has room for a few bytes in itself.)
        if (doc_.decoded_.empty()) doc_.decoded_.reserve(doc_.text_.size() - position_);
        const size_t offset = doc_.text_.size() + doc_.decoded_.size();
        doc_.decoded_.append(s);
        return offset | (uint64_t(s.size()) << 32);
    }

    /// Events give where in the text they end (open: where the container begins).
    bool add(Kind kind, uint64_t payload, size_t textEnd) {
        position_ = textEnd;
        const Node n = placed(kind, payload);
        if (frames_.empty()) doc_.root_ = n;
        else complete(n);
        return true;
    }
    void key(uint64_t ref) {
        Frame& f = frames_.back();
        f.keyOffset = static_cast<uint32_t>(ref);
        f.keyLength = static_cast<uint32_t>(ref >> 32);
        f.keyOrder = keys_++;
    }
    bool open(bool array, size_t offset) {
        position_ = offset;
        if (frames_.size() >= kMaxJsonDepth) {
            tooDeep = true;
            error = "nesting deeper than " + std::to_string(kMaxJsonDepth) + " levels";
            errorPath = path(true);
            return false;  // stops the parse
        }
        // The container's own place (key, index) is taken now; its node is written on close.
        const Node self = placed(array ? Kind::Array : Kind::Object, 0);
        bool stream = false;
        if (listener_ && frames_.size() <= 2) {  // the listener's parts are near the root
            if (streaming()) elementNodes_ = doc_.nodes_.size();
            stream = array && frames_.size() == 1 && !frames_[0].array &&
                     listener_->streamArray(keyOf(self), offset);
        }
        Frame f;
        f.array = array;
        f.streamed = stream;
        f.firstPending = static_cast<uint32_t>(pending_.size());
        f.ownKeyOffset = self.keyOffset;
        f.ownKeyLength = self.keyLength;
        f.ownKeyOrder = self.keyOrder;
        frames_.push_back(f);
        return true;
    }
    bool close(Kind kind, size_t textEnd) {
        position_ = textEnd;
        const Frame frame = frames_.back();
        size_t end = pending_.size();
        if (kind == Kind::Object) end = sortMembers(frame.firstPending, end);
        Node self;
        self.kind = kind;
        self.keyOffset = frame.ownKeyOffset;
        self.keyLength = frame.ownKeyLength;
        self.keyOrder = frame.ownKeyOrder;
        self.payload = doc_.nodes_.size() | (uint64_t(end - frame.firstPending) << 32);
        doc_.nodes_.insert(doc_.nodes_.end(), pending_.begin() + frame.firstPending,
                           pending_.begin() + static_cast<std::ptrdiff_t>(end));
        pending_.resize(frame.firstPending);
        frames_.pop_back();
        if (frames_.empty()) doc_.root_ = self;
        else complete(self);
        return true;
    }

    /// Repeated keys in the order the text has them (they are found per object, as each
    /// closes).
    std::vector<DuplicateKey> takeDuplicates() {
        std::stable_sort(duplicates_.begin(), duplicates_.end(),
                         [](const auto& a, const auto& b) { return a.first < b.first; });
        std::vector<DuplicateKey> out;
        out.reserve(duplicates_.size());
        for (auto& [order, dup] : duplicates_) out.push_back(std::move(dup));
        return out;
    }

    /// Path of the innermost open container (for parse errors).
    [[nodiscard]] std::string currentPath() const { return path(false); }
    /// The path of the value being read: the next element of the innermost array, or the
    /// current key's member of the innermost object. Only while a value is being read: where
    /// a key is expected, the current key is the previous member's.
    [[nodiscard]] std::string valuePath() const { return path(true); }

private:
    struct Frame {
        bool array = false;
        bool streamed = false;      ///< An array whose elements go to the listener.
        uint32_t firstPending = 0;  ///< Where its values start in pending_.
        uint32_t next = 0;          ///< Arrays: index of the next element.
        uint32_t ownKeyOffset = 0;  ///< Its own key in its parent object.
        uint32_t ownKeyLength = 0;
        uint32_t ownKeyOrder = 0;
        uint32_t keyOffset = 0;     ///< Objects: the current key (of the open child or the next value).
        uint32_t keyLength = 0;
        uint32_t keyOrder = 0;
    };

    [[nodiscard]] std::string_view keyOf(const Node& n) const { return {doc_.at(n.keyOffset), n.keyLength}; }
    /// Whether the innermost open container is the array being streamed.
    [[nodiscard]] bool streaming() const { return frames_.size() == 2 && frames_[1].streamed; }

    /// Where a value of the innermost container goes: the next element or the current key.
    /// Counts it in its array.
    Node placed(Kind kind, uint64_t payload) {
        Node n;
        n.kind = kind;
        n.payload = payload;
        if (!frames_.empty()) {
            Frame& f = frames_.back();
            if (f.array) {
                ++f.next;
            } else {
                n.keyOffset = f.keyOffset;
                n.keyLength = f.keyLength;
                n.keyOrder = f.keyOrder;
            }
        }
        return n;
    }

    /// A complete value of the innermost open container: kept in it, or told to the listener.
    void complete(const Node& n) {
        if (listener_ && frames_.size() <= 2) {
            if (streaming()) {
                listener_->element(frames_[1].next - 1, JsonValue(&doc_, &n), position_);
                if (n.kind == Kind::Object || n.kind == Kind::Array)
                    doc_.nodes_.resize(elementNodes_);  // drops its children
                return;
            }
            if (frames_.size() == 1 && !frames_[0].array) listener_->rootMember(keyOf(n), JsonValue(&doc_, &n));
        }
        pending_.push_back(n);
    }

    /// Sorts the closing object's members by key, keeping the order of equal keys, and keeps
    /// the last of each repeated key (as nlohmann::json does), noting the others. Returns the
    /// new end.
    size_t sortMembers(size_t first, size_t end) {
        if (end - first < 2) return end;
        auto begin = pending_.begin() + static_cast<std::ptrdiff_t>(first);
        auto last = pending_.begin() + static_cast<std::ptrdiff_t>(end);
        const auto less = [this](const Node& a, const Node& b) { return json_detail::keyLess(keyOf(a), keyOf(b)); };
        if (end - first <= 16) {  // most objects: insertion sort, stable
            for (auto i = begin + 1; i != last; ++i) {
                const Node n = *i;
                auto j = i;
                for (; j != begin && less(n, *(j - 1)); --j) *j = *(j - 1);
                *j = n;
            }
        } else if (!std::is_sorted(begin, last, less)) {
            sortLarge(first, end);
        }
        size_t out = first;
        for (size_t i = first; i < end; ++i) {
            if (i + 1 < end && sameKey(keyOf(pending_[i]), keyOf(pending_[i + 1]))) {
                noteDuplicate(pending_[i + 1]);  // the later one repeats the key
                continue;                        // the last one wins
            }
            pending_[out++] = pending_[i];
        }
        return out;
    }

    /// A large object (the resources of a graph): sorted by each key's first 8 bytes, read
    /// once into an array of their own, before whole keys, which sit all over the text, are
    /// compared (only where those bytes tie). Stable, as sortMembers.
    void sortLarge(size_t first, size_t end) {
        struct Keyed {
            uint64_t prefix;  ///< Big-endian, so that it orders as the bytes do.
            uint32_t at;
        };
        std::vector<Keyed> keyed(end - first);
        for (size_t i = first; i < end; ++i) {
            const std::string_view k = keyOf(pending_[i]);
            unsigned char bytes[8] = {};
            if (!k.empty()) std::memcpy(bytes, k.data(), std::min<size_t>(k.size(), 8));
            uint64_t prefix = 0;
            for (const unsigned char b : bytes) prefix = prefix << 8 | b;
            keyed[i - first] = {prefix, static_cast<uint32_t>(i)};
        }
        std::stable_sort(keyed.begin(), keyed.end(), [this](const Keyed& a, const Keyed& b) {
            if (a.prefix != b.prefix) return a.prefix < b.prefix;
            return keyOf(pending_[a.at]) < keyOf(pending_[b.at]);
        });
        std::vector<Node> sorted(end - first);
        for (size_t i = 0; i < sorted.size(); ++i) sorted[i] = pending_[keyed[i].at];
        std::copy(sorted.begin(), sorted.end(), pending_.begin() + static_cast<std::ptrdiff_t>(first));
    }

    void noteDuplicate(const Node& n) {
        const std::string_view key = keyOf(n);
        duplicates_.push_back({n.keyOrder, {jsonPathMember(path(false), key), std::string(key)}});
    }

    /// The innermost open container's path or, with `pending`, that of where the next value
    /// goes: each open container's place is its parent's current key or last index.
    [[nodiscard]] std::string path(bool pending) const {
        std::string out;
        for (size_t i = 0; i < frames_.size(); ++i) {
            const bool last = i + 1 == frames_.size();
            if (last && !pending) break;
            const Frame& f = frames_[i];
            if (f.array) {
                out += "[" + std::to_string(last ? f.next : f.next - 1) + "]";
            } else {
                out = jsonPathMember(out, std::string_view(doc_.at(f.keyOffset), f.keyLength));
            }
        }
        return out;
    }

    JsonDocument& doc_;
    JsonListener* listener_;
    size_t position_ = 0;  ///< Where the last event ended in the text.
    std::vector<Node> pending_;
    std::vector<Frame> frames_;
    size_t elementNodes_ = 0;  ///< Streaming: the document's size when the element began.
    uint32_t keys_ = 0;        ///< Keys so far.
    std::vector<std::pair<uint32_t, DuplicateKey>> duplicates_;  ///< With their keyOrder
};
}  // namespace skygraph
