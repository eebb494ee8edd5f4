// render_memory_bench: end-to-end memory and time of `pushpin` renders on generated scenes, uncapped
// and under a memory cap (-mm), as child processes.
//
// Scenes (Maya ASCII, written once into --dir and reused while their parameters match):
//   mixed          900 NURBS spheres (makeNurbSphere, per-span divisions 12..18), 1,300 polygon
//                  spheres (polySphere, 40..100 × 20..60 subdivisions) and one 1581² quad terrain
//                  stored in the file (about 5M triangles), crowded in front of one camera at
//                  1280×720 and lit by a directional light; about 25M triangles in all.
//   occluder       a dense polygon wall filling the view in front of spheres that together have 10×
//                  the wall's triangles; occluder-wall is the same scene without the spheres.
//   empty          the mixed scene's camera, light and resolution without geometry: its peak RSS is
//                  what the cap is added to.
// --scale F scales every object's resolution by √F in each direction, so triangle counts scale by
// about F. --detail F scales only the mixed scene's spheres the same way: their triangles grow by
// about F while the stored terrain keeps its size, so the render data can be made many times a cap
// without a larger file.
//
// Each configuration runs --runs times (a failed run is not repeated); the table gives exit code, min/median/max wall time, peak
// resident memory of the child (wait4 ru_maxrss), the figures of pushpin's --stats JSON that exist
// (memory.peakCharged, tessellation.evicted/recomputed, tiles.count; "–" when absent) and whether
// the EXR image is bit-identical to the uncapped one. The checks the out-of-core goal needs follow
// the table: peak RSS ≤ empty RSS + cap + 64 MB, capped time ≤ 1.5× uncapped, 2 threads ≥ 1.8× one,
// occluder time ≤ 1.1× the wall's. --baseline adds a second binary's uncapped renders beside the
// first. When `blender` is found the mixed scene is also built by a generated Python script and
// rendered with Cycles on the CPU at 1 sample, for its time and peak RSS.
//
// usage: render_memory_bench [--scale F] [--detail F] [--runs N] [--dir DIR] [--pushpin PATH] [--baseline PATH]
//                            [--threads 1,2] [--caps 256,512,1024] [--blender PATH | --no-blender]
//                            [--scenes mixed,occluder]
#include "bench/bench_support.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace OIIO = OIIO_NAMESPACE;
using pushpin::bench::ChildRun;
using pushpin::bench::runChild;

// Bumped whenever the generated text changes, so that files of an older generator are rewritten.
constexpr int kGeneratorVersion = 3;
constexpr int kWidth = 1280, kHeight = 720;
constexpr double kPi = 3.14159265358979323846;
// Tangent of half the horizontal field of view of Maya's default camera: 36 mm film (1.417 in
// horizontal aperture) at a 35 mm focal length, horizontal film fit; the vertical one follows the
// image aspect.
constexpr double kTanHalfX = 18.0 / 35.0;
constexpr double kTanHalfY = kTanHalfX * kHeight / kWidth;

// ------------------------------------------------------------------------------ random numbers
// splitmix64: the same numbers on every platform and standard library (std distributions are not).
class Random {
public:
    explicit Random(uint64_t seed) : m_state(seed) {}
    uint64_t next() {
        uint64_t z = (m_state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }  // [0, 1)
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    int integer(int lo, int hi) { return lo + int(next() % uint64_t(hi - lo + 1)); }  // [lo, hi]

private:
    uint64_t m_state;
};

// ------------------------------------------------------------------------------ scene description
struct Vec3 {
    double x = 0, y = 0, z = 0;
};

enum class Kind { NurbsSphere, PolySphere };

// One sphere; `a` and `b` are per-span divisions (NURBS: 8 sections × 4 spans) or polySphere's
// subdivisionsAxis and subdivisionsHeight.
struct SceneObject {
    Kind kind = Kind::PolySphere;
    int a = 0, b = 0;
    double radius = 1;
    Vec3 translate, rotate;  // rotate in degrees, Maya's xyz order
    int shader = 0;
};

constexpr int kNurbsSections = 8, kNurbsSpans = 4;

uint64_t objectTriangles(const SceneObject& o) {
    // A NURBS sphere's grid is (8·a) × (4·b) quads split in two, less the zero-area triangles of
    // the row at each pole, which pushpin drops: the same count as a UV sphere of 8·a segments and
    // 4·b rings, two pole fans plus quads split in two.
    const uint64_t segments = o.kind == Kind::NurbsSphere ? uint64_t(kNurbsSections) * o.a : uint64_t(o.a);
    const uint64_t rings = o.kind == Kind::NurbsSphere ? uint64_t(kNurbsSpans) * o.b : uint64_t(o.b);
    return 2ull * segments * (rings - 1);
}

// Quad grid stored in the file: quads × quads faces over [x0, x1] × [zNear, zFar], heights from
// terrainHeight(). Faces wind so that their normals point up (+y).
struct Terrain {
    int quads = 0;
    double x0 = -160, x1 = 160, zNear = 10, zFar = -290;
};

// Gentle hills; the Blender script evaluates the same expression.
double terrainHeight(double x, double z) {
    return 3.0 * std::sin(0.045 * x + 0.8) * std::cos(0.037 * z) + 1.2 * std::sin(0.13 * x - 0.09 * z) +
           0.4 * std::cos(0.31 * x + 0.27 * z) - 4.0;
}

// polyPlane facing the camera (axis +z).
struct Wall {
    int subdivisions = 0;
    double size = 40, z = -30;
};

struct Shader {
    const char* type;  // lambert or blinn
    double r, g, b;
};

const Shader kShaders[] = {
    {"lambert", 0.72, 0.30, 0.22}, {"lambert", 0.25, 0.55, 0.32}, {"blinn", 0.20, 0.35, 0.75},
    {"blinn", 0.85, 0.75, 0.35},   {"lambert", 0.60, 0.60, 0.62},
};
constexpr int kShaderCount = int(sizeof(kShaders) / sizeof(kShaders[0]));
constexpr int kGroundShader = 4;

struct SceneSpec {
    std::string name;
    std::string params;  // what the file was generated from, checked before reusing it
    Vec3 cameraTranslate, cameraRotate;
    std::vector<SceneObject> objects;
    std::optional<Terrain> terrain;
    std::optional<Wall> wall;

    uint64_t triangles() const {
        uint64_t n = 0;
        for (const SceneObject& o : objects) n += objectTriangles(o);
        if (terrain) n += 2ull * uint64_t(terrain->quads) * uint64_t(terrain->quads);
        if (wall) n += 2ull * uint64_t(wall->subdivisions) * uint64_t(wall->subdivisions);
        return n;
    }
    size_t count(Kind k) const {
        return size_t(std::count_if(objects.begin(), objects.end(), [k](const SceneObject& o) { return o.kind == k; }));
    }
};

int scaled(int value, double linearScale, int minimum) {
    return std::max(minimum, int(std::lround(value * linearScale)));
}

// Camera axes of a Maya camera rotated by rx degrees about X (no other rotation).
struct CameraFrame {
    Vec3 position, forward, up;
};

CameraFrame cameraFrame(const Vec3& t, double rxDegrees) {
    const double a = rxDegrees * kPi / 180.0;
    return {t, {0, std::sin(a), -std::cos(a)}, {0, std::cos(a), std::sin(a)}};
}

// The point at distance d along the view direction, offset to screen position (sx, sy) in [-1, 1].
Vec3 viewPoint(const CameraFrame& c, double d, double sx, double sy) {
    const double ox = sx * kTanHalfX * d, oy = sy * kTanHalfY * d;
    return {c.position.x + d * c.forward.x + ox, c.position.y + d * c.forward.y + oy * c.up.y,
            c.position.z + d * c.forward.z + oy * c.up.z};
}

std::string scaleText(double scale) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", scale);
    return buf;
}

