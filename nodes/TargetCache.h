#pragma once
/// @file
/// A few GPU target sets kept by view size (and whatever else the caller matches on), so that a
/// render-to-texture view and the main view do not reallocate each other's every frame; the least
/// recently used one goes when a fifth is needed. `T` needs a `std::uint64_t lastUse` member.
#include <algorithm>
#include <cstdint>
#include <vector>

namespace sgfx::nodes {

/// Per-view-size GPU targets, least recently used first out (see the file comment).
template <class T, std::size_t Capacity = 4> class TargetCache {
public:
    // The entry `matches` accepts, or a new one that `init` sets up.
    template <class Match, class Init> T& get(std::uint64_t frame, Match matches, Init init) {
        for (T& t : entries_)
            if (matches(t)) {
                t.lastUse = frame;
                return t;
            }
        if (entries_.size() >= Capacity)
            entries_.erase(std::min_element(entries_.begin(), entries_.end(),
                                            [](const T& a, const T& b) { return a.lastUse < b.lastUse; }));
        T& t = entries_.emplace_back();
        t.lastUse = frame;
        init(t);
        return t;
    }

    // Drops every entry (their GL objects with them); the context they were made in must be current.
    void clear() { entries_.clear(); }

private:
    std::vector<T> entries_;
};

} // namespace sgfx::nodes
