// Reading the render globals (reference/render-globals.md) with validation: every value that is
// not finite or out of its range falls back to Maya's default and leaves one note.
#include "core/render/render_settings.h"

#include "core/util/format.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace pushpin::render {

namespace {

// Reads the attributes of one node; kNoNode leaves every default in place.
class NodeReader {
public:
    NodeReader(scene::Evaluator& ev, scene::NodeId node, std::vector<std::string>& notes)
        : m_ev(ev), m_node(node), m_notes(notes) {
        if (node != scene::kNoNode && node < ev.graph().size()) m_name = ev.graph().node(node).name;
        else m_node = scene::kNoNode;
    }

    bool present() const { return m_node != scene::kNoNode; }
    // True when the file stores a value for the attribute or something drives it.
    bool set(const char* attr) const {
        if (!present()) return false;
        const scene::Graph& g = m_ev.graph();
        return g.value(m_node, attr) != nullptr || g.source(m_node, attr).has_value();
    }

    double real(const char* attr, double def, double lo, double hi) {
        if (!present()) return def;
        const double v = m_ev.getDouble(m_node, attr, def);
        if (std::isfinite(v) && v >= lo && v <= hi) return v;
        note(attr, util::formatNumber(v, 10) + " is out of range " + util::formatNumber(lo, 10) + ".." +
                       util::formatNumber(hi, 10),
             util::formatNumber(def, 10));
        return def;
    }
    int integer(const char* attr, int def, int lo, int hi) {
        if (!present()) return def;
        const double v = m_ev.getDouble(m_node, attr, def);
        if (std::isfinite(v) && v >= lo && v <= hi && v == std::floor(v)) return static_cast<int>(v);
        note(attr, util::formatNumber(v, 10) + " is not an integer in " + std::to_string(lo) + ".." + std::to_string(hi),
             std::to_string(def));
        return def;
    }
    bool boolean(const char* attr, bool def) {
        if (!present()) return def;
        const double v = m_ev.getDouble(m_node, attr, def ? 1.0 : 0.0);
        if (std::isfinite(v)) return v != 0.0;
        note(attr, util::formatNumber(v, 10) + " is not a boolean", def ? "on" : "off");
        return def;
    }
    std::string string(const char* attr) const {
        return present() ? m_ev.graph().getString(m_node, attr) : std::string();
    }
    void note(const std::string& attr, const std::string& problem, const std::string& replacement) {
        m_notes.push_back(m_name + "." + attr + ": " + problem + "; using " + replacement);
    }

private:
    scene::Evaluator& m_ev;
    scene::NodeId m_node;
    std::vector<std::string>& m_notes;
    std::string m_name;
};

}  // namespace

