// tests/support/stored_grid.h: a polygon grid stored in Maya ASCII as Maya writes a mesh without
// history (.vt, .ed, .fc, uv sets, normals), for tests of stored-mesh decoding and rendering.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

namespace pushpin::test {

// The transform `name` and its mesh `name`Shape: an nx × ny quad grid of 0.1-unit cells in the
// XZ plane (rows towards -Z, a small bump in Y), its edges listed as Maya lists a plane's (the
// rows of edges, then the columns, so a run of faces uses edges far apart in the list), a few
// hard; two uv sets, the current one ("cur") on every face but the first row, the other ("map1")
// on the first three faces; stored normals for every face-vertex (some "not set"); face records
// in runs of 100 (`gap`: the third run left out); and a last face with a hole, away from the grid.
// `extra` is one setAttr's arguments for the shape (a plug and its value, then ';');
// `transformLines` follow the transform's createNode.
inline std::string storedGridMesh(const std::string& name, int nx, int ny, std::string_view extra, bool gap = false,
                                  std::string_view transformLines = {}) {
    const int vx = nx + 1;
    const int gridPoints = vx * (ny + 1), rowEdges = nx * (ny + 1), edges = rowEdges + vx * ny;
    auto n = [](double v) { return " " + std::to_string(v); };
    auto i32 = [](long long v) { return " " + std::to_string(v); };
    auto vid = [&](int i, int j) { return j * vx + i; };
    std::string t = "createNode transform -n \"" + name + "\";\n" + std::string(transformLines) + "createNode mesh -n \"" +
                    name + "Shape\" -p \"" + name + "\";\n";
    t += "\tsetAttr \".uvst[0].uvsn\" -type \"string\" \"map1\";\n";
    t += "\tsetAttr -s 8 \".uvst[0].uvsp[0:7]\" -type \"float2\" 0 0 1 0 1 1 0 1 0.5 0 0.5 1 0.25 0.25 0.75 0.75;\n";
    t += "\tsetAttr \".uvst[1].uvsn\" -type \"string\" \"cur\";\n";
    t += "\tsetAttr -s" + i32(gridPoints) + " \".uvst[1].uvsp[0:" + std::to_string(gridPoints - 1) + "]\" -type \"float2\"";
    for (int p = 0; p < gridPoints; ++p) t += n((p % vx) / double(nx)) + n((p / vx) / double(ny));
    t += ";\n\tsetAttr \".cuvs\" -type \"string\" \"cur\";\n";
    t += "\tsetAttr " + std::string(extra) + "\n";
    const int points = gridPoints + 8;
    t += "\tsetAttr -s" + i32(points) + " \".vt[0:" + std::to_string(points - 1) + "]\"";
    for (int p = 0; p < gridPoints; ++p) t += n(p % vx * 0.1) + n(std::sin(p * 0.37) * 0.05) + n(p / vx * -0.1);
    for (double v : {5.0, 6.0, 6.0, 5.0}) t += n(v) + " 1" + n(v == 5.0 ? 0.0 : 1.0);
    for (double v : {5.25, 5.75, 5.75, 5.25}) t += n(v) + " 1" + n(v == 5.25 ? 0.25 : 0.75);
    t += ";\n";
    t += "\tsetAttr -s" + i32(edges + 8) + " \".ed[0:" + std::to_string(edges + 7) + "]\"";
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i < nx; ++i) t += i32(vid(i, j)) + i32(vid(i + 1, j)) + ((i + j) % 7 == 0 ? " 0" : " 1");
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i <= nx; ++i) t += i32(vid(i, j)) + i32(vid(i, j + 1)) + ((i * j) % 5 == 1 ? " 0" : " 1");
    for (int k = 0; k < 4; ++k) t += i32(gridPoints + k) + i32(gridPoints + (k + 1) % 4) + " 0";
    for (int k = 0; k < 4; ++k) t += i32(gridPoints + 4 + k) + i32(gridPoints + 4 + (k + 1) % 4) + " 1";
    t += ";\n";
    const int faces = nx * ny + 1, faceVertices = 4 * nx * ny + 8;
    t += "\tsetAttr -s" + i32(faceVertices) + " \".n[0:" + std::to_string(faceVertices - 1) + "]\" -type \"float3\"";
    for (int c = 0; c < faceVertices; ++c)
        t += c % 11 == 3 ? " 1e+20 1e+20 1e+20" : n(std::sin(c * 0.1) * 0.2) + " 1" + n(std::cos(c * 0.3) * 0.2);
    t += ";\n";
    for (int first = 0; first < faces; first += 100) {
        if (gap && first == 200) continue;
        const int last = std::min(faces, first + 100) - 1;
        t += "\tsetAttr \".fc[" + std::to_string(first) + ":" + std::to_string(last) + "]\" -type \"polyFaces\"";
        for (int f = first; f <= last; ++f) {
            if (f == nx * ny) {
                t += " f 4" + i32(edges) + i32(edges + 1) + i32(edges + 2) + i32(edges + 3);
                t += " h 4" + i32(~(edges + 7)) + i32(~(edges + 6)) + i32(~(edges + 5)) + i32(~(edges + 4));
                t += " mu 0 4 0 1 2 3";
                continue;
            }
            const int i = f % nx, j = f / nx;
            const int e0 = j * nx + i, e1 = rowEdges + j * vx + i + 1, e2 = (j + 1) * nx + i, e3 = rowEdges + j * vx + i;
            t += " f 4" + i32(e0) + i32(e1) + i32(~e2) + i32(~e3);
            if (j > 0) t += " mu 1 4" + i32(vid(i, j)) + i32(vid(i + 1, j)) + i32(vid(i + 1, j + 1)) + i32(vid(i, j + 1));
            if (f < 3) t += " mu 0 4 0 1 2 3";
        }
        t += ";\n";
    }
    return t;
}

}  // namespace pushpin::test
