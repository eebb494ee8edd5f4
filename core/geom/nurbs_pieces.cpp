#include "core/geom/nurbs_pieces.h"

#include "core/geom/finite.h"
#include "core/geom/union_find.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace pushpin::geom {

namespace {

constexpr uint32_t kNone = 0xffffffffu;
// How far from a grid point whose normal vanishes its stand-in is looked for, in rings of points
// (beyond that it takes +Z: a surface degenerate over so wide a region has no normal to borrow).
constexpr size_t kNormalRings = 3;

// The distinct knots inside [lo, hi], with lo and hi themselves: the span boundaries of a direction.
std::vector<double> spanBreaks(const std::vector<double>& knots, double lo, double hi) {
    std::vector<double> breaks;
    for (double k : knots)
        if (k >= lo && k <= hi && (breaks.empty() || k > breaks.back())) breaks.push_back(k);
    if (breaks.empty() || breaks.front() > lo) breaks.insert(breaks.begin(), lo);
    if (breaks.back() < hi) breaks.push_back(hi);
    return breaks;
}

// Grid parameters: `divisions` steps in every non-empty span; `span` receives each step's span.
std::vector<double> gridParameters(const std::vector<double>& breaks, int divisions, std::vector<uint32_t>& span) {
    std::vector<double> params;
    span.clear();
    for (size_t s = 0; s + 1 < breaks.size(); ++s) {
        for (int d = 0; d < divisions; ++d) {
            params.push_back(breaks[s] + (breaks[s + 1] - breaks[s]) * double(d) / double(divisions));
            span.push_back(uint32_t(s));
        }
    }
    params.push_back(breaks.back());
    return params;
}

// Sorted, distinct cell indices around [a, b) of n: one more on each side, and the far end's
// across the wrap (which only matters where a seam is welded, and costs one row where none is).
std::vector<uint32_t> cellsAround(uint32_t a, uint32_t b, uint32_t n) {
    std::vector<uint32_t> out;
    out.reserve(b - a + 4);
    if (a == 0 && b < n) out.push_back(n - 1);
    if (a > 0) out.push_back(a - 1);
    for (uint32_t k = a; k < b; ++k) out.push_back(k);
    if (b < n) out.push_back(b);
    if (b == n && a > 0) out.push_back(0);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

// The point rows (columns) the cells `cells` use: each cell's and the next.
std::vector<uint32_t> pointsOfCells(const std::vector<uint32_t>& cells) {
    std::vector<uint32_t> out;
    out.reserve(2 * cells.size());
    for (uint32_t c : cells) {
        out.push_back(c);
        out.push_back(c + 1);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

// The triangle halves of a cell: (i, j)–(i+1, j+1) splits into (a, b, c) and (a, c, d),
// counter-clockwise in (u, v), so their geometric normal is dP/du × dP/dv, the surface normal.
constexpr int kQuad[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
constexpr int kHalves[2][3] = {{0, 1, 2}, {0, 2, 3}};

// The grid point of corner k of half h of cell (i, j).
struct GridPoint {
    size_t i, j;
};
GridPoint cornerOf(size_t i, size_t j, int h, int k) {
    const int q = kHalves[h][k];
    return {i + size_t(kQuad[q][0]), j + size_t(kQuad[q][1])};
}

}  // namespace

uint32_t NurbsGrid::root(uint32_t p) const {
    const auto it = std::lower_bound(welds.begin(), welds.end(), std::pair<uint32_t, uint32_t>(p, 0u));
    return it != welds.end() && it->first == p ? it->second : p;
}

std::optional<NurbsGrid> makeNurbsGrid(const NurbsSurface& s, int divU, int divV, std::string& problem) {
    std::optional<NurbsGrid> g = nurbsGridParameters(s, divU, divV, problem);
    if (g && !weldNurbsGrid(s, *g, problem)) return std::nullopt;
    return g;
}

std::optional<NurbsGrid> nurbsGridParameters(const NurbsSurface& s, int divU, int divV, std::string& problem) {
    NurbsGrid g;
    const std::vector<double> breaksU = spanBreaks(s.knotsU(), s.uMin(), s.uMax());
    const std::vector<double> breaksV = spanBreaks(s.knotsV(), s.vMin(), s.vMax());
    g.us = gridParameters(breaksU, std::max(divU, 1), g.spanOfU);
    g.vs = gridParameters(breaksV, std::max(divV, 1), g.spanOfV);
    g.spansV = uint32_t(breaksV.size() - 1);
    const size_t nu = g.us.size(), nv = g.vs.size();
    if (nu < 2 || nv < 2) {
        problem = "the surface has an empty parameter domain";
        return std::nullopt;
    }
    const Bounds3 hull = s.bounds();
    const double size = std::max({hull.size().x, hull.size().y, hull.size().z, 1e-30});
    g.tolerance = 1e-6 * size;
    g.minArea2 = 1e-24 * std::pow(size, 4.0);
    return g;
}

bool weldNurbsGrid(const NurbsSurface& s, NurbsGrid& g, std::string& problem) {
    const size_t nu = g.us.size(), nv = g.vs.size();
    g.welds.clear();
    // The boundary points, each once, and their positions.
    std::vector<uint32_t> boundary;
    boundary.reserve(2 * (nu + nv));
    for (size_t j = 0; j < nv; ++j) boundary.push_back(g.point(0, j)), boundary.push_back(g.point(nu - 1, j));
    for (size_t i = 0; i < nu; ++i) boundary.push_back(g.point(i, 0)), boundary.push_back(g.point(i, nv - 1));
    std::sort(boundary.begin(), boundary.end());
    boundary.erase(std::unique(boundary.begin(), boundary.end()), boundary.end());
    std::vector<glm::dvec3> pos(boundary.size());
    for (size_t k = 0; k < boundary.size(); ++k) {
        pos[k] = s.point(g.us[boundary[k] / nv], g.vs[boundary[k] % nv]);
        if (!isFinite(pos[k])) {
            problem = "the surface evaluates to NaN/Inf";
            return false;
        }
    }
    auto at = [&](size_t i, size_t j) {
        return size_t(std::lower_bound(boundary.begin(), boundary.end(), g.point(i, j)) - boundary.begin());
    };
    // Sets of boundary points; each group's root is its lowest point.
    LowestRootSets sets(boundary.size());
    auto close = [&](size_t a, size_t b) { return glm::length(pos[a] - pos[b]) <= g.tolerance; };
    auto weld = [&](size_t a, size_t b) { sets.join(uint32_t(a), uint32_t(b)); };
    for (size_t j = 0; j < nv; ++j)
        if (close(at(0, j), at(nu - 1, j))) weld(at(0, j), at(nu - 1, j));
    for (size_t i = 0; i < nu; ++i)
        if (close(at(i, 0), at(i, nv - 1))) weld(at(i, 0), at(i, nv - 1));
    for (size_t i : {size_t(0), nu - 1}) {
        bool collapsed = true;
        for (size_t j = 1; j < nv && collapsed; ++j) collapsed = close(at(i, 0), at(i, j));
        if (collapsed)
            for (size_t j = 1; j < nv; ++j) weld(at(i, 0), at(i, j));
    }
    for (size_t j : {size_t(0), nv - 1}) {
        bool collapsed = true;
        for (size_t i = 1; i < nu && collapsed; ++i) collapsed = close(at(0, j), at(i, j));
        if (collapsed)
            for (size_t i = 1; i < nu; ++i) weld(at(0, j), at(i, j));
    }
    // Boundary positions are sorted by point, so the lowest index of a group is its lowest point.
    for (size_t k = 0; k < boundary.size(); ++k)
        if (const uint32_t r = sets.find(uint32_t(k)); r != k) g.welds.emplace_back(boundary[k], boundary[r]);
    return true;
}

NurbsCellsWork nurbsCellsWork(const NurbsGrid& g, const NurbsCells& c) {
    const uint64_t rows = std::min<uint64_t>(c.i1 - c.i0 + 3, g.cellRows()) + 1;
    const uint64_t cols = std::min<uint64_t>(c.j1 - c.j0 + 3, g.cellColumns()) + 1;
    return {rows * cols, 2 * (rows - 1) * (cols - 1)};
}

std::optional<Tessellation> tessellateNurbsCells(const NurbsSurface& s, const NurbsGrid& g, const NurbsCells& c,
                                                 std::string& problem) {
    const uint32_t cellRows = uint32_t(g.cellRows()), cellCols = uint32_t(g.cellColumns());
    // The cells whose triangles may share an edge with these (welds join only boundary rows and
    // columns, and the rows and columns next to them), and the points they use.
    const std::vector<uint32_t> rowCells = cellsAround(c.i0, c.i1, cellRows);
    const std::vector<uint32_t> colCells = cellsAround(c.j0, c.j1, cellCols);
    const std::vector<uint32_t> rows = pointsOfCells(rowCells), cols = pointsOfCells(colCells);
    std::vector<uint32_t> rowAt(g.pointRows(), kNone), colAt(g.pointColumns(), kNone);
    for (size_t k = 0; k < rows.size(); ++k) rowAt[rows[k]] = uint32_t(k);
    for (size_t k = 0; k < cols.size(); ++k) colAt[cols[k]] = uint32_t(k);
    const size_t width = cols.size();
    std::vector<glm::dvec3> pos(rows.size() * width);
    for (size_t a = 0; a < rows.size(); ++a)
        for (size_t b = 0; b < width; ++b) {
            pos[a * width + b] = s.point(g.us[rows[a]], g.vs[cols[b]]);
            if (!isFinite(pos[a * width + b])) {
                problem = "the surface evaluates to NaN/Inf";
                return std::nullopt;
            }
        }
    auto position = [&](GridPoint p) -> const glm::dvec3& { return pos[rowAt[p.i] * width + colAt[p.j]]; };

    // Normals of the cells' own points; a vanishing one takes the nearest non-vanishing normal of
    // the grid, ring by ring up to kNormalRings (evaluated where it lies outside these points).
    const size_t pointsU = c.i1 - c.i0 + 1, pointsV = c.j1 - c.j0 + 1;
    std::vector<glm::dvec3> nrm(pointsU * pointsV);
    for (size_t a = 0; a < pointsU; ++a)
        for (size_t b = 0; b < pointsV; ++b) {
            nrm[a * pointsV + b] = s.normal(g.us[c.i0 + a], g.vs[c.j0 + b]);
            if (!isFinite(nrm[a * pointsV + b])) {
                problem = "the surface evaluates to NaN/Inf";
                return std::nullopt;
            }
        }
    auto gridNormal = [&](size_t i, size_t j) {
        if (i >= c.i0 && i <= c.i1 && j >= c.j0 && j <= c.j1) return nrm[(i - c.i0) * pointsV + (j - c.j0)];
        const glm::dvec3 n = s.normal(g.us[i], g.vs[j]);
        return isFinite(n) ? n : glm::dvec3(0.0);
    };
    std::vector<glm::dvec3> shading(nrm.size());
    const size_t nu = g.pointRows(), nv = g.pointColumns();
    for (size_t a = 0; a < pointsU; ++a)
        for (size_t b = 0; b < pointsV; ++b) {
            glm::dvec3 n = nrm[a * pointsV + b];
            const size_t i = c.i0 + a, j = c.j0 + b;
            bool found = glm::dot(n, n) > 0.0;
            for (size_t r = 1; r <= kNormalRings && !found; ++r)
                for (size_t x = (i >= r ? i - r : 0); x <= std::min(nu - 1, i + r) && !found; ++x)
                    for (size_t y = (j >= r ? j - r : 0); y <= std::min(nv - 1, j + r) && !found; ++y) {
                        const glm::dvec3 q = gridNormal(x, y);
                        if (glm::dot(q, q) > 0.0) {
                            n = q;
                            found = true;
                        }
                    }
            shading[a * pointsV + b] = found ? glm::normalize(n) : glm::dvec3(0, 0, 1);
        }

    const double du = s.uMax() - s.uMin(), dv = s.vMax() - s.vMin();
    // Which halves of the cells looked at have zero area (bit h of the cell's entry).
    std::vector<uint32_t> cellRowAt(cellRows, kNone), cellColAt(cellCols, kNone);
    for (size_t k = 0; k < rowCells.size(); ++k) cellRowAt[rowCells[k]] = uint32_t(k);
    for (size_t k = 0; k < colCells.size(); ++k) cellColAt[colCells[k]] = uint32_t(k);
    std::vector<uint8_t> flat(rowCells.size() * colCells.size(), 0);
    for (size_t a = 0; a < rowCells.size(); ++a)
        for (size_t b = 0; b < colCells.size(); ++b)
            for (int h = 0; h < 2; ++h) {
                const size_t i = rowCells[a], j = colCells[b];
                const glm::dvec3& p0 = position(cornerOf(i, j, h, 0));
                const glm::dvec3& p1 = position(cornerOf(i, j, h, 1));
                const glm::dvec3& p2 = position(cornerOf(i, j, h, 2));
                const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
                if (!(glm::dot(n, n) > g.minArea2)) flat[a * colCells.size() + b] |= uint8_t(1u << h);
            }
    auto zeroArea = [&](size_t i, size_t j, int h) {
        return (flat[cellRowAt[i] * colCells.size() + cellColAt[j]] >> h) & 1u;
    };

    Tessellation out;
    const uint64_t triangles = 2 * c.count();
    out.corners.reserve(3 * triangles);
    out.face.reserve(triangles);
    out.material.reserve(triangles);
    std::vector<uint32_t> vertexOf(pointsU * pointsV, kNone);
    auto vertex = [&](GridPoint p) {
        const size_t k = (p.i - c.i0) * pointsV + (p.j - c.j0);
        if (vertexOf[k] == kNone) {
            vertexOf[k] = uint32_t(out.positions.size());
            out.positions.push_back(glm::vec3(position(p)));
            out.normals.push_back(glm::vec3(shading[k]));
            out.uvs.push_back(glm::vec2(float((g.us[p.i] - s.uMin()) / du), float((g.vs[p.j] - s.vMin()) / dv)));
        }
        return vertexOf[k];
    };
    for (uint32_t i = c.i0; i < c.i1; ++i)
        for (uint32_t j = c.j0; j < c.j1; ++j)
            for (int h = 0; h < 2; ++h) {
                if (zeroArea(i, j, h)) {
                    const uint32_t v = vertex(cornerOf(i, j, h, 0));
                    out.corners.insert(out.corners.end(), {v, v, v});
                } else {
                    for (int k = 0; k < 3; ++k) out.corners.push_back(vertex(cornerOf(i, j, h, k)));
                }
                out.face.push_back(g.spanOfU[i] * g.spansV + g.spanOfV[j]);
                out.material.push_back(0);
            }
    out.positions.shrink_to_fit();
    out.normals.shrink_to_fit();
    out.uvs.shrink_to_fit();
    computeTessellationBounds(out);

    // Adjacency among the triangles of nonzero area of these cells and the cells around them, on
    // welded point identities (renumbered densely); then the cells' own triangles take theirs.
    // A point is numbered by its place among the evaluated ones; a welded boundary point by its
    // root's, or after them when the root lies outside (a pole's first point, say).
    std::vector<uint32_t> outside;
    for (const auto& [point, root] : g.welds)
        if (rowAt[root / nv] == kNone || colAt[root % nv] == kNone) outside.push_back(root);
    std::sort(outside.begin(), outside.end());
    outside.erase(std::unique(outside.begin(), outside.end()), outside.end());
    auto pointId = [&](GridPoint p) {
        size_t i = p.i, j = p.j;
        if (i == 0 || i + 1 == nu || j == 0 || j + 1 == nv) {
            const uint32_t r = g.root(g.point(i, j));
            i = r / nv, j = r % nv;
            if (rowAt[i] == kNone || colAt[j] == kNone)
                return uint32_t(pos.size() + size_t(std::lower_bound(outside.begin(), outside.end(), r) - outside.begin()));
        }
        return uint32_t(rowAt[i] * width + colAt[j]);
    };
    Tessellation around;
    std::vector<uint32_t> slots, cornerPoint;
    slots.reserve(2 * rowCells.size() * colCells.size());
    cornerPoint.reserve(6 * rowCells.size() * colCells.size());
    for (uint32_t i : rowCells)
        for (uint32_t j : colCells)
            for (int h = 0; h < 2; ++h) {
                if (zeroArea(i, j, h)) continue;
                slots.push_back(g.slot(i, j) + uint32_t(h));
                for (int k = 0; k < 3; ++k) cornerPoint.push_back(pointId(cornerOf(i, j, h, k)));
            }
    around.face.resize(slots.size());
    buildTriangleNeighbors(around, cornerPoint);
    out.neighbors.assign(3 * triangles, kNoNeighbor);
    for (size_t t = 0; t < slots.size(); ++t) {
        const uint32_t cell = slots[t] / 2, i = cell / cellCols, j = cell % cellCols;
        if (i < c.i0 || i >= c.i1 || j < c.j0 || j >= c.j1) continue;
        const size_t local = 2 * (size_t(i - c.i0) * (c.j1 - c.j0) + (j - c.j0)) + slots[t] % 2;
        for (int k = 0; k < 3; ++k) {
            const uint32_t n = around.neighbors[3 * t + size_t(k)];
            out.neighbors[3 * local + size_t(k)] = n == kNoNeighbor ? kNoNeighbor : slots[n];
        }
    }
    return out;
}

NurbsPieces NurbsPieces::split(const NurbsSurface& s, const NurbsGrid& g, uint32_t pieceTriangles) {
    NurbsPieces out;
    const uint64_t rows = g.cellRows(), cols = g.cellColumns();
    const uint64_t maxCells = std::max<uint64_t>(pieceTriangles / 2, 1);
    // Bands of cell rows and columns: as many as the size needs, split in proportion to the grid's
    // sides so that pieces are about square in cells, then more until every piece fits.
    // While a whole row of cells fits in a piece, pieces are bands of whole rows, each one run of
    // slots (nothing to store a row); otherwise rectangles, a run a row.
    const uint64_t wanted = (g.cellCount() + maxCells - 1) / maxCells;
    uint64_t bu = cols <= maxCells ? std::min(wanted, rows)
                                   : std::clamp<uint64_t>(uint64_t(std::lround(std::sqrt(double(wanted) * double(rows) / double(cols)))), 1, rows);
    uint64_t bv = std::clamp<uint64_t>((wanted + bu - 1) / bu, 1, cols);
    auto ceilDiv = [](uint64_t a, uint64_t b) { return (a + b - 1) / b; };
    while (ceilDiv(rows, bu) * ceilDiv(cols, bv) > maxCells) {
        if ((ceilDiv(rows, bu) >= ceilDiv(cols, bv) && bu < rows) || bv == cols) ++bu;
        else ++bv;
        if (bu == rows && bv == cols) break;
    }
    auto edge = [](uint64_t k, uint64_t bands, uint64_t n) { return uint32_t(k * n / bands); };
    for (uint64_t a = 0; a < bu; ++a)
        for (uint64_t b = 0; b < bv; ++b) {
            Piece p;
            p.cells = {edge(a, bu, rows), edge(a + 1, bu, rows), edge(b, bv, cols), edge(b + 1, bv, cols)};
            // The control points whose basis functions reach the cells' parameters.
            const int su0 = findKnotSpan(s.degreeU(), s.knotsU(), s.cvCountU(), g.us[p.cells.i0]);
            const int su1 = findKnotSpan(s.degreeU(), s.knotsU(), s.cvCountU(), g.us[p.cells.i1]);
            const int sv0 = findKnotSpan(s.degreeV(), s.knotsV(), s.cvCountV(), g.vs[p.cells.j0]);
            const int sv1 = findKnotSpan(s.degreeV(), s.knotsV(), s.cvCountV(), g.vs[p.cells.j1]);
            for (int i = std::max(su0 - s.degreeU(), 0); i <= std::min(su1, s.cvCountU() - 1); ++i)
                for (int j = std::max(sv0 - s.degreeV(), 0); j <= std::min(sv1, s.cvCountV() - 1); ++j)
                    p.bounds.extend(s.cvPoint(i, j));
            p.runBegin = uint32_t(out.m_pieceRuns.size());
            const bool wholeRows = p.cells.j0 == 0 && p.cells.j1 == cols;
            for (uint32_t i = p.cells.i0; i < (wholeRows ? p.cells.i0 + 1 : p.cells.i1); ++i)
                out.m_pieceRuns.push_back(
                    {g.slot(i, p.cells.j0), uint32_t(out.m_pieces.size()), 2 * (i - p.cells.i0) * (p.cells.j1 - p.cells.j0)});
            p.runEnd = uint32_t(out.m_pieceRuns.size());
            out.m_pieces.push_back(p);
        }
    out.m_runs = out.m_pieceRuns;
    std::sort(out.m_runs.begin(), out.m_runs.end(),
              [](const SlotRun& x, const SlotRun& y) { return x.firstSlot < y.firstSlot; });
    return out;
}

uint64_t NurbsPieces::bytes() const {
    return uint64_t(m_pieces.capacity()) * sizeof(Piece) + uint64_t(m_runs.capacity() + m_pieceRuns.capacity()) * sizeof(SlotRun);
}

uint64_t nurbsTriangleCount(const NurbsSurface& s, int divU, int divV) {
    const uint64_t spansU = spanBreaks(s.knotsU(), s.uMin(), s.uMax()).size() - 1;
    const uint64_t spansV = spanBreaks(s.knotsV(), s.vMin(), s.vMax()).size() - 1;
    return 2 * spansU * uint64_t(std::max(divU, 1)) * spansV * uint64_t(std::max(divV, 1));
}

std::optional<Tessellation> tessellateNurbs(const NurbsSurface& s, int divU, int divV, std::string& problem) {
    const std::optional<NurbsGrid> g = makeNurbsGrid(s, divU, divV, problem);
    if (!g) return std::nullopt;
    return tessellateNurbsCells(s, *g, g->allCells(), problem);
}

}  // namespace pushpin::geom
