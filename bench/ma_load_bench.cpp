// Load throughput of scene::MaReader on a generated Maya ASCII scene holding one big polygon grid
// (default 1000 × 1000 = 1M vertices, ~2M edges, ~1M quads with UVs), written the way Maya writes
// meshes: `.vt`, `.ed`, `.fc` (polyFaces) and `.uvst[0].uvsp` in chunks of a few hundred elements.
// Prints file size, min/median/max load time and MB/s over several runs, and the peak RSS growth
// of the process during the loads next to the bytes the Graph stores (and those of the face records
// per face).
//
// With --duplicates=MIB the scene is instead MIB MiB of identical `createNode transform -n "x";`
// lines, each renamed as Maya would (x, x1, x2, …): the renaming must keep the reader's usual
// throughput, and the memory per node is printed.
//
// With --files the remaining arguments are real scenes: each is loaded `runs` times and the best
// time kept; the total throughput and time per node are printed (files that fail to load are
// counted and left out), which is the reader's usual pace on real work.
//
// Usage: ma_load_bench [--grid=N | --duplicates=MIB | --files SCENE...] [--runs=R] [--keep]
#include "core/scene/ma_reader.h"

#include <sys/resource.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using pushpin::scene::Graph;
using pushpin::scene::MaReader;

// Appends numbers with std::to_chars into a buffer flushed to the file in large blocks.
class Writer {
public:
    explicit Writer(const fs::path& path) : m_out(path, std::ios::binary) { m_buf.reserve(kFlush + 4096); }
    ~Writer() { flush(); }
    Writer& operator<<(std::string_view s) {
        m_buf.append(s);
        maybeFlush();
        return *this;
    }
    Writer& num(double v) {
        char tmp[32];
        auto r = std::to_chars(tmp, tmp + sizeof tmp, v, std::chars_format::general, 9);
        m_buf.append(tmp, size_t(r.ptr - tmp));
        m_buf.push_back(' ');
        maybeFlush();
        return *this;
    }
    Writer& num(int64_t v) {
        char tmp[24];
        auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
        m_buf.append(tmp, size_t(r.ptr - tmp));
        m_buf.push_back(' ');
        maybeFlush();
        return *this;
    }
    void flush() {
        m_out.write(m_buf.data(), std::streamsize(m_buf.size()));
        m_buf.clear();
    }

private:
    static constexpr size_t kFlush = size_t(1) << 20;
    void maybeFlush() {
        if (m_buf.size() >= kFlush) flush();
    }
    std::ofstream m_out;
    std::string m_buf;
};

std::string range(const char* attr, int64_t first, int64_t last) {
    return std::string("\tsetAttr \"") + attr + "[" + std::to_string(first) + ":" + std::to_string(last) + "]\"";
}