// Crowded shot: spheres at distances 40..300 centred anywhere in the frame (some reach past its edges),
// never sunk more than 40% of their radius into the terrain, so near ones hide parts of far ones.
SceneSpec mixedScene(double scale, double detail) {
    SceneSpec s;
    s.name = "mixed";
    s.params = "mixed scale=" + scaleText(scale);
    if (detail != 1.0) s.params += " detail=" + scaleText(detail);
    s.cameraTranslate = {0, 12, 30};
    s.cameraRotate = {-6, 0, 0};
    const double k = std::sqrt(scale);  // per-direction factor, so triangles scale by `scale`
    const double ks = k * std::sqrt(detail);  // the spheres' factor
    const CameraFrame cam = cameraFrame(s.cameraTranslate, s.cameraRotate.x);
    Random rng(0x6d69786564ull);
    constexpr int kNurbs = 900, kPoly = 1300;
    for (int i = 0; i < kNurbs + kPoly; ++i) {
        SceneObject o;
        // 9 of every 22 are NURBS spheres (900 of 2,200), interleaved so both kinds spread over all
        // depths.
        o.kind = (i % 22) < 9 ? Kind::NurbsSphere : Kind::PolySphere;
        if (o.kind == Kind::NurbsSphere) {
            const int div = rng.integer(12, 18);
            o.a = o.b = scaled(div, ks, 1);
        } else {
            o.a = scaled(rng.integer(40, 100), ks, 3);
            o.b = scaled(rng.integer(20, 60), ks, 2);
        }
        o.radius = rng.uniform(0.5, 2.0);
        const double d = rng.uniform(40.0, 300.0);
        Vec3 p = viewPoint(cam, d, rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
        p.y = std::max(p.y, terrainHeight(p.x, p.z) + 0.6 * o.radius);
        o.translate = p;
        o.rotate = {rng.uniform(-180, 180), rng.uniform(-180, 180), rng.uniform(-180, 180)};
        o.shader = rng.integer(0, kShaderCount - 1);
        s.objects.push_back(o);
    }
    Terrain t;
    t.quads = scaled(1581, k, 2);
    s.terrain = t;
    return s;
}

// A wall at distance 30 filling the view, and (withHidden) spheres behind it at distances 50..150,
// all inside the view frustum, until their triangles reach 10× the wall's.
SceneSpec occluderScene(double scale, bool withHidden) {
    SceneSpec s;
    s.name = withHidden ? "occluder" : "occluder-wall";
    s.params = s.name + " scale=" + scaleText(scale);
    s.cameraTranslate = {0, 0, 0};
    s.cameraRotate = {0, 0, 0};
    const double k = std::sqrt(scale);
    Wall w;
    w.subdivisions = scaled(775, k, 1);
    s.wall = w;
    if (!withHidden) return s;
    const uint64_t target = 10ull * 2ull * uint64_t(w.subdivisions) * uint64_t(w.subdivisions);
    const CameraFrame cam = cameraFrame(s.cameraTranslate, 0);
    Random rng(0x6f63636c75646572ull);
    uint64_t hidden = 0;
    for (int i = 0; hidden < target; ++i) {
        SceneObject o;
        o.kind = i % 2 == 0 ? Kind::NurbsSphere : Kind::PolySphere;
        if (o.kind == Kind::NurbsSphere) {
            o.a = o.b = scaled(20, k, 1);
        } else {
            o.a = scaled(100, k, 3);
            o.b = scaled(60, k, 2);
        }
        o.radius = rng.uniform(1.0, 4.0);
        o.translate = viewPoint(cam, rng.uniform(50.0, 150.0), rng.uniform(-0.9, 0.9), rng.uniform(-0.9, 0.9));
        o.rotate = {rng.uniform(-180, 180), rng.uniform(-180, 180), 0};
        o.shader = rng.integer(0, kShaderCount - 1);
        hidden += objectTriangles(o);
        s.objects.push_back(o);
    }
    return s;
}

SceneSpec emptyScene(const SceneSpec& like) {
    SceneSpec s;
    s.name = "empty";
    s.params = "empty";
    s.cameraTranslate = like.cameraTranslate;
    s.cameraRotate = like.cameraRotate;
    return s;
}

// ------------------------------------------------------------------------------ text output
// Buffered writer with fast number formatting (std::to_chars); the terrain alone is ~250 MB of text.
class TextFile {
public:
    explicit TextFile(const fs::path& path) : m_file(std::fopen(path.c_str(), "wb")) { m_buf.reserve(kFlushBytes + 4096); }
    ~TextFile() {
        if (m_file) std::fclose(m_file);
    }
    TextFile(const TextFile&) = delete;
    TextFile& operator=(const TextFile&) = delete;

    bool isOpen() const { return m_file != nullptr; }
    TextFile& operator<<(std::string_view text) {
        m_buf.append(text);
        flushIfFull();
        return *this;
    }
    TextFile& num(int64_t v) {  // followed by one space
        char tmp[24];
        const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
        m_buf.append(tmp, r.ptr);
        m_buf.push_back(' ');
        flushIfFull();
        return *this;
    }
    TextFile& num(double v, int decimals = 6) {  // fixed notation, followed by one space
        char tmp[48];
        const auto r = std::to_chars(tmp, tmp + sizeof tmp, v, std::chars_format::fixed, decimals);
        m_buf.append(tmp, r.ptr);
        m_buf.push_back(' ');
        flushIfFull();
        return *this;
    }
    bool close() {
        if (!m_file) return false;
        const bool ok = flush() && std::fclose(m_file) == 0;
        m_file = nullptr;
        return ok;
    }

private:
    static constexpr size_t kFlushBytes = size_t(8) << 20;
    bool flush() {
        const bool ok = std::fwrite(m_buf.data(), 1, m_buf.size(), m_file) == m_buf.size();
        m_buf.clear();
        m_failed = m_failed || !ok;
        return !m_failed;
    }
    void flushIfFull() {
        if (m_buf.size() >= kFlushBytes) flush();
    }
    FILE* m_file;
    std::string m_buf;
    bool m_failed = false;
};

std::string double3(const Vec3& v) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "-type \"double3\" %.6f %.6f %.6f ", v.x, v.y, v.z);
    return buf;
}

std::string nodeName(const char* base, size_t i) { return std::string(base) + std::to_string(i + 1); }

// Writes the terrain mesh's .vt, .ed and .fc in chunks, the way Maya writes long arrays.
void writeTerrainArrays(TextFile& w, const Terrain& t) {
    const int64_t q = t.quads, v = q + 1;
    const int64_t verts = v * v, hEdges = v * q, edges = 2 * hEdges, faces = q * q;
    const double dx = (t.x1 - t.x0) / double(q), dz = (t.zFar - t.zNear) / double(q);
    auto vid = [v](int64_t i, int64_t j) { return j * v + i; };
    auto hEdge = [q](int64_t i, int64_t j) { return j * q + i; };                // (i,j) → (i+1,j)
    auto vEdge = [v, hEdges](int64_t i, int64_t j) { return hEdges + j * v + i; };  // (i,j) → (i,j+1)
    constexpr int64_t kChunk = 1000;

    w << "\tsetAttr -s " << std::to_string(verts) << " \".vt\";\n";
    for (int64_t first = 0; first < verts; first += kChunk) {
        const int64_t last = std::min(verts, first + kChunk) - 1;
        w << "\tsetAttr \".vt[" << std::to_string(first) << ":" << std::to_string(last) << "]\"";
        for (int64_t k = first; k <= last; ++k) {
            if ((k - first) % 4 == 0) w << "\n\t\t ";
            const double x = t.x0 + double(k % v) * dx, z = t.zNear + double(k / v) * dz;
            w.num(x, 4).num(terrainHeight(x, z), 4).num(z, 4);
        }
        w << ";\n";
    }
    w << "\tsetAttr -s " << std::to_string(edges) << " \".ed\";\n";
    for (int64_t first = 0; first < edges; first += kChunk) {
        const int64_t last = std::min(edges, first + kChunk) - 1;
        w << "\tsetAttr \".ed[" << std::to_string(first) << ":" << std::to_string(last) << "]\"";
        for (int64_t e = first; e <= last; ++e) {
            if ((e - first) % 8 == 0) w << "\n\t\t";
            int64_t a, b;
            if (e < hEdges) {
                a = vid(e % q, e / q);
                b = a + 1;
            } else {
                a = e - hEdges;  // vid(i, j) of vertical edge (i, j)
                b = a + v;
            }
            w.num(a).num(b).num(int64_t(1));  // 1: smooth edge
        }
        w << ";\n";
    }
    // Face (i, j) walks (i,j) → (i+1,j) → (i+1,j+1) → (i,j+1); j runs toward zFar (−z), so the
    // right-hand normal points up.
    w << "\tsetAttr -s " << std::to_string(faces) << " -ch " << std::to_string(4 * faces) << " \".fc\";\n";
    for (int64_t first = 0; first < faces; first += kChunk) {
        const int64_t last = std::min(faces, first + kChunk) - 1;
        w << "\tsetAttr \".fc[" << std::to_string(first) << ":" << std::to_string(last) << "]\" -type \"polyFaces\"";
        for (int64_t f = first; f <= last; ++f) {
            const int64_t i = f % q, j = f / q;
            w << "\n\t\tf 4 ";
            w.num(hEdge(i, j)).num(vEdge(i + 1, j)).num(-hEdge(i, j + 1) - 1).num(-vEdge(i, j) - 1);
        }
        w << ";\n";
    }
}

