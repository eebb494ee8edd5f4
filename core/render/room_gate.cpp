#include "core/render/room_gate.h"

namespace pushpin::render {

RoomGate::Tile::Tile(RoomGate& gate, const std::function<void()>& onHeld) : m_gate(gate) {
    std::unique_lock lock(m_gate.m_mutex);
    if (m_gate.m_holding > 0) {
        lock.unlock();
        if (onHeld) onHeld();
        lock.lock();
        m_gate.m_changed.wait(lock, [&] { return m_gate.m_holding == 0; });
    }
    ++m_gate.m_inTile;
}

RoomGate::Tile::~Tile() {
    {
        std::lock_guard lock(m_gate.m_mutex);
        --m_gate.m_inTile;
        ++m_gate.m_ended;
    }
    m_gate.m_changed.notify_all();
}

bool RoomGate::Turn::wait() {
    std::unique_lock lock(m_gate.m_mutex);
    if (m_gate.m_inTile - m_gate.m_waiting - 1 <= 0) return false;
    if (!m_holding) {
        m_holding = true;
        ++m_gate.m_holding;
    }
    ++m_gate.m_waiting;
    ++m_gate.m_waits;
    const uint64_t seen = m_gate.m_ended;
    m_gate.m_changed.wait(lock, [&] { return m_gate.m_ended != seen; });
    --m_gate.m_waiting;
    return true;
}

RoomGate::Turn::~Turn() {
    if (!m_holding) return;
    {
        std::lock_guard lock(m_gate.m_mutex);
        --m_gate.m_holding;
    }
    m_gate.m_changed.notify_all();
}

uint64_t RoomGate::waits() const {
    std::lock_guard lock(m_mutex);
    return m_waits;
}

}  // namespace pushpin::render