// Writes the grid scene; returns the number of faces.
int64_t writeGridScene(const fs::path& path, int n) {
    Writer w(path);
    const int64_t verts = int64_t(n) * n;
    const int64_t hEdges = int64_t(n) * (n - 1);  // along x, one row of n-1 per y
    const int64_t edges = 2 * hEdges;
    const int64_t faces = int64_t(n - 1) * (n - 1);
    auto vid = [n](int64_t i, int64_t j) { return j * n + i; };
    auto hEdge = [n](int64_t i, int64_t j) { return j * (n - 1) + i; };          // (i,j) → (i+1,j)
    auto vEdge = [n, hEdges](int64_t i, int64_t j) { return hEdges + j * n + i; };  // (i,j) → (i,j+1)

    w << "//Maya ASCII 2018 scene\n//Name: grid.ma\nrequires maya \"2018\";\n"
      << "currentUnit -l centimeter -a degree -t film;\nfileInfo \"application\" \"maya\";\n"
      << "createNode transform -n \"grid\";\ncreateNode mesh -n \"gridShape\" -p \"grid\";\n"
      << "\tsetAttr -k off \".v\";\n\tsetAttr \".uvst[0].uvsn\" -type \"string\" \"map1\";\n";
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);

    w << "\tsetAttr -s " << std::to_string(verts) << " \".uvst[0].uvsp\";\n";
    for (int64_t first = 0; first < verts; first += 500) {
        const int64_t last = std::min(verts, first + 500) - 1;
        w << range(".uvst[0].uvsp", first, last) << " -type \"float2\"";
        for (int64_t v = first; v <= last; ++v) {
            if ((v - first) % 6 == 0) w << "\n\t\t ";
            w.num(double(v % n) / (n - 1)).num(double(v / n) / (n - 1));
        }
        w << ";\n";
    }
    w << "\tsetAttr \".cuvs\" -type \"string\" \"map1\";\n";
    w << "\tsetAttr -s " << std::to_string(verts) << " \".vt\";\n";
    for (int64_t first = 0; first < verts; first += 166) {
        const int64_t last = std::min(verts, first + 166) - 1;
        w << range(".vt", first, last);
        for (int64_t v = first; v <= last; ++v) {
            if ((v - first) % 4 == 0) w << "\n\t\t ";
            w.num(double(v % n) * 0.1 - n * 0.05).num(jitter(rng)).num(double(v / n) * -0.1 + n * 0.05);
        }
        w << ";\n";
    }
    w << "\tsetAttr -s " << std::to_string(edges) << " \".ed\";\n";
    for (int64_t first = 0; first < edges; first += 500) {
        const int64_t last = std::min(edges, first + 500) - 1;
        w << range(".ed", first, last);
        for (int64_t e = first; e <= last; ++e) {
            if ((e - first) % 8 == 0) w << "\n\t\t";
            int64_t a, b;
            if (e < hEdges) {
                const int64_t j = e / (n - 1), i = e % (n - 1);
                a = vid(i, j), b = vid(i + 1, j);
            } else {
                const int64_t k = e - hEdges, j = k / n, i = k % n;
                a = vid(i, j), b = vid(i, j + 1);
            }
            w.num(a).num(b).num(int64_t(1));
        }
        w << ";\n";
    }
    w << "\tsetAttr -s " << std::to_string(faces) << " -ch " << std::to_string(faces * 4) << " \".fc\";\n";
    for (int64_t first = 0; first < faces; first += 500) {
        const int64_t last = std::min(faces, first + 500) - 1;
        w << range(".fc", first, last) << " -type \"polyFaces\"";
        for (int64_t f = first; f <= last; ++f) {
            const int64_t j = f / (n - 1), i = f % (n - 1);
            w << "\n\t\tf 4 ";
            w.num(hEdge(i, j)).num(vEdge(i + 1, j)).num(-hEdge(i, j + 1) - 1).num(-vEdge(i, j) - 1);
            w << "\n\t\tmu 0 4 ";
            w.num(vid(i, j)).num(vid(i + 1, j)).num(vid(i + 1, j + 1)).num(vid(i, j + 1));
        }
        w << ";\n";
    }
    w << "select -ne :initialShadingGroup;\n\tsetAttr \".ro\" yes;\n"
      << "connectAttr \"gridShape.iog\" \":initialShadingGroup.dsm\" -na;\n// End of grid.ma\n";
    return faces;
}

// Writes about `mib` MiB of `createNode transform -n "x";` lines; returns the number of lines.
int64_t writeDuplicateScene(const fs::path& path, int mib) {
    Writer w(path);
    w << "//Maya ASCII 2018 scene\n//Name: duplicates.ma\nrequires maya \"2018\";\n";
    static constexpr std::string_view kLine = "createNode transform -n \"x\";\n";
    const int64_t lines = int64_t(mib) * (int64_t(1) << 20) / int64_t(kLine.size());
    for (int64_t i = 0; i < lines; ++i) w << kLine;
    w << "// End of duplicates.ma\n";
    return lines;
}

