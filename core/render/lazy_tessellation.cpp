#include "core/render/lazy_tessellation.h"

#include <utility>

namespace pushpin::render {

uint64_t transientBytes(const geom::GeometryHandle& h, size_t piece) {
    return (h.keepsSource() || h.makesPiecesAlone() ? 0 : h.meshMakingBytes()) + h.pieceWorkBytesEstimate(piece);
}

LazyTessellations::Pin LazyTessellations::acquire(const geom::GeometryHandle& handle, uint32_t piece,
                                                  const TakeRoom& takeRoom) {
    std::optional<Pin> pin = m_tessellations.tryAcquire(
        PieceKey{&handle, piece},
        [&] {
            // A shape in pieces that does not keep its mesh has it made once for the pieces made
            // while it stays resident.
            const bool shareMesh = handle.pieceCount() > 1 && !handle.keepsSource() && !handle.makesPiecesAlone();
            std::optional<MeshCache::Pin> mesh;
            if (shareMesh) {
                mesh = m_meshes.tryAcquire(
                    handle.sourceId(),
                    [&] {
                        const cache::MemoryCharge room = takeRoom(handle.meshMakingBytes());
                        return handle.makeMesh();
                    },
                    [&](const std::shared_ptr<const geom::Mesh>&) { return handle.meshBytes(); });
                if (!mesh) throw TessellationDoesNotFit{handle.meshBytes()};
            }
            // While it is made, a tessellation needs its shape's mesh (evaluated again when not
            // kept or shared), its working memory and itself: room for them is taken first.
            const uint64_t making =
                (shareMesh ? handle.pieceWorkBytesEstimate(piece) : transientBytes(handle, piece)) + handle.pieceBytesEstimate(piece);
            const cache::MemoryCharge room = takeRoom(making);
            geom::Tessellation t = shareMesh ? handle.tessellatePiece(piece, ***mesh) : handle.tessellatePiece(piece);
            m_trianglesMade.fetch_add(t.triangleCount(), std::memory_order_relaxed);
            m_transientFreed.fetch_add(making, std::memory_order_relaxed);
            return t;
        },
        [](const geom::Tessellation& t) { return t.bytes(); });
    if (!pin) throw TessellationDoesNotFit{handle.pieceBytesEstimate(piece)};
    return std::move(*pin);
}

}  // namespace pushpin::render