void writeMeshShapeHeader(TextFile& w, const std::string& shape, const std::string& parent) {
    w << "createNode mesh -n \"" << shape << "\" -p \"" << parent << "\";\n"
      << "\tsetAttr -k off \".v\";\n\tsetAttr \".vir\" yes;\n\tsetAttr \".vif\" yes;\n"
      << "\tsetAttr \".uvst[0].uvsn\" -type \"string\" \"map1\";\n\tsetAttr \".cuvs\" -type \"string\" \"map1\";\n"
      << "\tsetAttr \".dcc\" -type \"string\" \"Ambient+Diffuse\";\n";
}

// The scene as Maya writes it: DAG nodes, creators, shaders with shading groups, default nodes
// edited with `select -ne`, then light links and connections. Written to a temporary name and
// renamed, so an interrupted run leaves no partial file to reuse.
bool writeMa(const SceneSpec& s, const fs::path& path) {
    const fs::path tmp = path.string() + ".tmp";
    TextFile w(tmp);
    if (!w.isOpen()) return false;
    char buf[256];
    w << "//Maya ASCII 2018 scene\n//Name: " << path.filename().string() << "\n"
      << "//render_memory_bench: " << s.params << " generator=" << std::to_string(kGeneratorVersion) << "\n"
      << "requires maya \"2018\";\ncurrentUnit -l centimeter -a degree -t film;\n"
      << "fileInfo \"application\" \"maya\";\nfileInfo \"product\" \"Maya 2018\";\n";

    w << "createNode transform -n \"shotCam\";\n\tsetAttr \".t\" " << double3(s.cameraTranslate) << ";\n"
      << "\tsetAttr \".r\" " << double3(s.cameraRotate) << ";\n"
      << "createNode camera -n \"shotCamShape\" -p \"shotCam\";\n\tsetAttr -k off \".v\";\n"
      << "\tsetAttr \".rnd\" yes;\n\tsetAttr \".fl\" 35;\n\tsetAttr \".coi\" 100;\n"
      << "\tsetAttr \".imn\" -type \"string\" \"shotCam\";\n";
    w << "createNode transform -n \"sunLight\";\n\tsetAttr \".r\" -type \"double3\" -50 30 0 ;\n"
      << "createNode directionalLight -n \"sunLightShape\" -p \"sunLight\";\n\tsetAttr -k off \".v\";\n"
      << "\tsetAttr \".in\" 1.2;\n";

    for (size_t i = 0; i < s.objects.size(); ++i) {
        const SceneObject& o = s.objects[i];
        const bool nurbs = o.kind == Kind::NurbsSphere;
        const std::string xform = nodeName(nurbs ? "nurbsSphere" : "pSphere", i);
        const std::string shape = nodeName(nurbs ? "nurbsSphereShape" : "pSphereShape", i);
        w << "createNode transform -n \"" << xform << "\";\n\tsetAttr \".t\" " << double3(o.translate) << ";\n"
          << "\tsetAttr \".r\" " << double3(o.rotate) << ";\n";
        if (nurbs) {
            w << "createNode nurbsSurface -n \"" << shape << "\" -p \"" << xform << "\";\n"
              << "\tsetAttr -k off \".v\";\n\tsetAttr \".vir\" yes;\n\tsetAttr \".vif\" yes;\n\tsetAttr \".tw\" yes;\n"
              << "\tsetAttr \".dvu\" 0;\n\tsetAttr \".dvv\" 0;\n\tsetAttr \".cpr\" 4;\n\tsetAttr \".cps\" 4;\n";
            // Per-span divisions are numberU × uDivisionsFactor (and likewise in v).
            std::snprintf(buf, sizeof buf,
                          "\tsetAttr \".nu\" %d;\n\tsetAttr \".nv\" %d;\n\tsetAttr \".nufa\" 1;\n\tsetAttr \".nvfa\" 1;\n",
                          o.a, o.b);
            w << buf;
            std::snprintf(buf, sizeof buf,
                          "createNode makeNurbSphere -n \"makeNurbSphere%zu\";\n\tsetAttr \".ax\" -type \"double3\" 0 1 0 ;\n"
                          "\tsetAttr \".r\" %.6f;\n\tsetAttr \".s\" %d;\n\tsetAttr \".nsp\" %d;\n",
                          i + 1, o.radius, kNurbsSections, kNurbsSpans);
            w << buf;
        } else {
            writeMeshShapeHeader(w, shape, xform);
            std::snprintf(buf, sizeof buf,
                          "createNode polySphere -n \"polySphere%zu\";\n\tsetAttr \".r\" %.6f;\n\tsetAttr \".sa\" %d;\n"
                          "\tsetAttr \".sh\" %d;\n",
                          i + 1, o.radius, o.a, o.b);
            w << buf;
        }
    }
    if (s.terrain) {
        w << "createNode transform -n \"terrain\";\n";
        writeMeshShapeHeader(w, "terrainShape", "terrain");
        writeTerrainArrays(w, *s.terrain);
    }
    if (s.wall) {
        w << "createNode transform -n \"wall\";\n\tsetAttr \".t\" -type \"double3\" 0 0 " << std::to_string(s.wall->z)
          << " ;\n";
        writeMeshShapeHeader(w, "wallShape", "wall");
        std::snprintf(buf, sizeof buf,
                      "createNode polyPlane -n \"polyPlane1\";\n\tsetAttr \".ax\" -type \"double3\" 0 0 1 ;\n"
                      "\tsetAttr \".w\" %g;\n\tsetAttr \".h\" %g;\n\tsetAttr \".sw\" %d;\n\tsetAttr \".sh\" %d;\n"
                      "\tsetAttr \".cuv\" 2;\n",
                      s.wall->size, s.wall->size, s.wall->subdivisions, s.wall->subdivisions);
        w << buf;
    }

    const bool anyGeometry = !s.objects.empty() || s.terrain || s.wall;
    const int shaders = anyGeometry ? kShaderCount : 0;
    for (int k = 0; k < shaders; ++k) {
        const Shader& sh = kShaders[k];
        std::snprintf(buf, sizeof buf, "createNode %s -n \"mat%d\";\n\tsetAttr \".c\" -type \"float3\" %.3f %.3f %.3f ;\n",
                      sh.type, k, sh.r, sh.g, sh.b);
        w << buf;
        if (std::strcmp(sh.type, "blinn") == 0) w << "\tsetAttr \".ec\" 0.3;\n\tsetAttr \".sro\" 0.5;\n";
        std::snprintf(buf, sizeof buf,
                      "createNode shadingEngine -n \"mat%dSG\";\n\tsetAttr \".ihi\" 0;\n\tsetAttr \".ro\" yes;\n"
                      "createNode materialInfo -n \"materialInfo%d\";\n",
                      k, k + 1);
        w << buf;
    }
    const std::string links = std::to_string(shaders + 2);
    w << "createNode lightLinker -s -n \"lightLinker1\";\n\tsetAttr -s " << links << " \".lnk\";\n\tsetAttr -s "
      << links << " \".slnk\";\n";
    w << "createNode displayLayerManager -n \"layerManager\";\ncreateNode displayLayer -n \"defaultLayer\";\n"
      << "createNode renderLayerManager -n \"renderLayerManager\";\ncreateNode renderLayer -n \"defaultRenderLayer\";\n"
      << "\tsetAttr \".g\" yes;\n";

    w << "select -ne :time1;\n\tsetAttr \".o\" 1;\n"
      << "select -ne :renderPartition;\n\tsetAttr -s " << links << " \".st\";\n"
      << "select -ne :initialShadingGroup;\n\tsetAttr \".ro\" yes;\n"
      << "select -ne :initialParticleSE;\n\tsetAttr \".ro\" yes;\n"
      << "select -ne :defaultShaderList1;\n\tsetAttr -s " << std::to_string(shaders + 2) << " \".s\";\n"
      << "select -ne :lightList1;\n"
      << "select -ne :defaultRenderGlobals;\n\tsetAttr \".ren\" -type \"string\" \"mayaSoftware\";\n"
      << "select -ne :defaultResolution;\n\tsetAttr \".w\" " << std::to_string(kWidth) << ";\n\tsetAttr \".h\" "
      << std::to_string(kHeight) << ";\n\tsetAttr \".pa\" 1;\n\tsetAttr \".dar\" 1.7777777910232544;\n"
      << "select -ne :defaultLightSet;\n";

    for (const char* kind : {"link", "shadowLink"}) {
        w << "relationship \"" << kind << "\" \":lightLinker1\" \":initialShadingGroup.message\" \":defaultLightSet.message\";\n";
        w << "relationship \"" << kind << "\" \":lightLinker1\" \":initialParticleSE.message\" \":defaultLightSet.message\";\n";
        for (int k = 0; k < shaders; ++k) {
            std::snprintf(buf, sizeof buf, "relationship \"%s\" \":lightLinker1\" \"mat%dSG.message\" \":defaultLightSet.message\";\n",
                          kind, k);
            w << buf;
        }
    }
    w << "connectAttr \"layerManager.dli[0]\" \"defaultLayer.id\";\n"
      << "connectAttr \"renderLayerManager.rlmi[0]\" \"defaultRenderLayer.rlid\";\n";
    // Creators feed their shapes; each shape's instObjGroups (iog) joins its shading group's
    // dagSetMembers (dsm).
    for (size_t i = 0; i < s.objects.size(); ++i) {
        const SceneObject& o = s.objects[i];
        if (o.kind == Kind::NurbsSphere)
            std::snprintf(buf, sizeof buf,
                          "connectAttr \"makeNurbSphere%zu.os\" \"nurbsSphereShape%zu.cr\";\n"
                          "connectAttr \"nurbsSphereShape%zu.iog\" \"mat%dSG.dsm\" -na;\n",
                          i + 1, i + 1, i + 1, o.shader);
        else
            std::snprintf(buf, sizeof buf,
                          "connectAttr \"polySphere%zu.out\" \"pSphereShape%zu.i\";\n"
                          "connectAttr \"pSphereShape%zu.iog\" \"mat%dSG.dsm\" -na;\n",
                          i + 1, i + 1, i + 1, o.shader);
        w << buf;
    }
    if (s.terrain) {
        std::snprintf(buf, sizeof buf, "connectAttr \"terrainShape.iog\" \"mat%dSG.dsm\" -na;\n", kGroundShader);
        w << buf;
    }
    if (s.wall)
        w << "connectAttr \"polyPlane1.out\" \"wallShape.i\";\n"
          << "connectAttr \"wallShape.iog\" \"mat" << std::to_string(kGroundShader) << "SG.dsm\" -na;\n";
    for (int k = 0; k < shaders; ++k) {
        std::snprintf(buf, sizeof buf,
                      "connectAttr \"mat%dSG.msg\" \"materialInfo%d.sg\";\nconnectAttr \"mat%d.msg\" \"materialInfo%d.m\";\n"
                      "connectAttr \"mat%d.oc\" \"mat%dSG.ss\";\nconnectAttr \"mat%dSG.pa\" \":renderPartition.st\" -na;\n"
                      "connectAttr \"mat%d.msg\" \":defaultShaderList1.s\" -na;\n",
                      k, k + 1, k, k + 1, k, k, k, k);
        w << buf;
    }
    w << "connectAttr \"sunLightShape.ltd\" \":lightList1.l\" -na;\n"
      << "connectAttr \"sunLight.iog\" \":defaultLightSet.dsm\" -na;\n"
      << "// End of " << path.filename().string() << "\n";
    if (!w.close()) return false;
    std::error_code ec;
    fs::rename(tmp, path, ec);
    return !ec;
}

