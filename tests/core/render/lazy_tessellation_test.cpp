#include "core/render/lazy_tessellation.h"

#include <gtest/gtest.h>

#include "core/geom/poly_primitives.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

namespace pushpin::render {
namespace {

using geom::GeometryHandle;
using geom::Mesh;

std::shared_ptr<const Mesh> sphere(int axis, int height) {
    geom::PolySphereParams p;
    p.subdivisionsAxis = axis;
    p.subdivisionsHeight = height;
    return std::make_shared<const Mesh>(*geom::makePolySphere(p));
}

// A mesh made again on each call, not kept, and counted.
class CountingSource : public geom::MeshSource {
public:
    explicit CountingSource(std::shared_ptr<const Mesh> mesh) : m_mesh(std::move(mesh)) {}
    std::shared_ptr<const Mesh> mesh() const override {
        ++calls;
        return std::make_shared<const Mesh>(*m_mesh);
    }
    bool keepsMesh() const override { return false; }
    mutable std::atomic<int> calls{0};

private:
    std::shared_ptr<const Mesh> m_mesh;
};

struct NoRoom : std::runtime_error {
    NoRoom() : std::runtime_error("no room") {}
};

// Takes room from `budget`, dropping what `lazy` holds unpinned when it must, as the renderer does.
LazyTessellations::TakeRoom roomFrom(cache::MemoryBudget& budget, LazyTessellations& lazy) {
    return [&budget, &lazy](uint64_t bytes) {
        for (int attempt = 0; attempt < 2; ++attempt) {
            if (auto c = cache::MemoryCharge::tryCharge(budget, cache::MemoryCategory::Geometry, bytes)) return std::move(*c);
            if (!lazy.reclaim(bytes)) break;
        }
        throw NoRoom();
    };
}

bool sameTessellation(const geom::Tessellation& a, const geom::Tessellation& b) {
    return a.triangleCount() == b.triangleCount() && a.positions.size() == b.positions.size() &&
           std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(a.positions[0])) == 0 &&
           a.corners == b.corners && a.face == b.face && a.neighbors == b.neighbors;
}

TEST(LazyTessellation, InstancesShareOneTessellationMadeOnFirstNeed) {
    cache::MemoryBudget budget;
    LazyTessellations lazy(&budget);
    const auto h = GeometryHandle::fromMesh(sphere(24, 12), {}, nullptr, true);
    EXPECT_EQ(lazy.trianglesMade(), 0u);
    LazyTessellations::Pin a = lazy.acquire(*h, 0, roomFrom(budget, lazy));
    LazyTessellations::Pin b = lazy.acquire(*h, 0, roomFrom(budget, lazy));
    EXPECT_EQ(&*a, &*b);
    EXPECT_EQ(lazy.trianglesMade(), h->triangleCount());
    EXPECT_EQ(lazy.tessellationStats().made, 1u);
    EXPECT_EQ(lazy.tessellationStats().hits, 1u);
    EXPECT_EQ(budget.usedBytes(cache::MemoryCategory::Tessellation), a->bytes());
    EXPECT_EQ(budget.usedBytes(cache::MemoryCategory::Geometry), 0u) << "the making's room is given back";
}

// What making a handle's only piece charges while it is made.
uint64_t makingBytes(const GeometryHandle& h) { return transientBytes(h, 0) + h.pieceBytesEstimate(0); }

// Under a budget that holds what one making needs, the unpinned tessellation is dropped for the
// next and made again, the same numbers, when it is needed later.
TEST(LazyTessellation, DropsTheUnpinnedAndMakesThemAgainTheSame) {
    const auto h1 = GeometryHandle::fromMesh(sphere(40, 20), {}, nullptr, true);
    const auto h2 = GeometryHandle::fromMesh(sphere(40, 21), {}, nullptr, true);
    const uint64_t cap = std::max(makingBytes(*h1), makingBytes(*h2)) + 1024;
    cache::MemoryBudget budget(cap);
    {
        LazyTessellations lazy(&budget);
        std::optional<geom::Tessellation> first;
        {
            LazyTessellations::Pin p = lazy.acquire(*h1, 0, roomFrom(budget, lazy));
            ASSERT_GT(p->bytes(), 1024u);
            first = *p;
        }
        { LazyTessellations::Pin p = lazy.acquire(*h2, 0, roomFrom(budget, lazy)); }
        EXPECT_EQ(lazy.tessellationStats().evicted, 1u);
        LazyTessellations::Pin again = lazy.acquire(*h1, 0, roomFrom(budget, lazy));
        EXPECT_TRUE(sameTessellation(*again, *first));
        EXPECT_EQ(lazy.tessellationStats().recomputed, 1u);
        EXPECT_EQ(lazy.trianglesMade(), 2 * h1->triangleCount() + h2->triangleCount());
        EXPECT_LE(budget.peakBytes(), cap);
    }
    EXPECT_EQ(budget.usedBytes(), 0u);
}

// What a tile pins stays; a piece that cannot be made room for beside it is refused, and nothing
// of the refused making stays charged.
TEST(LazyTessellation, PinnedTessellationsStayAndARefusalLeavesNothingCharged) {
    const auto h1 = GeometryHandle::fromMesh(sphere(40, 20), {}, nullptr, true);
    const auto h2 = GeometryHandle::fromMesh(sphere(40, 21), {}, nullptr, true);
    cache::MemoryBudget budget(makingBytes(*h1) + 1024);
    LazyTessellations lazy(&budget);
    LazyTessellations::Pin held = lazy.acquire(*h1, 0, roomFrom(budget, lazy));
    ASSERT_GT(held->bytes() + makingBytes(*h2), budget.capBytes());
    const uint64_t before = budget.usedBytes();
    EXPECT_THROW((void)lazy.acquire(*h2, 0, roomFrom(budget, lazy)), NoRoom);
    EXPECT_EQ(budget.usedBytes(), before);
    EXPECT_EQ(held->triangleCount(), h1->triangleCount());
    EXPECT_EQ(lazy.tessellationStats().evicted, 0u);
}

// The pieces of a shape whose source keeps no mesh are made from one mesh, made once while it
// stays resident, and together they hold the shape's triangles.
TEST(LazyTessellation, PiecesOfAShapeShareOneMesh) {
    const auto mesh = sphere(32, 16);
    auto source = std::make_shared<CountingSource>(mesh);
    const auto h = GeometryHandle::fromMeshSource(source, *mesh, {}, nullptr, true, 64);
    ASSERT_GT(h->pieceCount(), 4u);
    ASSERT_FALSE(h->keepsSource());
    ASSERT_FALSE(h->makesPiecesAlone());
    const int callsBefore = source->calls;
    cache::MemoryBudget budget;
    LazyTessellations lazy(&budget);
    std::vector<LazyTessellations::Pin> pins;
    uint64_t triangles = 0;
    for (uint32_t k = 0; k < h->pieceCount(); ++k) {
        pins.push_back(lazy.acquire(*h, k, roomFrom(budget, lazy)));
        triangles += pins.back()->triangleCount();
    }
    EXPECT_EQ(source->calls - callsBefore, 1);
    EXPECT_EQ(lazy.meshStats().made, 1u);
    EXPECT_EQ(triangles, lazy.trianglesMade());
    EXPECT_LE(triangles, h->triangleCount());
    EXPECT_EQ(budget.usedBytes(cache::MemoryCategory::Geometry), h->meshBytes()) << "the shared mesh stays charged";
}

// Threads that need the same pieces together make each once.
TEST(LazyTessellation, ThreadsNeedingAPieceTogetherMakeItOnce) {
    const auto h = GeometryHandle::fromMesh(sphere(64, 32), {}, nullptr, true);
    cache::MemoryBudget budget;
    LazyTessellations lazy(&budget);
    std::vector<std::thread> threads;
    std::vector<const geom::Tessellation*> seen(4, nullptr);
    for (size_t t = 0; t < seen.size(); ++t)
        threads.emplace_back([&, t] {
            LazyTessellations::Pin p = lazy.acquire(*h, 0, roomFrom(budget, lazy));
            seen[t] = &*p;
        });
    for (std::thread& th : threads) th.join();
    for (const geom::Tessellation* s : seen) EXPECT_EQ(s, seen[0]);
    EXPECT_EQ(lazy.tessellationStats().made, 1u);
    EXPECT_EQ(lazy.trianglesMade(), h->triangleCount());
}

}  // namespace
}  // namespace pushpin::render
