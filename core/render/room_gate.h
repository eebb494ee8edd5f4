// core/render/room_gate.h: how the threads of a capped render take turns when a tile finds no
// room in the memory budget. A tile that cannot make room for what it needs next waits for the
// tiles the other threads are rendering to end (their pins and buffers go back); from its first
// wait until it has its room or gives up, no thread starts another tile. The tile then goes on
// where it stopped instead of being given up and rendered again at the end of the frame. A tile
// gives up only when every other thread's tile is waiting too, or none is running.
// Thread-safe; one per frame.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>

namespace pushpin::render {

class RoomGate {
public:
    // A thread's tile, from its start to its end (rendered, given up or failed). Starting waits
    // while a tile of another thread searches for room, after calling `onHeld` (without the
    // gate's lock) so that the thread can give back what it holds between tiles; ending wakes
    // the tiles waiting.
    class Tile {
    public:
        Tile(RoomGate& gate, const std::function<void()>& onHeld);
        ~Tile();
        Tile(const Tile&) = delete;
        Tile& operator=(const Tile&) = delete;

    private:
        RoomGate& m_gate;
    };

    // One search for room inside a tile. wait() waits until a tile of another thread ends and
    // returns true, or returns false at once when no other thread is in a tile that is not itself
    // waiting (nothing would ever end). From the first wait() to the Turn's end, no tile starts.
    class Turn {
    public:
        explicit Turn(RoomGate& gate) : m_gate(gate) {}
        ~Turn();
        Turn(const Turn&) = delete;
        Turn& operator=(const Turn&) = delete;
        bool wait();

    private:
        RoomGate& m_gate;
        bool m_holding = false;
    };

    // How many times a tile waited for another's end.
    uint64_t waits() const;

private:
    mutable std::mutex m_mutex;
    std::condition_variable m_changed;
    int m_inTile = 0;      // threads inside a tile
    int m_holding = 0;     // of those, the ones searching for room after a wait: no tile starts
    int m_waiting = 0;     // of those, the ones waiting for a tile to end
    uint64_t m_ended = 0;  // tiles ended so far
    uint64_t m_waits = 0;
};

}  // namespace pushpin::render