// True when `path` exists and its third line names the same parameters and generator.
bool upToDate(const fs::path& path, const SceneSpec& s) {
    FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return false;
    char head[512] = {};
    const size_t n = std::fread(head, 1, sizeof head - 1, f);
    std::fclose(f);
    const std::string want = "//render_memory_bench: " + s.params + " generator=" + std::to_string(kGeneratorVersion) + "\n";
    return std::string_view(head, n).find(want) != std::string_view::npos;
}

// ------------------------------------------------------------------------------ Blender script
// Python for `blender -b --factory-startup --python`: the same spheres (a NURBS sphere becomes a
// UV sphere of 8·div segments and 4·div rings, which has its triangle count), the same terrain, all
// built in the script from arrays through foreach_set, the same camera (35 mm lens on a 36 mm horizontal sensor) and resolution; Cycles
// on the CPU, 1 sample, no denoising. Every object gets its own mesh data, as in the .ma file.
// Blender keeps Maya's coordinates: only the camera and light orientation matter to the image.
bool writeBlenderScript(const SceneSpec& s, const fs::path& path, const fs::path& image, int threads) {
    TextFile w(path);
    if (!w.isOpen()) return false;
    char buf[512];
    w << "import array, math, sys, time\nimport bpy\nfrom mathutils import Euler\n"
      << "t0 = time.time()\n"
      << "bpy.ops.wm.read_factory_settings(use_empty=True)\nscene = bpy.context.scene\n";
    w << "SHADERS = [";
    for (const Shader& sh : kShaders) {
        std::snprintf(buf, sizeof buf, "(%.3f, %.3f, %.3f), ", sh.r, sh.g, sh.b);
        w << buf;
    }
    w << "]\nmats = []\nfor k, c in enumerate(SHADERS):\n"
      << "    m = bpy.data.materials.new('mat%d' % k)\n    m.diffuse_color = (c[0], c[1], c[2], 1.0)\n"
      << "    mats.append(m)\n";
    w << "# kind (n: NURBS sphere as UV sphere, p: polySphere), segments, rings, radius, translate, rotate, shader\n"
      << "OBJECTS = [\n";
    for (const SceneObject& o : s.objects) {
        const bool nurbs = o.kind == Kind::NurbsSphere;
        const int segments = nurbs ? kNurbsSections * o.a : o.a, rings = nurbs ? kNurbsSpans * o.b : o.b;
        std::snprintf(buf, sizeof buf, "('%c', %d, %d, %.6f, %.6f, %.6f, %.6f, %.4f, %.4f, %.4f, %d),\n", nurbs ? 'n' : 'p',
                      segments, rings, o.radius, o.translate.x, o.translate.y, o.translate.z, o.rotate.x, o.rotate.y,
                      o.rotate.z, o.shader);
        w << buf;
    }
    w << "]\n"
      // Vertices and faces go in through foreach_set: bmesh's create_uvsphere takes about 0.17 s
      // for a sphere of 12k triangles, which would make the script's set-up minutes long.
      << "def uv_sphere(name, seg, rings, r):\n"
      << "    # A vertex ring per latitude and two poles on the y axis, like polySphere.\n"
      << "    co = array.array('f')\n"
      << "    for i in range(1, rings):\n"
      << "        th = math.pi * i / rings\n"
      << "        y, s = r * math.cos(th), r * math.sin(th)\n"
      << "        for j in range(seg):\n"
      << "            ph = 2.0 * math.pi * j / seg\n"
      << "            co.extend((s * math.cos(ph), y, -s * math.sin(ph)))\n"
      << "    top = seg * (rings - 1)\n"
      << "    co.extend((0.0, r, 0.0, 0.0, -r, 0.0))\n"
      << "    idx = array.array('i')\n"
      << "    for j in range(seg):\n"
      << "        idx.extend((top, j, (j + 1) % seg))\n"
      << "    for i in range(rings - 2):\n"
      << "        b = i * seg\n"
      << "        for j in range(seg):\n"
      << "            k = (j + 1) % seg\n"
      << "            idx.extend((b + j, b + seg + j, b + seg + k, b + k))\n"
      << "    b = (rings - 2) * seg\n"
      << "    for j in range(seg):\n"
      << "        idx.extend((top + 1, b + (j + 1) % seg, b + j))\n"
      << "    tot = array.array('i', [3]) * seg + array.array('i', [4]) * (seg * (rings - 2)) + array.array('i', [3]) * seg\n"
      << "    start = array.array('i', range(0, 3 * seg, 3))\n"
      << "    start.extend(range(3 * seg, 3 * seg + 4 * seg * (rings - 2), 4))\n"
      << "    start.extend(range(3 * seg + 4 * seg * (rings - 2), len(idx), 3))\n"
      << "    me = bpy.data.meshes.new(name)\n"
      << "    me.vertices.add(len(co) // 3)\n    me.vertices.foreach_set('co', co)\n"
      << "    me.loops.add(len(idx))\n    me.loops.foreach_set('vertex_index', idx)\n"
      << "    me.polygons.add(len(tot))\n    me.polygons.foreach_set('loop_start', start)\n"
      << "    me.polygons.foreach_set('loop_total', tot)\n"
      << "    me.polygons.foreach_set('use_smooth', [True] * len(tot))\n"
      << "    me.update(calc_edges=True)\n"
      << "    return me\n"
      << "for k, (kind, seg, rings, r, tx, ty, tz, rx, ry, rz, sh) in enumerate(OBJECTS):\n"
      << "    me = uv_sphere('m%d' % k, seg, rings, r)\n"
      << "    me.materials.append(mats[sh])\n"
      << "    ob = bpy.data.objects.new('o%d' % k, me)\n    ob.location = (tx, ty, tz)\n"
      << "    ob.rotation_euler = Euler((math.radians(rx), math.radians(ry), math.radians(rz)), 'XYZ')\n"
      << "    scene.collection.objects.link(ob)\n";
    if (s.terrain) {
        const Terrain& t = *s.terrain;
        std::snprintf(buf, sizeof buf, "Q = %d\nX0, X1, ZN, ZF = %.6f, %.6f, %.6f, %.6f\n", t.quads, t.x0, t.x1, t.zNear,
                      t.zFar);
        w << buf;
        w << "V = Q + 1\ndx = (X1 - X0) / Q\ndz = (ZF - ZN) / Q\n"
          << "sin, cos = math.sin, math.cos\nco = array.array('f')\n"
          << "xs = [X0 + i * dx for i in range(V)]\n"
          << "for j in range(V):\n    z = ZN + j * dz\n    row = []\n"
          << "    for x in xs:\n"
          << "        row += (x, 3.0 * sin(0.045 * x + 0.8) * cos(0.037 * z) + 1.2 * sin(0.13 * x - 0.09 * z)"
          << " + 0.4 * cos(0.31 * x + 0.27 * z) - 4.0, z)\n"
          << "    co.extend(row)\n"
          << "idx = array.array('i')\n"
          << "for j in range(Q):\n    b = j * V\n"
          << "    idx.extend([v for i in range(Q) for v in (b + i, b + i + 1, b + V + i + 1, b + V + i)])\n"
          << "me = bpy.data.meshes.new('terrain')\nme.vertices.add(V * V)\nme.vertices.foreach_set('co', co)\n"
          << "me.loops.add(len(idx))\nme.loops.foreach_set('vertex_index', idx)\nme.polygons.add(Q * Q)\n"
          << "me.polygons.foreach_set('loop_start', array.array('i', range(0, 4 * Q * Q, 4)))\n"
          << "me.polygons.foreach_set('loop_total', array.array('i', [4]) * (Q * Q))\n"
          << "me.polygons.foreach_set('use_smooth', [True] * (Q * Q))\n"
          << "del co, idx\nme.update(calc_edges=True)\n";
        std::snprintf(buf, sizeof buf, "me.materials.append(mats[%d])\n", kGroundShader);
        w << buf;
        w << "scene.collection.objects.link(bpy.data.objects.new('terrain', me))\n";
    }
    std::snprintf(buf, sizeof buf,
                  "cam = bpy.data.cameras.new('shotCam')\ncam.lens = 35.0\ncam.sensor_width = 36.0\n"
                  "cam.sensor_fit = 'HORIZONTAL'\ncam.clip_start = 0.1\ncam.clip_end = 10000.0\n"
                  "camob = bpy.data.objects.new('shotCam', cam)\ncamob.location = (%.6f, %.6f, %.6f)\n"
                  "camob.rotation_euler = Euler((math.radians(%.6f), math.radians(%.6f), math.radians(%.6f)), 'XYZ')\n"
                  "scene.collection.objects.link(camob)\nscene.camera = camob\n",
                  s.cameraTranslate.x, s.cameraTranslate.y, s.cameraTranslate.z, s.cameraRotate.x, s.cameraRotate.y,
                  s.cameraRotate.z);
    w << buf;
    w << "sun = bpy.data.lights.new('sunLight', 'SUN')\nsun.energy = 3.0\n"
      << "sunob = bpy.data.objects.new('sunLight', sun)\n"
      << "sunob.rotation_euler = Euler((math.radians(-50.0), math.radians(30.0), 0.0), 'XYZ')\n"
      << "scene.collection.objects.link(sunob)\n";
    std::snprintf(buf, sizeof buf,
                  "scene.render.engine = 'CYCLES'\nscene.cycles.device = 'CPU'\nscene.cycles.samples = 1\n"
                  "scene.cycles.use_adaptive_sampling = False\nscene.cycles.use_denoising = False\n"
                  "scene.render.resolution_x = %d\nscene.render.resolution_y = %d\n"
                  "scene.render.resolution_percentage = 100\nscene.render.threads_mode = 'FIXED'\n"
                  "scene.render.threads = %d\nscene.render.image_settings.file_format = 'OPEN_EXR'\n",
                  kWidth, kHeight, threads);
    w << buf;
    w << "scene.render.filepath = '" << image.string() << "'\n"
      << "t1 = time.time()\nbpy.ops.render.render(write_still=True)\nt2 = time.time()\n"
      << "print('render_memory_bench: build %.3f s, render %.3f s' % (t1 - t0, t2 - t1))\n"
      << "sys.stdout.flush()\n";
    return w.close();
}

