#pragma once
// Live-heap counter for the node-memory figures of sgfx_cull and osg_cull (include in exactly one
// translation unit of a program: it replaces the global operator new/delete). Counts
// malloc_usable_size, i.e. what the allocator really hands out (size rounded up to its bins; the
// 8-byte chunk header is not included), the same way on both sides. Off unless a program switches
// it on, so the timed runs pay one predictable branch per allocation.
#include <malloc.h>

#include <cstddef>
#include <cstdlib>
#include <new>

namespace alloccount {
inline bool enabled = false;
inline long long live = 0;  // bytes
inline long long count = 0; // allocations
} // namespace alloccount

namespace alloccount {
// The operators below call these, not each other: GCC otherwise inlines one into another and
// reports a malloc/operator delete mismatch that is not there.
[[gnu::noinline]] inline void* acquire(std::size_t n) {
    void* p = std::malloc(n ? n : 1);
    if (!p) throw std::bad_alloc();
    if (enabled) {
        live += static_cast<long long>(malloc_usable_size(p));
        ++count;
    }
    return p;
}
[[gnu::noinline]] inline void release(void* p) noexcept {
    if (p && enabled) {
        live -= static_cast<long long>(malloc_usable_size(p));
        --count;
    }
    std::free(p);
}
} // namespace alloccount

void* operator new(std::size_t n) {
    return alloccount::acquire(n);
}
void* operator new[](std::size_t n) {
    return alloccount::acquire(n);
}
void operator delete(void* p) noexcept {
    alloccount::release(p);
}
void operator delete[](void* p) noexcept {
    alloccount::release(p);
}
void operator delete(void* p, std::size_t) noexcept {
    alloccount::release(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    alloccount::release(p);
}
