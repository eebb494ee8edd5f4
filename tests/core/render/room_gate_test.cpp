// Tests for core/render/room_gate.h: a tile without room waits for another thread's tile to end,
// holds new tiles back meanwhile, and never waits when nothing else could end.
#include "core/render/room_gate.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace pushpin::render {
namespace {

// Spins until `done()` holds (or 10 s pass, which fails the test).
template <class Done>
bool eventually(Done&& done) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!done()) {
        if (std::chrono::steady_clock::now() > until) return false;
        std::this_thread::yield();
    }
    return true;
}

TEST(RoomGate, ATileAloneDoesNotWait) {
    RoomGate gate;
    const RoomGate::Tile tile(gate, {});
    RoomGate::Turn turn(gate);
    EXPECT_FALSE(turn.wait());
    EXPECT_EQ(gate.waits(), 0u);
}

TEST(RoomGate, WaitsForAnotherThreadsTileToEndAndHoldsNewTilesBack) {
    RoomGate gate;
    std::atomic<bool> otherInTile{false}, endOther{false}, waited{false}, thirdStarted{false}, turnDone{false};
    std::atomic<int> onHeldCalls{0};
    std::thread other([&] {
        {
            const RoomGate::Tile tile(gate, {});
            otherInTile = true;
            eventually([&] { return endOther.load(); });
        }
        // The next tile of this thread waits until the search for room is over.
        const RoomGate::Tile next(gate, [&] { ++onHeldCalls; });
        thirdStarted = true;
        EXPECT_TRUE(turnDone.load());
    });
    ASSERT_TRUE(eventually([&] { return otherInTile.load(); }));
    {
        const RoomGate::Tile tile(gate, {});
        RoomGate::Turn turn(gate);
        std::thread ender([&] {
            eventually([&] { return gate.waits() == 1; });
            endOther = true;
        });
        EXPECT_TRUE(turn.wait());
        waited = true;
        ender.join();
        // The other thread's next tile is held while this turn lasts.
        ASSERT_TRUE(eventually([&] { return onHeldCalls.load() == 1; }));
        EXPECT_FALSE(thirdStarted.load());
        // Nothing else runs now: a second wait gives up at once.
        EXPECT_FALSE(turn.wait());
        turnDone = true;
    }
    other.join();
    EXPECT_TRUE(waited.load());
    EXPECT_TRUE(thirdStarted.load());
    EXPECT_EQ(gate.waits(), 1u);
}

TEST(RoomGate, OfTwoTilesWithoutRoomOneGivesUp) {
    RoomGate gate;
    std::atomic<bool> firstInTile{false}, secondInTile{false};
    std::atomic<int> gaveUp{0}, waitedThenRoom{0};
    auto run = [&](std::atomic<bool>& mine, std::atomic<bool>& theirs) {
        const RoomGate::Tile tile(gate, {});
        mine = true;
        eventually([&] { return theirs.load(); });
        RoomGate::Turn turn(gate);
        // One of the two waits (the other is running); the other finds the first waiting and
        // gives up, which ends its tile and wakes the first.
        if (turn.wait())
            ++waitedThenRoom;
        else
            ++gaveUp;
    };
    std::thread a([&] { run(firstInTile, secondInTile); });
    std::thread b([&] { run(secondInTile, firstInTile); });
    a.join();
    b.join();
    EXPECT_EQ(gaveUp.load(), 1);
    EXPECT_EQ(waitedThenRoom.load(), 1);
}

}  // namespace
}  // namespace pushpin::render