// ------------------------------------------------------------------------------ --stats JSON
// Flattens a JSON document into dotted paths ("images.0.render.triangles") → scalar text. Enough
// for pushpin's own --stats files; returns an empty map on malformed input.
class JsonFlattener {
public:
    static std::map<std::string, std::string> flatten(std::string_view text) {
        JsonFlattener p(text);
        p.skipBlank();
        if (!p.value("") || (p.skipBlank(), p.m_pos != text.size())) p.m_out.clear();
        return std::move(p.m_out);
    }

private:
    explicit JsonFlattener(std::string_view text) : m_text(text) {}
    void skipBlank() {
        while (m_pos < m_text.size() && std::strchr(" \t\r\n", m_text[m_pos])) ++m_pos;
    }
    bool peek(char c) const { return m_pos < m_text.size() && m_text[m_pos] == c; }
    static std::string join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
    bool string(std::string& out) {
        if (!peek('"')) return false;
        ++m_pos;
        while (m_pos < m_text.size() && m_text[m_pos] != '"') {
            char c = m_text[m_pos++];
            if (c == '\\' && m_pos < m_text.size()) {
                const char e = m_text[m_pos++];
                c = e == 'n' ? '\n' : e == 't' ? '\t' : e;
                if (e == 'u') {  // keep \uXXXX as written
                    out += "\\u";
                    continue;
                }
            }
            out.push_back(c);
        }
        if (!peek('"')) return false;
        ++m_pos;
        return true;
    }
    bool value(const std::string& path) {
        skipBlank();
        if (m_pos >= m_text.size()) return false;
        const char c = m_text[m_pos];
        if (c == '{' || c == '[') {
            const bool object = c == '{';
            ++m_pos;
            skipBlank();
            if (peek(object ? '}' : ']')) return ++m_pos, true;
            for (size_t index = 0;; ++index) {
                std::string key = std::to_string(index);
                if (object) {
                    skipBlank();
                    key.clear();
                    if (!string(key)) return false;
                    skipBlank();
                    if (!peek(':')) return false;
                    ++m_pos;
                }
                if (!value(join(path, key))) return false;
                skipBlank();
                if (peek(',')) {
                    ++m_pos;
                    continue;
                }
                if (!peek(object ? '}' : ']')) return false;
                ++m_pos;
                return true;
            }
        }
        std::string scalar;
        if (c == '"') {
            if (!string(scalar)) return false;
        } else {
            while (m_pos < m_text.size() && !std::strchr(",}] \t\r\n", m_text[m_pos])) scalar.push_back(m_text[m_pos++]);
            if (scalar.empty()) return false;
        }
        m_out[path] = std::move(scalar);
        return true;
    }