RenderSettings readRenderSettings(scene::Evaluator& ev, const scene::RenderSetup& setup,
                                  std::vector<std::string>& notes) {
    RenderSettings s;

    NodeReader res(ev, setup.resolution, notes);
    s.width = res.integer("width", s.width, 1, 32768);
    s.height = res.integer("height", s.height, 1, 32768);
    // The schema's default (1.333) is the rounded form of 4:3; a file that stores no value gets
    // the exact ratio so a default 640×480 render has square pixels.
    if (res.set("deviceAspectRatio")) s.deviceAspectRatio = res.real("deviceAspectRatio", s.deviceAspectRatio, 1e-3, 1e3);

    NodeReader q(ev, setup.renderQuality, notes);
    s.edgeAntiAliasing = q.integer("edgeAntiAliasing", s.edgeAntiAliasing, 0, 3);
    s.shadingSamples = q.integer("shadingSamples", s.shadingSamples, 1, 32);
    s.maxShadingSamples = q.integer("maxShadingSamples", s.maxShadingSamples, 1, 32);
    if (s.maxShadingSamples < s.shadingSamples) {
        q.note("maxShadingSamples", std::to_string(s.maxShadingSamples) + " is below shadingSamples",
               std::to_string(s.shadingSamples));
        s.maxShadingSamples = s.shadingSamples;
    }
    s.useMultiPixelFilter = q.boolean("useMultiPixelFilter", s.useMultiPixelFilter);
    const int pft = q.integer("pixelFilterType", s.pixelFilterType, 0, 1000);
    if (pft == 0 || pft == 2 || pft == 4 || pft == 5 || pft == 6) {
        s.pixelFilterType = pft;
    } else {
        q.note("pixelFilterType", std::to_string(pft) + " is not a supported filter (0 box, 2 triangle, 4 gaussian, "
                                                        "5 quadratic B-spline, 6 cubic B-spline)",
               std::to_string(s.pixelFilterType));
    }
    s.pixelFilterWidthX = q.real("pixelFilterWidthX", s.pixelFilterWidthX, 1.0, 3.0);
    s.pixelFilterWidthY = q.real("pixelFilterWidthY", s.pixelFilterWidthY, 1.0, 3.0);
    s.redThreshold = q.real("redThreshold", s.redThreshold, 0.0, 1.0);
    s.greenThreshold = q.real("greenThreshold", s.greenThreshold, 0.0, 1.0);
    s.blueThreshold = q.real("blueThreshold", s.blueThreshold, 0.0, 1.0);
    s.coverageThreshold = q.real("coverageThreshold", s.coverageThreshold, 0.0, 1.0);

    NodeReader rg(ev, setup.renderGlobals, notes);
    s.animation = rg.boolean("animation", s.animation);
    s.startFrame = rg.real("startFrame", s.startFrame, -1e9, 1e9);
    s.endFrame = rg.real("endFrame", s.endFrame, -1e9, 1e9);
    if (s.endFrame < s.startFrame) {
        rg.note("endFrame", util::formatNumber(s.endFrame, 10) + " is before startFrame", util::formatNumber(s.startFrame, 10));
        s.endFrame = s.startFrame;
    }
    s.byFrameStep = rg.real("byFrameStep", s.byFrameStep, 1e-6, 1e9);
    s.extensionPadding = rg.integer("extensionPadding", s.extensionPadding, 0, 32);
    s.imageFormat = rg.integer("imageFormat", s.imageFormat, 0, 1000000);
    s.imfPluginKey = rg.string("imfPluginKey");
    s.imageFilePrefix = rg.string("imageFilePrefix");
    s.outFormatControl = rg.integer("outFormatControl", s.outFormatControl, 0, 2);
    s.outFormatExt = rg.string("outFormatExt");
    s.putFrameBeforeExt = rg.boolean("putFrameBeforeExt", s.putFrameBeforeExt);
    s.periodInExt = rg.integer("periodInExt", s.periodInExt, 0, 2);
    s.gammaCorrection = rg.real("gammaCorrection", s.gammaCorrection, 1e-3, 1e3);
    s.clipFinalShadedColor = rg.boolean("clipFinalShadedColor", s.clipFinalShadedColor);
    s.jitterFinalColor = rg.boolean("jitterFinalColor", s.jitterFinalColor);
    s.composite = rg.boolean("composite", s.composite);
    s.enableDefaultLight = rg.boolean("enableDefaultLight", s.enableDefaultLight);
    s.numCpusToUse = rg.integer("numCpusToUse", s.numCpusToUse, 0, 4096);
    s.forceTileSize = rg.boolean("forceTileSize", s.forceTileSize);
    s.tileWidth = rg.integer("tileWidth", s.tileWidth, 16, 256);
    s.tileHeight = rg.integer("tileHeight", s.tileHeight, 16, 256);
    s.useRenderRegion = rg.boolean("useRenderRegion", s.useRenderRegion);
    s.left = rg.integer("left", s.left, 0, 32767);
    s.rght = rg.integer("rght", s.rght, 0, 32767);
    s.bot = rg.integer("bot", s.bot, 0, 32767);
    s.top = rg.integer("top", s.top, 0, 32767);
    if (s.useRenderRegion && (s.left > s.rght || s.bot > s.top)) {
        rg.note("useRenderRegion",
                "region left " + std::to_string(s.left) + " rght " + std::to_string(s.rght) + " bot " +
                    std::to_string(s.bot) + " top " + std::to_string(s.top) + " is empty",
                "the whole image");
        s.useRenderRegion = false;
    }
    return s;
}

MemoryCap memoryCap(const RenderSettings& settings, const char* slurmMemPerNode) {
    if (settings.maximumMemoryBytes > 0) return {settings.maximumMemoryBytes, "-mm"};
    if (slurmMemPerNode == nullptr) return {};
    // Slurm writes a plain count of MiB. Anything else (a unit suffix, a sign, a value that
    // overflows when turned into bytes) is not trusted as a cap.
    const char* end = slurmMemPerNode + std::strlen(slurmMemPerNode);
    uint64_t mebibytes = 0;
    const auto [last, error] = std::from_chars(slurmMemPerNode, end, mebibytes);
    if (error != std::errc() || last != end || mebibytes == 0 || mebibytes > (UINT64_MAX >> 20)) return {};
    return {mebibytes << 20, "$SLURM_MEM_PER_NODE"};
}

MemoryCap memoryCap(const RenderSettings& settings) {
    return memoryCap(settings, std::getenv("SLURM_MEM_PER_NODE"));
}

uint64_t memoryCapBytes(const RenderSettings& settings) { return memoryCap(settings).bytes; }

}  // namespace pushpin::render
