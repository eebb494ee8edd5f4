// core/util/page_array.h: a growable array of plain values in pages of their own (an anonymous
// mapping), grown in place by the kernel (mremap): growing neither copies the values nor holds
// the old and the new storage at once, so a memory budget need only be told what it grows by.
// For a buffer that grows large and is reused (a tile's fragments); small arrays belong in a
// std::vector. Not thread-safe; one owner.
// Memory: capacity() values rounded up to whole pages, resident as they are written.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>

#include <sys/mman.h>
#include <unistd.h>

namespace pushpin::util {

template <class T>
class PageArray {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>,
                  "PageArray moves its values by remapping pages");

public:
    PageArray() = default;
    PageArray(const PageArray&) = delete;
    PageArray& operator=(const PageArray&) = delete;
    PageArray(PageArray&& o) noexcept
        : m_data(std::exchange(o.m_data, nullptr)), m_size(std::exchange(o.m_size, 0)),
          m_capacity(std::exchange(o.m_capacity, 0)) {}
    PageArray& operator=(PageArray&& o) noexcept {
        if (this != &o) {
            release();
            m_data = std::exchange(o.m_data, nullptr);
            m_size = std::exchange(o.m_size, 0);
            m_capacity = std::exchange(o.m_capacity, 0);
        }
        return *this;
    }
    ~PageArray() { release(); }

    size_t size() const { return m_size; }
    bool empty() const { return m_size == 0; }
    size_t capacity() const { return m_capacity; }
    T* data() { return m_data; }
    const T* data() const { return m_data; }
    T* begin() { return m_data; }
    T* end() { return m_data + m_size; }
    const T* begin() const { return m_data; }
    const T* end() const { return m_data + m_size; }
    T& operator[](size_t i) { return m_data[i]; }
    const T& operator[](size_t i) const { return m_data[i]; }

    // Bytes the mapping would take for room for `count` values (whole pages).
    static uint64_t bytesFor(size_t count) {
        const uint64_t page = pageBytes();
        return (uint64_t(count) * sizeof(T) + page - 1) / page * page;
    }
    uint64_t bytes() const { return m_capacity ? bytesFor(m_capacity) : 0; }

    // Room for at least `count` values (the values kept). Throws std::bad_alloc when the system
    // has no memory for it.
    void reserve(size_t count) {
        if (count <= m_capacity) return;
        const uint64_t newBytes = bytesFor(count);
        void* p = m_data ? mremap(m_data, bytes(), newBytes, MREMAP_MAYMOVE)
                         : mmap(nullptr, newBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) throw std::bad_alloc();
        m_data = static_cast<T*>(p);
        m_capacity = size_t(newBytes / sizeof(T));
    }
    // Appends within the capacity: the caller reserves first.
    void pushWithinCapacity(const T& value) { m_data[m_size++] = value; }
    void clear() { m_size = 0; }
    // Gives the pages back.
    void release() {
        if (m_data) munmap(m_data, bytes());
        m_data = nullptr;
        m_size = m_capacity = 0;
    }

private:
    static uint64_t pageBytes() {
        static const uint64_t page = uint64_t(sysconf(_SC_PAGESIZE));
        return page;
    }
    T* m_data = nullptr;
    size_t m_size = 0;
    size_t m_capacity = 0;
};

}  // namespace pushpin::util