    std::string_view m_text;
    size_t m_pos = 0;
    std::map<std::string, std::string> m_out;
};

std::string readWholeFile(const fs::path& path) {
    std::string text;
    FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return text;
    char buf[65536];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, n);
    std::fclose(f);
    return text;
}

struct Stats {
    std::map<std::string, std::string> fields;
    std::optional<double> number(const std::string& key) const {
        auto it = fields.find(key);
        if (it == fields.end()) return std::nullopt;
        double v = 0;
        const auto r = std::from_chars(it->second.data(), it->second.data() + it->second.size(), v);
        if (r.ec != std::errc() || r.ptr != it->second.data() + it->second.size()) return std::nullopt;
        return v;
    }
    std::string text(const std::string& key) const {
        auto it = fields.find(key);
        return it == fields.end() ? std::string() : it->second;
    }
    // A field of the first image's render statistics.
    std::optional<double> render(const std::string& key) const { return number("images.0.render." + key); }
    std::optional<double> tiles() const {
        if (auto v = render("tiles.count")) return v;
        return render("tiles");  // older files: a plain count
    }
    std::vector<std::string> notes() const {
        std::vector<std::string> out;
        for (size_t i = 0;; ++i) {
            auto it = fields.find("notes." + std::to_string(i));
            if (it == fields.end()) return out;
            out.push_back(it->second);
        }
    }
};

// ------------------------------------------------------------------------------ child processes
// The children run through runChild (bench/bench_support.h), their stdout and stderr in dir/logs.

// The first line of a file that starts with `prefix`, or its first line.
std::string firstLine(const fs::path& path, std::string_view prefix) {
    const std::string text = readWholeFile(path);
    std::string first;
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(pos, end - pos);
        if (line.rfind(prefix, 0) == 0) return line;
        if (first.empty()) first = line;
        pos = end + 1;
    }
    return first;
}

// ------------------------------------------------------------------------------ image comparison
struct ImageDiff {
    bool compared = false;
    bool identical = false;
    double maxAbs = 0;
    std::string problem;
};

bool readFloats(const fs::path& path, OIIO::ImageSpec& spec, std::vector<float>& pixels, std::string& problem) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) {
        problem = "cannot read " + path.string() + ": " + OIIO::geterror();
        return false;
    }
    spec = in->spec();
    pixels.resize(size_t(spec.width) * spec.height * spec.nchannels);
    const bool ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data());
    if (!ok) problem = "cannot read " + path.string() + ": " + in->geterror();
    in->close();
    return ok;
}

// Compares every channel of every pixel by its bits; maxAbs is the largest absolute difference.
ImageDiff compareImages(const fs::path& a, const fs::path& b) {
    ImageDiff d;
    OIIO::ImageSpec sa, sb;
    std::vector<float> pa, pb;
    if (!readFloats(a, sa, pa, d.problem) || !readFloats(b, sb, pb, d.problem)) return d;
    d.compared = true;
    if (sa.width != sb.width || sa.height != sb.height || sa.nchannels != sb.nchannels) {
        d.problem = "different sizes or channels";
        d.maxAbs = INFINITY;
        return d;
    }
    d.identical = true;
    for (size_t i = 0; i < pa.size(); ++i) {
        if (std::bit_cast<uint32_t>(pa[i]) == std::bit_cast<uint32_t>(pb[i])) continue;
        d.identical = false;
        const double diff = std::fabs(double(pa[i]) - double(pb[i]));
        d.maxAbs = std::max(d.maxAbs, std::isnan(diff) ? INFINITY : diff);
    }
    return d;
}

// ------------------------------------------------------------------------------ measurement
struct Measurement {
    std::string binary;  // label shown in the table
    std::string scene;
    int threads = 1;
    int capMB = 0;  // 0: uncapped
    int exitCode = -1;
    std::vector<double> seconds;
    long peakKiB = 0;
    Stats stats;
    fs::path image;
    std::string error;                   // first "Error:" line of a failed run
    std::optional<double> blenderBuild;  // Blender only: scene build and render seconds
    std::optional<double> blenderRender;
    std::string comparedWith;  // which row the image was compared against
    ImageDiff diff;

    double median() const {
        std::vector<double> s = seconds;
        std::sort(s.begin(), s.end());
        return s.empty() ? 0.0 : s[s.size() / 2];
    }
    double peakMB() const { return double(peakKiB) / 1024.0; }
    bool ok() const { return exitCode == 0; }
};

struct Bench {
    fs::path dir;
    int runs = 1;

    // Runs a pushpin binary on a scene `runs` times (stopping after a failed run).
    Measurement pushpin(const std::string& label, const fs::path& binary, const std::string& scene, const fs::path& ma,
                        int threads, int capMB) const {
        Measurement m;
        m.binary = label;
        m.scene = scene;
        m.threads = threads;
        m.capMB = capMB;
        const std::string tag = label + "_" + scene + "_n" + std::to_string(threads) +
                                (capMB ? "_mm" + std::to_string(capMB) : std::string("_uncapped"));
        const fs::path outDir = dir / "out", statsPath = dir / "logs" / (tag + ".json");
        for (int run = 0; run < runs; ++run) {
            fs::remove(statsPath);
            std::vector<std::string> args = {binary.string(), "-n", std::to_string(threads), "-rd", outDir.string(),
                                             "-im", tag, "-of", "exr", "--stats", statsPath.string(), "--quiet"};
            if (capMB) args.insert(args.begin() + 1, {"-mm", std::to_string(capMB)});
            args.push_back(ma.string());
            const ChildRun r = runChild(args, dir / "logs" / (tag + ".out"), dir / "logs" / (tag + ".err"));
            m.exitCode = r.exitCode;
            m.seconds.push_back(r.seconds);
            m.peakKiB = std::max(m.peakKiB, r.peakKiB);
            if (r.exitCode != 0) {
                m.error = firstLine(dir / "logs" / (tag + ".err"), "Error:");
                break;
            }
            m.stats.fields = JsonFlattener::flatten(readWholeFile(statsPath));
            m.image = m.stats.text("images.0.path");
        }
        return m;
    }

    Measurement blender(const fs::path& binary, const SceneSpec& spec, int threads) const {
        Measurement m;
        m.binary = "blender cycles";
        m.scene = spec.name;
        m.threads = threads;
        const std::string tag = "blender_" + spec.name + "_n" + std::to_string(threads);
        const fs::path script = dir / (tag + ".py"), image = dir / "out" / (tag + ".exr");
        if (!writeBlenderScript(spec, script, image, threads)) {
            m.error = "cannot write " + script.string();
            return m;
        }
        for (int run = 0; run < runs; ++run) {
            const fs::path out = dir / "logs" / (tag + ".out");
            const ChildRun r = runChild({binary.string(), "-b", "--factory-startup", "-noaudio", "--python-exit-code",
                                         "1", "--python", script.string()},
                                        out, dir / "logs" / (tag + ".err"));
            m.exitCode = r.exitCode;
            m.seconds.push_back(r.seconds);
            m.peakKiB = std::max(m.peakKiB, r.peakKiB);
            const std::string line = firstLine(out, "render_memory_bench:");
            double build = 0, render = 0;
            if (std::sscanf(line.c_str(), "render_memory_bench: build %lf s, render %lf s", &build, &render) == 2) {
                m.blenderBuild = build;
                m.blenderRender = render;
            } else if (r.exitCode == 0) {
                m.exitCode = 1;  // Blender returns 0 even when the script failed before rendering
            }
            if (m.exitCode != 0) {
                m.error = firstLine(dir / "logs" / (tag + ".err"), "Error");
                if (m.error.empty()) m.error = "see " + (dir / "logs" / (tag + ".out")).string();
                break;
            }
            m.image = image;
        }
        return m;
    }
};

