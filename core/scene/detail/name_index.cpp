#include "core/scene/detail/name_index.h"

#include <algorithm>
#include <limits>

namespace pushpin::scene::detail {

namespace {
// How far a base's array may reach past the names it holds: twice their count and a little more,
// so that memory stays within a small multiple of the names whatever numbers a file uses.
size_t slotLimit(uint32_t count) { return 2 * size_t(count) + 16; }
}  // namespace

NameIndex::Split NameIndex::split(std::string_view name) {
    size_t start = name.size();
    while (start > 0 && name[start - 1] >= '0' && name[start - 1] <= '9') --start;
    const size_t digits = name.size() - start;
    if (digits == 0 || digits > 9 || (digits > 1 && name[start] == '0')) return Split{name, 0, false};
    uint32_t number = 0;
    for (size_t i = start; i < name.size(); ++i) number = number * 10 + uint32_t(name[i] - '0');
    return Split{name.substr(0, start), number, true};
}

uint32_t NameIndex::findBase(std::string_view base) const {
    return m_baseIndex.find(util::hashBytes(base), [&](uint32_t b) { return baseText(m_bases[b]) == base; });
}

uint32_t* NameIndex::slotOf(const Split& s, uint32_t* base) {
    const uint32_t b = findBase(s.base);
    if (base) *base = b;
    if (b == kNone || s.number >= m_bases[b].slots.size()) return nullptr;
    return &m_bases[b].slots[s.number];
}

uint32_t NameIndex::addBase(std::string_view base) {
    if (m_bases.size() >= kNone || m_text.size() + base.size() > std::numeric_limits<uint32_t>::max()) return kNone;
    const uint32_t b = uint32_t(m_bases.size());
    Base& record = m_bases.emplace_back();
    record.textOffset = uint32_t(m_text.size());
    record.textSize = uint32_t(base.size());
    m_text.append(base);
    m_baseIndex.insert(util::hashBytes(base), b);
    return b;
}

void NameIndex::insert(std::string_view name, uint32_t entry) {
    ++m_count;
    const Split s = split(name);
    if (s.numbered) {
        uint32_t b = findBase(s.base);
        if (b == kNone) b = addBase(s.base);
        if (b != kNone) {
            Base& base = m_bases[b];
            const size_t limit = slotLimit(base.count);
            if (s.number >= base.slots.size() && s.number < limit)
                base.slots.resize(std::min(limit, std::max(size_t(s.number) + 1, 2 * base.slots.size())), kNone);
            if (s.number < base.slots.size()) {
                base.slots[s.number] = entry;
                ++base.count;
                return;
            }
        }
        ++m_othersNumbered;
    }
    m_others.insert(util::hashBytes(name), entry);
}

bool NameIndex::replace(std::string_view name, uint32_t entry, uint32_t replacement) {
    const Split s = split(name);
    if (s.numbered)
        if (uint32_t* slot = slotOf(s); slot && *slot == entry) {
            *slot = replacement;
            return true;
        }
    return m_others.replace(util::hashBytes(name), [&](uint32_t e) { return e == entry; }, replacement);
}

bool NameIndex::erase(std::string_view name, uint32_t entry) {
    const Split s = split(name);
    if (s.numbered) {
        uint32_t b = kNone;
        if (uint32_t* slot = slotOf(s, &b); slot && *slot == entry) {
            *slot = kNone;
            --m_bases[b].count;
            --m_count;
            return true;
        }
    }
    if (m_others.erase(util::hashBytes(name), [&](uint32_t e) { return e == entry; }) == kNone) return false;
    if (s.numbered) --m_othersNumbered;
    --m_count;
    return true;
}

size_t NameIndex::memoryBytes() const {
    size_t bytes = m_bases.capacity() * sizeof(Base) + m_baseIndex.memoryBytes() + m_text.capacity() +
                   m_others.memoryBytes();
    for (const Base& b : m_bases) bytes += b.slots.capacity() * sizeof(uint32_t);
    return bytes;
}

}  // namespace pushpin::scene::detail