// Writes `lines` createNode lines that each name a new node (x0, x1, …): the same nodes as the
// duplicate scene without a rename, to weigh what renaming adds.
void writeUniqueScene(const fs::path& path, int64_t lines) {
    Writer w(path);
    w << "//Maya ASCII 2018 scene\n//Name: unique.ma\nrequires maya \"2018\";\n";
    for (int64_t i = 0; i < lines; ++i) w << "createNode transform -n \"x" << std::to_string(i) << "\";\n";
    w << "// End of unique.ma\n";
}

// Loads `path`, adding the seconds the load took to `seconds`.
Graph timedLoad(const fs::path& path, std::vector<double>& seconds) {
    const auto start = std::chrono::steady_clock::now();
    Graph g = MaReader::readFile(path);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return g;
}

double peakRssMiB() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;  // Linux reports kilobytes
}

// Bytes of numbers and face records the Graph keeps for the mesh (its own, necessary copy), and
// what the same numbers and ids take unpacked (doubles, floats, 32-bit integers).
struct Payload {
    double numberBytes = 0, faceBytes = 0;
    double plainNumberBytes = 0, plainFaceBytes = 0;
    double intBytes = 0, plainIntBytes = 0;  // the numbers kept as packed integers
    size_t faces = 0;
};
Payload graphPayload(const Graph& g) {
    using pushpin::scene::Numbers;
    Payload p;
    auto add = [&](const pushpin::scene::Value& value) {
        if (auto* nums = std::get_if<Numbers>(&value)) {
            p.numberBytes += double(nums->heapBytes());
            p.plainNumberBytes += double(nums->size()) * (nums->storage() == Numbers::Storage::Doubles ? 8.0 : 4.0);
            if (nums->storage() == Numbers::Storage::Ints) {
                p.intBytes += double(nums->heapBytes());
                p.plainIntBytes += 4.0 * double(nums->size());
            }
        }
        if (auto* pf = std::get_if<std::shared_ptr<const pushpin::scene::PolyFaces>>(&value); pf && *pf) {
            const pushpin::scene::PolyFaces& faces = **pf;
            p.faceBytes += double(sizeof(pushpin::scene::PolyFaces) + faces.heapBytes());
            p.faces += faces.faceCount();
            // Unpacked: an offset per loop, and per edge its id, its uv ids and its colour id.
            double ids = double(faces.loopCount() + 1);
            for (size_t loop = 0; loop < faces.loopCount(); ++loop)
                ids += double(faces.edgeCount(loop)) * double(1 + faces.uvCount(loop) + (faces.colors(loop).empty() ? 0 : 1));
            p.plainFaceBytes += double(sizeof(pushpin::scene::PolyFaces)) + 4.0 * ids;
        }
    };
    for (const auto& node : g.nodes())
        for (const auto& [key, data] : node.attrs) {
            if (data.hasValue) add(data.value);
            for (const auto& [first, run] : data.multi.runs()) add(run.value);
        }
    return p;
}

}  // namespace