std::string formatNumber(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

std::string orDash(const std::optional<double>& v, const char* format = "%.0f") { return v ? formatNumber(format, *v) : "–"; }

std::string mb(const std::optional<double>& bytes) { return bytes ? formatNumber("%.0f", *bytes / 1048576.0) : "–"; }

std::string imageColumn(const Measurement& m) {
    if (m.comparedWith.empty()) return "–";
    if (!m.diff.compared) return m.diff.problem.empty() ? "–" : "not compared (" + m.diff.problem + ")";
    if (m.diff.identical) return "identical (vs " + m.comparedWith + ")";
    return "max abs diff " + formatNumber("%.3g", m.diff.maxAbs) + " (vs " + m.comparedWith + ")";
}

std::vector<int> parseList(const std::string& text) {
    std::vector<int> out;
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find(',', pos);
        if (end == std::string::npos) end = text.size();
        const int v = std::atoi(text.substr(pos, end - pos).c_str());
        if (v > 0) out.push_back(v);
        pos = end + 1;
    }
    return out;
}

std::optional<fs::path> findOnPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    if (!path) return std::nullopt;
    std::string_view rest(path);
    while (!rest.empty()) {
        const size_t colon = rest.find(':');
        const fs::path candidate = fs::path(std::string(rest.substr(0, colon))) / name;
        if (access(candidate.c_str(), X_OK) == 0) return candidate;
        if (colon == std::string_view::npos) break;
        rest.remove_prefix(colon + 1);
    }
    return std::nullopt;
}

const char* passFail(bool pass) { return pass ? "pass" : "**FAIL**"; }

}  // namespace

