#include "core/render/lazy_tessellation.h"

#include <utility>

namespace pushpin::render {

uint64_t transientBytes(const geom::GeometryHandle& h, size_t piece) {
    return (h.keepsSource() || h.makesPiecesAlone() ? 0 : h.meshMakingBytes()) + h.pieceWorkBytesEstimate(piece);
}

LazyTessellations::Pin LazyTessellations::acquire(const geom::GeometryHandle& handle, uint32_t piece,
                                                  const TakeRoom& takeRoom) {
    const PieceKey key{&handle, piece};
    if (std::optional<Pin> resident = m_tessellations.tryPin(key)) return std::move(*resident);
    // Room is taken before a value is claimed for making, so that a caller whose takeRoom waits
    // for other threads to give memory back never holds a making they may be waiting for.
    // A shape in pieces that does not keep its mesh has it made once for the pieces made while it
    // stays resident.
    const bool shareMesh = handle.pieceCount() > 1 && !handle.keepsSource() && !handle.makesPiecesAlone();
    std::optional<MeshCache::Pin> mesh;
    if (shareMesh) {
        mesh = m_meshes.tryPin(handle.sourceId());
        if (!mesh) {
            cache::MemoryCharge room = takeRoom(handle.meshMakingBytes());
            mesh = m_meshes.tryAcquire(
                handle.sourceId(),
                [&] {
                    std::shared_ptr<const geom::Mesh> made = handle.makeMesh();
                    room.reset();  // the mesh itself is charged next
                    return made;
                },
                [&](const std::shared_ptr<const geom::Mesh>&) { return handle.meshBytes(); });
            if (!mesh) throw TessellationDoesNotFit{handle.meshBytes()};
        }
    }
    // While it is made, a tessellation needs its shape's mesh (evaluated again when not kept or
    // shared), its working memory and itself: room for them is taken first.
    const uint64_t making =
        (shareMesh ? handle.pieceWorkBytesEstimate(piece) : transientBytes(handle, piece)) + handle.pieceBytesEstimate(piece);
    cache::MemoryCharge room = takeRoom(making);
    std::optional<Pin> pin = m_tessellations.tryAcquire(
        key,
        [&] {
            geom::Tessellation t = shareMesh ? handle.tessellatePiece(piece, ***mesh) : handle.tessellatePiece(piece);
            room.reset();  // the tessellation itself is charged next
            m_trianglesMade.fetch_add(t.triangleCount(), std::memory_order_relaxed);
            m_transientFreed.fetch_add(making, std::memory_order_relaxed);
            return t;
        },
        [](const geom::Tessellation& t) { return t.bytes(); });
    if (!pin) throw TessellationDoesNotFit{handle.pieceBytesEstimate(piece)};
    return std::move(*pin);
}

}  // namespace pushpin::render
