// core/geom/nurbs_pieces.h: the uniform grid a NURBS surface is tessellated on (reference/
// algorithms.md §8, primary pass), any rectangle of its cells tessellated on its own, and a large
// surface cut into such rectangles (pieces) so that a tile needs the triangles of only the pieces
// it sees (DESIGN.md steps 2 and 6a), as mesh_pieces.h does for meshes.
//
// The grid: divU × divV steps in every non-empty span, point (i, j) at parameters (us[i], vs[j]),
// cell (i, j) between points (i, j) and (i + 1, j + 1). Cell (i, j) splits into two triangles
// with the ids ("slots") 2·(i·cellsV + j) and 2·(i·cellsV + j) + 1, whichever part of the grid is
// made; a triangle of zero area (at a pole) keeps its slot as a triangle whose three corners are
// one vertex, which rasterizes to nothing and has no neighbours.
// Point identities for adjacency: where a closed direction's first and last rows (columns) meet,
// their points are welded, and a boundary row (column) whose points all coincide (a pole) is
// welded into one point. Both are found from the boundary rows and columns alone, so the grid is
// known without evaluating its inside. Lengths are compared at 1e-6 of the control hull's size.
// A rectangle's tessellation is the whole grid's cut to its cells, bit for bit: the same corner
// positions, normals and uvs, and the same neighbours (by slot) across its borders, because it is
// made with the cells around it. A grid normal that vanishes takes the nearest non-vanishing one,
// ring by ring (three at most, then +Z), of the normals the surface gives at the grid points.
// Thread safety: a NurbsGrid and NurbsPieces are immutable; the functions are pure.
// Memory: a grid holds its parameters (8 bytes a row and a column) and its welds; NurbsPieces about
// 60 bytes a piece and 24 bytes a run (a band of whole rows is one run, a rectangle one a row).
#pragma once

#include "core/geom/bounds.h"
#include "core/geom/nurbs.h"
#include "core/geom/slot_run.h"
#include "core/geom/tessellation.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace pushpin::geom {

// Cells [i0, i1) × [j0, j1) of a grid.
struct NurbsCells {
    uint32_t i0 = 0, i1 = 0, j0 = 0, j1 = 0;
    uint64_t count() const { return uint64_t(i1 - i0) * uint64_t(j1 - j0); }
};

struct NurbsGrid {
    std::vector<double> us, vs;               // parameters of the point rows and columns
    std::vector<uint32_t> spanOfU, spanOfV;   // per cell row (column): its span, counted from 0
    uint32_t spansV = 0;                      // non-empty spans in V: cell (i, j)'s patch is spanOfU[i]·spansV + spanOfV[j]
    double tolerance = 0;                     // points this close are one point
    double minArea2 = 0;                      // a triangle whose doubled area squared is not above this has zero area
    std::vector<std::pair<uint32_t, uint32_t>> welds;  // (point, the lowest point it is welded to), by point

    size_t pointRows() const { return us.size(); }
    size_t pointColumns() const { return vs.size(); }
    size_t cellRows() const { return us.size() - 1; }
    size_t cellColumns() const { return vs.size() - 1; }
    uint64_t cellCount() const { return uint64_t(cellRows()) * uint64_t(cellColumns()); }
    uint32_t point(size_t i, size_t j) const { return uint32_t(i * vs.size() + j); }
    // The point a grid point is one with (itself when it is welded to no lower one).
    uint32_t root(uint32_t point) const;
    uint32_t slot(size_t i, size_t j) const { return uint32_t(2 * (i * cellColumns() + j)); }
    // Every cell of the grid.
    NurbsCells allCells() const { return {0, uint32_t(cellRows()), 0, uint32_t(cellColumns())}; }
};

// The grid of `s` with `divU` × `divV` steps per span (at least 1). nullopt with `problem` set
// when the domain is empty or the boundary evaluates to NaN/Inf.
std::optional<NurbsGrid> makeNurbsGrid(const NurbsSurface& s, int divU, int divV, std::string& problem);
// The same in two steps: the parameters, tolerances and spans alone (no evaluation: what cutting
// the grid into pieces needs), then the welds, from the boundary rows and columns evaluated
// (false with `problem` set when they evaluate to NaN/Inf).
std::optional<NurbsGrid> nurbsGridParameters(const NurbsSurface& s, int divU, int divV, std::string& problem);
bool weldNurbsGrid(const NurbsSurface& s, NurbsGrid& g, std::string& problem);

// The triangles of `cells`, two per cell in slot order (triangle 2·((i − i0)·(j1 − j0) + j − j0)
// + h is slot g.slot(i, j) + h), vertices numbered in order of first use, face = the cell's patch,
// material 0, neighbours as slots. nullopt with `problem` set when the surface evaluates to
// NaN/Inf at a point it needs.
std::optional<Tessellation> tessellateNurbsCells(const NurbsSurface& s, const NurbsGrid& g, const NurbsCells& cells,
                                                 std::string& problem);

// Grid points a rectangle of `cells` evaluates (its own and those of the cells around it) and
// the triangles it looks at for adjacency, for estimating its working memory.
struct NurbsCellsWork {
    uint64_t points = 0, triangles = 0;
};
NurbsCellsWork nurbsCellsWork(const NurbsGrid& g, const NurbsCells& cells);

class NurbsPieces {
public:
    struct Piece {
        NurbsCells cells;
        Bounds3 bounds;  // of the control points that shape its cells (the cells lie in their hull)
        uint32_t runBegin = 0, runEnd = 0;  // its runs in pieceRuns(), one a row of cells
    };
    // The grid cut into pieces of at most `pieceTriangles` / 2 cells (pieceTriangles ≥ 2): bands of
    // whole rows of cells while a row fits (one run of slots each), otherwise rectangles as close
    // to square in cells as the grid allows, in rows of rectangles.
    static NurbsPieces split(const NurbsSurface& s, const NurbsGrid& g, uint32_t pieceTriangles);

    const std::vector<Piece>& pieces() const { return m_pieces; }
    // Every run of slots, by firstSlot, and the runs of piece k in the order of its tessellation.
    const std::vector<SlotRun>& slotRuns() const { return m_runs; }
    std::span<const SlotRun> pieceSlotRuns(size_t k) const {
        return {m_pieceRuns.data() + m_pieces[k].runBegin, m_pieces[k].runEnd - m_pieces[k].runBegin};
    }
    uint64_t bytes() const;

private:
    std::vector<Piece> m_pieces;
    std::vector<SlotRun> m_runs, m_pieceRuns;
};

}  // namespace pushpin::geom