int main(int argc, char** argv) {
    double scale = 1.0, detail = 1.0;
    Bench bench;
    bench.dir = fs::temp_directory_path() / "pushpin-render-bench";
    fs::path pushpin = fs::canonical("/proc/self/exe").parent_path().parent_path() / "pushpin";
    std::optional<fs::path> baseline;
    std::optional<fs::path> blender;
    bool noBlender = false;
    std::vector<int> threadCounts = {1, 2}, caps = {256, 512, 1024};
    std::string scenes = "mixed,occluder";
    const char* usage =
        "usage: render_memory_bench [--scale F] [--detail F] [--runs N] [--dir DIR] [--pushpin PATH] [--baseline PATH]\n"
        "                           [--threads 1,2] [--caps 256,512,1024] [--blender PATH | --no-blender]\n"
        "                           [--scenes mixed,occluder]\n";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--scale") scale = std::atof(next().c_str());
        else if (a == "--detail") detail = std::atof(next().c_str());
        else if (a == "--runs") bench.runs = std::max(1, std::atoi(next().c_str()));
        else if (a == "--dir") bench.dir = next();
        else if (a == "--pushpin") pushpin = next();
        else if (a == "--baseline") baseline = next();
        else if (a == "--threads") threadCounts = parseList(next());
        else if (a == "--caps") caps = parseList(next());
        else if (a == "--blender") blender = next();
        else if (a == "--no-blender") noBlender = true;
        else if (a == "--scenes") scenes = next();
        else {
            std::fputs(usage, stderr);
            return 2;
        }
    }
    if (!(scale > 0) || !(detail > 0) || threadCounts.empty()) {
        std::fputs(usage, stderr);
        return 2;
    }
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress appears as it is measured
    // pushpin takes its default cap from SLURM_MEM_PER_NODE; uncapped rows must have none.
    unsetenv("SLURM_MEM_PER_NODE");
    for (const fs::path& p : {pushpin, baseline.value_or(pushpin)})
        if (access(p.c_str(), X_OK) != 0) {
            std::fprintf(stderr, "no executable at %s (use --pushpin / --baseline)\n", p.c_str());
            return 1;
        }
    if (!noBlender && !blender) blender = findOnPath("blender");
    if (noBlender) blender.reset();
    const bool wantMixed = scenes.find("mixed") != std::string::npos;
    const bool wantOccluder = scenes.find("occluder") != std::string::npos;
    fs::create_directories(bench.dir / "out");
    fs::create_directories(bench.dir / "logs");

    // Scenes.
    const SceneSpec mixed = mixedScene(scale, detail);
    std::vector<SceneSpec> specs = {emptyScene(mixed)};
    if (wantMixed) specs.push_back(mixed);
    if (wantOccluder) {
        specs.push_back(occluderScene(scale, true));
        specs.push_back(occluderScene(scale, false));
    }
    std::map<std::string, fs::path> files;
    std::printf("## Scenes (scale %g, sphere detail %g, %s)\n\n", scale, detail, bench.dir.c_str());
    std::printf("| scene | NURBS spheres | polygon spheres | stored mesh | triangles (generated) | file MB | written in s |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    for (const SceneSpec& s : specs) {
        const fs::path path = bench.dir / (s.name + ".ma");
        files[s.name] = path;
        double seconds = 0;
        if (!upToDate(path, s)) {
            const auto t0 = std::chrono::steady_clock::now();
            if (!writeMa(s, path)) {
                std::fprintf(stderr, "cannot write %s\n", path.c_str());
                return 1;
            }
            seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        std::string stored = "–";
        if (s.terrain) stored = std::to_string(s.terrain->quads) + "² quad terrain";
        if (s.wall) stored = std::to_string(s.wall->subdivisions) + "² polyPlane wall";
        std::printf("| %s | %zu | %zu | %s | %llu | %.1f | %s |\n", s.name.c_str(), s.count(Kind::NurbsSphere),
                    s.count(Kind::PolySphere), stored.c_str(), (unsigned long long)s.triangles(),
                    double(fs::file_size(path)) / 1e6, seconds > 0 ? formatNumber("%.1f", seconds).c_str() : "reused");
    }
    std::printf("\n");

    struct Binary {
        std::string label;
        fs::path path;
        bool primary;
    };
    std::vector<Binary> binaries = {{pushpin.filename().string(), pushpin, true}};
    if (baseline) {
        std::string label = baseline->filename().string();
        if (label == binaries[0].label) label += " (baseline)";
        binaries.push_back({label, *baseline, false});
    }

    std::vector<Measurement> rows;
    auto progress = [](const Measurement& m) {
        std::fprintf(stderr, "  %s %s -n %d %s: exit %d, %.1f s, %.0f MB%s%s\n", m.binary.c_str(), m.scene.c_str(),
                     m.threads, m.capMB ? ("-mm " + std::to_string(m.capMB)).c_str() : "uncapped", m.exitCode,
                     m.median(), m.peakMB(), m.error.empty() ? "" : ": ", m.error.c_str());
    };
    auto find = [&rows](const std::string& binary, const std::string& scene, int threads, int cap) -> Measurement* {
        for (Measurement& m : rows)
            if (m.binary == binary && m.scene == scene && m.threads == threads && m.capMB == cap) return &m;
        return nullptr;
    };
    for (const Binary& b : binaries) {
        std::vector<std::pair<std::string, std::vector<int>>> plan = {{"empty", {0}}};
        if (wantMixed) {
            std::vector<int> mixedCaps = {0};
            if (b.primary) mixedCaps.insert(mixedCaps.end(), caps.begin(), caps.end());
            plan.push_back({"mixed", mixedCaps});
        }
        if (wantOccluder) {
            plan.push_back({"occluder", {0}});
            plan.push_back({"occluder-wall", {0}});
        }
        for (const auto& [scene, sceneCaps] : plan)
            for (int cap : sceneCaps)
                for (int t : threadCounts) {
                    rows.push_back(bench.pushpin(b.label, b.path, scene, files[scene], t, cap));
                    progress(rows.back());
                }
    }
    if (blender && wantMixed)
        for (int t : threadCounts) {
            rows.push_back(bench.blender(*blender, mixed, t));
            progress(rows.back());
        }

    // Image comparisons: a capped render against the uncapped one with the same threads; an
    // uncapped render with more threads against the first thread count's; the baseline binary's
    // against the primary binary's same configuration.
    const std::string primary = binaries[0].label;
    for (Measurement& m : rows) {
        if (m.binary == "blender cycles" || !m.ok() || m.image.empty()) continue;
        Measurement* ref = nullptr;
        std::string what;
        if (m.capMB) {
            ref = find(m.binary, m.scene, m.threads, 0);
            what = "uncapped -n " + std::to_string(m.threads);
        } else if (m.binary != primary) {
            ref = find(primary, m.scene, m.threads, 0);
            what = primary;
        } else if (m.threads != threadCounts[0]) {
            ref = find(m.binary, m.scene, threadCounts[0], 0);
            what = "-n " + std::to_string(threadCounts[0]);
        }
        if (!ref || !ref->ok() || ref->image.empty()) continue;
        m.comparedWith = what;
        m.diff = compareImages(ref->image, m.image);
    }

    // Triangle counts and notes per scene, from the first successful pushpin run.
    std::printf("## Rendered triangles and notes\n\n");
    for (const SceneSpec& s : specs) {
        for (const Measurement& m : rows) {
            if (m.scene != s.name || !m.ok() || m.binary == "blender cycles") continue;
            const std::vector<std::string> notes = m.stats.notes();
            std::printf("- %s: %s of %llu triangles rendered (render.triangles, %s -n %d), %s objects of which %s outside"
                        " the view, %s skipped shapes, %zu notes\n",
                        s.name.c_str(), orDash(m.stats.render("triangles")).c_str(), (unsigned long long)s.triangles(),
                        m.binary.c_str(), m.threads, orDash(m.stats.number("images.0.objects")).c_str(),
                        orDash(m.stats.render("objectsCulledFrustum")).c_str(),
                        orDash(m.stats.number("images.0.skippedShapes")).c_str(), notes.size());
            for (size_t i = 0; i < notes.size() && i < 5; ++i) std::printf("  - note: %s\n", notes[i].c_str());
            break;
        }
    }
    std::printf("\n");

    std::printf("## Renders (%d run%s each, %ld cores)\n\n", bench.runs, bench.runs == 1 ? "" : "s",
                sysconf(_SC_NPROCESSORS_ONLN));
    std::printf("| binary | scene | threads | cap MB | exit | time s (min / median / max) | peak RSS MB | RSS − empty MB |"
                " peakCharged MB | evictions | recomputes | tiles | image |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const Measurement& m : rows) {
        std::vector<double> s = m.seconds;
        std::sort(s.begin(), s.end());
        const std::string times = s.empty() ? "–" : formatNumber("%.2f", s.front()) + " / " + formatNumber("%.2f", m.median()) + " / " + formatNumber("%.2f", s.back());
        std::string overEmpty = "–";
        if (m.scene != "empty" && m.binary != "blender cycles")
            if (const Measurement* e = find(m.binary, "empty", m.threads, 0); e && e->ok())
                overEmpty = formatNumber("%.0f", m.peakMB() - e->peakMB());
        std::printf("| %s | %s | %d | %s | %d | %s | %.0f | %s | %s | %s | %s | %s | %s |\n", m.binary.c_str(),
                    m.scene.c_str(), m.threads, m.capMB ? std::to_string(m.capMB).c_str() : "none", m.exitCode,
                    times.c_str(), m.peakMB(), overEmpty.c_str(), mb(m.stats.render("memory.peakCharged")).c_str(),
                    orDash(m.stats.render("tessellation.evicted")).c_str(),
                    orDash(m.stats.render("tessellation.recomputed")).c_str(), orDash(m.stats.tiles()).c_str(),
                    imageColumn(m).c_str());
    }
    std::printf("\n");
    for (const Measurement& m : rows) {
        if (!m.error.empty())
            std::printf("- %s %s -n %d %s: exit %d: %s\n", m.binary.c_str(), m.scene.c_str(), m.threads,
                        m.capMB ? ("-mm " + std::to_string(m.capMB)).c_str() : "uncapped", m.exitCode, m.error.c_str());
        if (m.blenderBuild)
            std::printf("- blender cycles -n %d, last run: %.1f s building the scene in Python, %.1f s in render() (BVH, render,"
                        " EXR); the rest of the wall time is start-up and exit\n",
                        m.threads, *m.blenderBuild, *m.blenderRender);
    }

    // Checks of the out-of-core goal.
    std::printf("\n## Checks\n\n");
    for (const Binary& b : binaries) {
        if (wantMixed) {
            for (int t : threadCounts) {
                const Measurement* u = find(b.label, "mixed", t, 0);
                const Measurement* e = find(b.label, "empty", t, 0);
                if (!u || !e) continue;
                for (int cap : caps) {
                    const Measurement* c = find(b.label, "mixed", t, cap);
                    if (!c) continue;
                    const double limit = e->peakMB() + cap + 64;
                    if (!c->ok()) {  // no image: time and pixels cannot be checked
                        std::printf("- %s mixed -n %d -mm %d: **FAIL**: exit %d after %.1f s at %.0f MB peak RSS (limit:"
                                    " empty %.0f + cap %d + 64 = %.0f MB); no image to time or compare\n",
                                    b.label.c_str(), t, cap, c->exitCode, c->median(), c->peakMB(), e->peakMB(), cap, limit);
                        continue;
                    }
                    std::printf("- %s mixed -n %d -mm %d: peak RSS %.0f MB ≤ empty %.0f + cap %d + 64 = %.0f MB: %s;"
                                " time %.1f s ≤ 1.5 × uncapped %.1f s: %s; image identical: %s",
                                b.label.c_str(), t, cap, c->peakMB(), e->peakMB(), cap, limit,
                                passFail(c->peakMB() <= limit), c->median(), u->median(),
                                passFail(u->ok() && c->median() <= 1.5 * u->median()), passFail(c->diff.identical));
                    // The render data the cap has to hold: what the uncapped render charges at its peak.
                    if (const std::optional<double> data = u->stats.render("memory.peakCharged"); data && u->ok())
                        std::printf("; render data (uncapped peakCharged) %.0f MB = %.1f× the cap (≥ 10×): %s",
                                    *data / 1048576.0, *data / (1048576.0 * cap), passFail(*data >= 10.0 * 1048576.0 * cap));
                    std::printf("\n");
                }
            }
            const Measurement* one = find(b.label, "mixed", 1, 0);
            const Measurement* two = find(b.label, "mixed", 2, 0);
            if (one && two && one->ok() && two->ok())
                std::printf("- %s mixed uncapped: 2 threads %.2f× faster than 1 (≥ 1.8×): %s\n", b.label.c_str(),
                            one->median() / two->median(), passFail(one->median() >= 1.8 * two->median()));
        }
        if (wantOccluder)
            for (int t : threadCounts) {
                const Measurement* o = find(b.label, "occluder", t, 0);
                const Measurement* w = find(b.label, "occluder-wall", t, 0);
                if (!o || !w || !o->ok() || !w->ok()) continue;
                std::printf("- %s occluder -n %d: %.1f s with the hidden spheres, %.1f s without: %.2f× (≤ 1.1×): %s;"
                            " skippedOccluded %s\n",
                            b.label.c_str(), t, o->median(), w->median(), o->median() / w->median(),
                            passFail(o->median() <= 1.1 * w->median()),
                            orDash(o->stats.render("tessellation.skippedOccluded")).c_str());
            }
    }
    if (baseline && wantMixed)
        for (int t : threadCounts) {
            const Measurement* now = find(binaries[0].label, "mixed", t, 0);
            const Measurement* then = find(binaries[1].label, "mixed", t, 0);
            if (!now || !then || !now->ok() || !then->ok()) continue;
            std::printf("- mixed -n %d uncapped, %s against %s: peak RSS %.0f MB ≤ half of %.0f MB: %s; time %.1f s ≤"
                        " %.1f s: %s\n",
                        t, binaries[0].label.c_str(), binaries[1].label.c_str(), now->peakMB(), then->peakMB(),
                        passFail(now->peakMB() <= 0.5 * then->peakMB()), now->median(), then->median(),
                        passFail(now->median() <= then->median()));
        }
    return 0;
}