int main(int argc, char** argv) {
    int grid = 1000, runs = 5, duplicates = 0;
    bool keep = false;
    std::vector<fs::path> files;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--files") == 0) {
            for (++i; i < argc; ++i) {
                if (std::strncmp(argv[i], "--runs=", 7) == 0) runs = std::max(1, std::atoi(argv[i] + 7));
                else files.emplace_back(argv[i]);
            }
            break;
        }
        if (std::strncmp(argv[i], "--grid=", 7) == 0) grid = std::max(2, std::atoi(argv[i] + 7));
        else if (std::strncmp(argv[i], "--duplicates=", 13) == 0) duplicates = std::max(1, std::atoi(argv[i] + 13));
        else if (std::strncmp(argv[i], "--runs=", 7) == 0) runs = std::max(1, std::atoi(argv[i] + 7));
        else if (std::strcmp(argv[i], "--keep") == 0) keep = true;
        else {
            std::fprintf(stderr, "usage: %s [--grid=N | --duplicates=MIB | --files SCENE...] [--runs=R] [--keep]\n", argv[0]);
            return 2;
        }
    }
    if (!files.empty()) {
        // Warm the schema tables first, so that the first file does not pay for building them.
        (void)MaReader::readString("createNode transform -n \"warm\";\n", "warm.ma");
        double bytes = 0, seconds = 0;
        size_t nodes = 0, loaded = 0, failed = 0;
        Payload total;
        for (const fs::path& f : files) {
            std::vector<double> times;
            size_t count = 0;
            try {
                for (int r = 0; r < runs; ++r) {
                    const Graph g = timedLoad(f, times);
                    count = g.size();
                    if (r == 0) {
                        const Payload p = graphPayload(g);
                        total.numberBytes += p.numberBytes;
                        total.plainNumberBytes += p.plainNumberBytes;
                        total.faceBytes += p.faceBytes;
                        total.plainFaceBytes += p.plainFaceBytes;
                        total.faces += p.faces;
                        total.intBytes += p.intBytes;
                        total.plainIntBytes += p.plainIntBytes;
                    }
                }
            } catch (const std::exception&) {
                ++failed;
                continue;
            }
            ++loaded;
            bytes += double(fs::file_size(f));
            seconds += *std::min_element(times.begin(), times.end());
            nodes += count;
        }
        const double mib = bytes / (1024.0 * 1024.0);
        std::printf("%zu scenes loaded (%zu failed), %.1f MiB, %zu nodes: best of %d runs each, %.3f s in all, "
                    "%.1f MiB/s, %.2f us per node\n",
                    loaded, failed, mib, nodes, runs, seconds, seconds > 0 ? mib / seconds : 0.0,
                    nodes ? seconds * 1e6 / double(nodes) : 0.0);
        std::printf("stored numbers: %.2f MiB, %.2f MiB unpacked (%.2fx), of which packed integers %.2f MiB, %.2f MiB "
                    "unpacked (%.2fx); face records of %zu faces: %.2f MiB, %.2f MiB unpacked (%.2fx)\n",
                    total.numberBytes / (1024.0 * 1024.0), total.plainNumberBytes / (1024.0 * 1024.0),
                    total.numberBytes > 0 ? total.plainNumberBytes / total.numberBytes : 0.0,
                    total.intBytes / (1024.0 * 1024.0), total.plainIntBytes / (1024.0 * 1024.0),
                    total.intBytes > 0 ? total.plainIntBytes / total.intBytes : 0.0, total.faces,
                    total.faceBytes / (1024.0 * 1024.0), total.plainFaceBytes / (1024.0 * 1024.0),
                    total.faceBytes > 0 ? total.plainFaceBytes / total.faceBytes : 0.0);
        return loaded ? 0 : 1;
    }
    if (duplicates > 0) {
        const fs::path path = fs::temp_directory_path() / ("pushpin_ma_load_bench_dup" + std::to_string(duplicates) + ".ma");
        const int64_t lines = writeDuplicateScene(path, duplicates);
        const double fileMiB = double(fs::file_size(path)) / (1024.0 * 1024.0);
        std::printf("scene: %s, %lld identical createNode lines, %.1f MiB\n", path.c_str(), (long long)lines, fileMiB);
        // The same number of nodes, each named anew: what the nodes cost without renaming. The two
        // files are loaded in turn, so that both meet the machine in the same state.
        const fs::path uniquePath = fs::temp_directory_path() / ("pushpin_ma_load_bench_unique" + std::to_string(duplicates) + ".ma");
        writeUniqueScene(uniquePath, lines);
        const double rssBefore = peakRssMiB();
        std::vector<double> seconds, uniqueSeconds;
        for (int r = 0; r < runs; ++r) {
            if (timedLoad(path, seconds).find("x" + std::to_string(lines - 1)) == pushpin::scene::kNoNode) {
                std::fprintf(stderr, "the last duplicate was not renamed x%lld\n", (long long)(lines - 1));
                return 1;
            }
            (void)timedLoad(uniquePath, uniqueSeconds);
        }
        const double rssGrowth = peakRssMiB() - rssBefore;
        std::sort(seconds.begin(), seconds.end());
        std::sort(uniqueSeconds.begin(), uniqueSeconds.end());
        std::printf("load over %d runs: min %.3f s, median %.3f s; throughput best %.1f MiB/s, median %.1f MiB/s\n",
                    runs, seconds.front(), seconds[seconds.size() / 2], fileMiB / seconds.front(),
                    fileMiB / seconds[seconds.size() / 2]);
        std::printf("peak RSS growth during loads: %.1f MiB, %.0f bytes per node\n", rssGrowth,
                    rssGrowth * 1024.0 * 1024.0 / double(lines));
        const double perNodeDup = seconds[seconds.size() / 2] * 1e6 / double(lines);
        const double perNodeUnique = uniqueSeconds[uniqueSeconds.size() / 2] * 1e6 / double(lines);
        std::printf("the same %lld nodes named anew (%.1f MiB): median %.3f s; medians %.2f us per node renamed, "
                    "%.2f us per node named anew: renaming adds %.0f%%\n",
                    (long long)lines, double(fs::file_size(uniquePath)) / (1024.0 * 1024.0),
                    uniqueSeconds[uniqueSeconds.size() / 2], perNodeDup, perNodeUnique,
                    100.0 * (perNodeDup / perNodeUnique - 1.0));
        if (!keep) {
            fs::remove(path);
            fs::remove(uniquePath);
        }
        return 0;
    }
    const fs::path path = fs::temp_directory_path() / ("pushpin_ma_load_bench_" + std::to_string(grid) + ".ma");
    const auto t0 = std::chrono::steady_clock::now();
    const int64_t faces = writeGridScene(path, grid);
    const double genSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double fileMiB = double(fs::file_size(path)) / (1024.0 * 1024.0);
    std::printf("scene: %s, %d x %d grid = %lld vertices, %lld faces, %.1f MiB (written in %.2f s)\n",
                path.c_str(), grid, grid, (long long)grid * grid, (long long)faces, fileMiB, genSeconds);

    const double rssBefore = peakRssMiB();
    std::vector<double> seconds;
    Payload payload;
    for (int r = 0; r < runs; ++r) {
        const Graph g = timedLoad(path, seconds);
        if (r == 0) {
            payload = graphPayload(g);
            std::vector<double> p;
            if (!g.numbers(g.find("gridShape"), "vrts[" + std::to_string(int64_t(grid) * grid - 1) + "]", p)) {
                std::fprintf(stderr, "the last vertex was not loaded\n");
                return 1;
            }
        }
    }
    const double rssGrowth = peakRssMiB() - rssBefore;
    std::vector<double> sorted = seconds;
    std::sort(sorted.begin(), sorted.end());
    const double tMin = sorted.front(), tMed = sorted[sorted.size() / 2], tMax = sorted.back();
    std::printf("load over %d runs: min %.3f s, median %.3f s, max %.3f s\n", runs, tMin, tMed, tMax);
    std::printf("throughput: best %.1f MiB/s, median %.1f MiB/s, worst %.1f MiB/s\n", fileMiB / tMin, fileMiB / tMed,
                fileMiB / tMax);
    const double mib = 1024.0 * 1024.0;
    std::printf("peak RSS growth during loads: %.1f MiB (%.2f x file size); graph payload (numbers + face "
                "records): %.1f MiB (%.1f MiB unpacked), of which face records %.1f MiB, %.1f bytes per face "
                "(%.1f unpacked)\n",
                rssGrowth, rssGrowth / fileMiB, (payload.numberBytes + payload.faceBytes) / mib,
                (payload.plainNumberBytes + payload.plainFaceBytes) / mib, payload.faceBytes / mib,
                payload.faces ? payload.faceBytes / double(payload.faces) : 0.0,
                payload.faces ? payload.plainFaceBytes / double(payload.faces) : 0.0);
    if (!keep) fs::remove(path);
    return 0;
}
