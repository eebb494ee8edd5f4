// The pushpin command line (reference/render-cli.md): parsing with every value validated where it
// is read, and the mapping of Render's flags onto the render globals.
#include "core/render/command_line.h"

#include "core/util/format.h"

#include "cache/error.h"
#include "core/render/image_output.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>

namespace pushpin::render {

namespace {

enum class Kind { Int, Float, Bool, String, Eaa, Pft, Fnc, Format, Region };

struct FlagSpec {
    const char* flag;
    Kind kind;
    double lo = 0, hi = 0;  // inclusive range for Int and Float
};

constexpr double kFrameLimit = 1e9;

// The render-globals flags. Ranges follow render-globals.md (and render-cli.md for -tw/-th).
const FlagSpec kOverrideFlags[] = {
    {"-im", Kind::String},       {"-p", Kind::String},          {"-of", Kind::Format},
    {"-fnc", Kind::Fnc},         {"-pad", Kind::Int, 0, 32},    {"-s", Kind::Float, -kFrameLimit, kFrameLimit},
    {"-e", Kind::Float, -kFrameLimit, kFrameLimit},             {"-b", Kind::Float, 1e-6, kFrameLimit},
    {"-x", Kind::Int, 1, 32768}, {"-y", Kind::Int, 1, 32768},   {"-reg", Kind::Region},
    {"-eaa", Kind::Eaa},         {"-ss", Kind::Int, 1, 32},     {"-mss", Kind::Int, 1, 32},
    {"-ufil", Kind::Bool},       {"-pft", Kind::Pft},           {"-pfx", Kind::Float, 1, 3},
    {"-pfy", Kind::Float, 1, 3}, {"-rct", Kind::Float, 0, 1},   {"-gct", Kind::Float, 0, 1},
    {"-bct", Kind::Float, 0, 1}, {"-cct", Kind::Float, 0, 1},   {"-g", Kind::Float, 1e-3, 1e3},
    {"-n", Kind::Int, 0, 4096},  {"-tw", Kind::Int, 16, 256},   {"-th", Kind::Int, 16, 256},
    {"-premul", Kind::Bool},     {"-rgb", Kind::Bool},          {"-alpha", Kind::Bool},
    {"-depth", Kind::Bool},      {"-ard", Kind::Float, 1e-3, 1e3}, {"-mm", Kind::Int, 1, 16777216},
};

// Render flags for what pushpin does not render yet (reference/render-cli.md), by the feature
// they belong to. Switch: a boolean that turns the feature itself on or off. Kinds: None (no
// argument), OptionalBool (a boolean may follow), Word (any one argument).
enum class ArgKind { None, OptionalBool, Bool, Int, Float, Word };
struct NotAppliedSpec {
    const char* flag;
    ArgKind arg;
    const char* feature;
    bool isSwitch = false;
};
const NotAppliedSpec kNotAppliedFlags[] = {
    {"-ert", ArgKind::Bool, "ray tracing", true},
    {"-rfl", ArgKind::Int, "ray tracing"},
    {"-rfr", ArgKind::Int, "ray tracing"},
    {"-sl", ArgKind::Int, "ray tracing"},
    {"-mb", ArgKind::Bool, "motion blur", true},
    {"-mbf", ArgKind::Float, "motion blur"},
    {"-sa", ArgKind::Float, "motion blur"},
    {"-mb2d", ArgKind::Bool, "motion blur"},
    {"-bll", ArgKind::Float, "motion blur"},
    {"-bls", ArgKind::Float, "motion blur"},
    {"-smv", ArgKind::Int, "motion blur"},
    {"-smc", ArgKind::Bool, "motion blur"},
    {"-kmv", ArgKind::Bool, "motion blur"},
    {"-mvs", ArgKind::Int, "motion blur"},
    {"-mvm", ArgKind::Int, "motion blur"},
    {"-edm", ArgKind::Bool, "depth-map shadows", true},
    {"-sp", ArgKind::Bool, "depth-map shadows"},
    {"-rut", ArgKind::Bool, "depth-map shadows"},
    {"-iip", ArgKind::None, "image planes"},
    {"-pss", ArgKind::Int, "particles and strokes"},
    {"-vs", ArgKind::Int, "fog and volume shaders"},
    {"-udb", ArgKind::Bool, "displacement"},
    {"-rl", ArgKind::Word, "render layers other than the default"},
    {"-rp", ArgKind::Word, "render passes"},
    {"-rs", ArgKind::Bool, "render layers other than the default"},
    {"-l", ArgKind::Word, "display layers"},
    {"-sel", ArgKind::Word, "rendering a selection of objects"},
    {"-field", ArgKind::Bool, "field rendering"},
    {"-pal", ArgKind::None, "field rendering"},
    {"-ntsc", ArgKind::None, "field rendering"},
    {"-ifg", ArgKind::Bool, "film gate"},
    {"-par", ArgKind::Float, "pixel aspect ratio"},
    {"-ar", ArgKind::Float, "pixel aspect ratio"},
    {"-percentRes", ArgKind::Float, "resolution scaling"},
    {"-xl", ArgKind::Int, "old-style render region"},
    {"-xr", ArgKind::Int, "old-style render region"},
    {"-yl", ArgKind::Int, "old-style render region"},
    {"-yh", ArgKind::Int, "old-style render region"},
    {"-uf", ArgKind::Bool, "tessellation caches"},
    {"-oi", ArgKind::Bool, "tessellation caches"},
    {"-premulthr", ArgKind::Float, "premultiply threshold"},
    {"-rfs", ArgKind::Int, "frame renumbering"},
    {"-rfb", ArgKind::Int, "frame renumbering"},
    {"-se", ArgKind::Int, "frame renumbering"},
    {"-be", ArgKind::Int, "frame renumbering"},
    {"-me", ArgKind::Bool, "image names with the scene or format name"},
    {"-mf", ArgKind::Bool, "image names with the scene or format name"},
    {"-skipExistingFrames", ArgKind::Bool, "skipping frames already on disk"},
    {"-rep", ArgKind::OptionalBool, "keeping existing images (-rep)"},
    {"-amt", ArgKind::OptionalBool, "aborting on a missing texture"},
    {"-ipr", ArgKind::OptionalBool, "IPR files"},
    {"-keepPreImage", ArgKind::OptionalBool, "pre-post-process images"},
    {"-log", ArgKind::Word, "log files"},
    {"-verb", ArgKind::None, "MEL scripts"},
    {"-test", ArgKind::None, "MEL scripts"},
    {"-keepMel", ArgKind::None, "MEL scripts"},
    {"-preRender", ArgKind::Word, "MEL scripts"},
    {"-postRender", ArgKind::Word, "MEL scripts"},
    {"-preLayer", ArgKind::Word, "MEL scripts"},
    {"-postLayer", ArgKind::Word, "MEL scripts"},
    {"-preFrame", ArgKind::Word, "MEL scripts"},
    {"-postFrame", ArgKind::Word, "MEL scripts"},
    {"-pre", ArgKind::Word, "MEL scripts"},
    {"-post", ArgKind::Word, "MEL scripts"},
    {"-listRenderers", ArgKind::None, "listing renderers"},
    {"-rst", ArgKind::Word, "render-setup templates"},
    {"-rsp", ArgKind::Word, "render-setup templates"},
    {"-rsa", ArgKind::Word, "render-setup templates"},
    {"-cont", ArgKind::None, "continuing after errors (-cont)"},
    {"-verbose", ArgKind::Bool, "verbose output (-verbose)"},
};

const NotAppliedSpec* notAppliedSpec(std::string_view flag) {
    for (const NotAppliedSpec& f : kNotAppliedFlags)
        if (flag == f.flag) return &f;
    return nullptr;
}

const FlagSpec* overrideSpec(std::string_view flag) {
    for (const FlagSpec& f : kOverrideFlags)
        if (flag == f.flag) return &f;
    return nullptr;
}

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

[[noreturn]] void bad(std::string_view flag, std::string_view value, const std::string& why) {
    throw UsageError(std::string(flag) + ": '" + util::excerpt(value) + "' " + why);
}

long long parseInt(std::string_view flag, std::string_view text, double lo, double hi) {
    long long v = 0;
    const char* begin = text.data();
    if (!text.empty() && text.front() == '+') ++begin;
    auto [ptr, ec] = std::from_chars(begin, text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || ptr != text.data() + text.size()) bad(flag, text, "is not an integer");
    if (v < lo || v > hi)
        bad(flag, text, "is out of range (" + util::formatNumber(lo) + ".." + util::formatNumber(hi) + ")");
    return v;
}

double parseFloat(std::string_view flag, std::string_view text, double lo, double hi) {
    double v = 0;
    const char* begin = text.data();
    if (!text.empty() && text.front() == '+') ++begin;
    auto [ptr, ec] = std::from_chars(begin, text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(v))
        bad(flag, text, "is not a finite number");
    if (v < lo || v > hi)
        bad(flag, text, "is out of range (" + util::formatNumber(lo) + ".." + util::formatNumber(hi) + ")");
    return v;
}

// Whether `text` is a boolean word; its value in `out`.
bool boolWord(std::string_view text, bool& out) {
    const std::string t = lower(text);
    if (t == "on" || t == "yes" || t == "true" || t == "1") return out = true, true;
    if (t == "off" || t == "no" || t == "false" || t == "0") return out = false, true;
    return false;
}

bool parseBool(std::string_view flag, std::string_view text) {
    bool value = false;
    if (!boolWord(text, value)) bad(flag, text, "is not a boolean (on/yes/true/1 or off/no/false/0)");
    return value;
}

int parseEaa(std::string_view flag, std::string_view text) {
    const std::string t = lower(text);
    if (t == "highest") return 0;
    if (t == "high") return 1;
    if (t == "medium") return 2;
    if (t == "low") return 3;
    long long v = 0;
    auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || v < 0 || v > 3)
        bad(flag, text, "is not an edge anti-aliasing level (0..3 or highest/high/medium/low)");
    return static_cast<int>(v);
}

int parsePft(std::string_view flag, std::string_view text) {
    const std::string t = lower(text);
    if (t == "box") return 0;
    if (t == "triangle") return 2;
    if (t == "gaussian") return 4;
    if (t == "quadraticbspline") return 5;
    if (t == "cubicbspline") return 6;
    if (t == "plugin") bad(flag, text, "is not supported: pushpin has no plug-in pixel filters");
    long long v = -1;
    auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() ||
        !(v == 0 || v == 2 || v == 4 || v == 5 || v == 6))
        bad(flag, text,
            "is not a pixel filter (0 box, 2 triangle, 4 gaussian, 5 quadraticbspline, 6 cubicbspline)");
    return static_cast<int>(v);
}

// The file-name conventions of render-cli.md, numbered 1..9 in that order.
const char* const kConventions[] = {"name",  "name.ext",  "name.#.ext", "name.ext.#", "name.#",
                                    "name#.ext", "name_#.ext", "namec",   "namec.ext"};

int parseFnc(std::string_view flag, std::string_view text) {
    int index = 0;
    const std::string t = lower(text);
    for (int i = 0; i < 9; ++i)
        if (t == kConventions[i]) index = i + 1;
    if (index == 0) {
        long long v = 0;
        auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (!text.empty() && ec == std::errc() && ptr == text.data() + text.size() && v >= 1 && v <= 9)
            index = static_cast<int>(v);
    }
    if (index == 0)
        bad(flag, text,
            "is not a file name convention (1..7 or name, name.ext, name.#.ext, name.ext.#, name.#, name#.ext, "
            "name_#.ext)");
    if (index >= 8) bad(flag, text, "is a movie convention; pushpin writes one image per frame");
    return index;
}

bool isOption(std::string_view a) { return !a.empty() && a[0] == '-'; }

}  // namespace

CommandLine parseCommandLine(const std::vector<std::string_view>& args) {
    CommandLine cl;
    std::optional<long long> ss, mss;
    std::optional<double> start, end;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        auto value = [&]() -> std::string_view {
            if (i + 1 >= args.size()) throw UsageError(util::excerpt(a) + " needs a value");
            return args[++i];
        };
        if (a == "-h" || a == "--help" || a == "-help") {
            cl.help = true;
        } else if (a == "--version") {
            cl.version = true;
        } else if (a == "--info") {
            cl.info = true;
        } else if (a == "--demo") {
            cl.demo = true;
        } else if (a == "--print-demo") {
            cl.printDemo = true;
        } else if (a == "--no-references") {
            cl.loadReferences = false;
        } else if (a == "--quiet") {
            cl.quiet = true;
        } else if (a == "--allow-scene-output-paths") {
            cl.allowSceneOutputPaths = true;
        } else if (a == "--frame") {
            const std::string_view v = value();
            cl.frame = parseFloat(a, v, -kFrameLimit, kFrameLimit);
        } else if (a == "--stats") {
            const std::string_view v = value();
            if (v.empty()) bad(a, v, "is not a file name");
            cl.statsPath = std::string(v);
        } else if (a == "--tile-pattern") {
            const std::string_view v = value();
            if (v.empty()) bad(a, v, "is not a file name");
            cl.tilePatternPath = std::string(v);
        } else if (a == "-cam") {
            const std::string_view v = value();
            if (v.empty()) bad(a, v, "is not a camera name");
            cl.cameras.emplace_back(v);
        } else if (a == "-rd") {
            const std::string_view v = value();
            if (v.empty()) bad(a, v, "is not a folder");
            cl.outputDir = std::string(v);
        } else if (a == "-r" || a == "-renderer") {
            const std::string_view v = value();
            if (v != "sw")
                bad(a, v, "is not supported: pushpin is the Maya Software renderer (-r sw)");
        } else if (const FlagSpec* spec = overrideSpec(a)) {
            std::string text;
            if (spec->kind == Kind::Region) {
                if (i + 4 >= args.size()) throw UsageError(std::string(a) + " needs 4 values (left right bottom top)");
                long long r[4];
                for (int k = 0; k < 4; ++k) r[k] = parseInt(a, args[++i], 0, 32767);
                if (r[0] > r[1]) bad(a, std::to_string(r[0]) + " " + std::to_string(r[1]), "has left after right");
                if (r[2] > r[3]) bad(a, std::to_string(r[2]) + " " + std::to_string(r[3]), "has bottom above top");
                text = std::to_string(r[0]) + " " + std::to_string(r[1]) + " " + std::to_string(r[2]) + " " +
                       std::to_string(r[3]);
            } else {
                const std::string_view v = value();
                switch (spec->kind) {
                    case Kind::Int: {
                        const long long n = parseInt(a, v, spec->lo, spec->hi);
                        if (a == "-ss") ss = n;
                        if (a == "-mss") mss = n;
                        text = std::to_string(n);
                        break;
                    }
                    case Kind::Float: {
                        const double x = parseFloat(a, v, spec->lo, spec->hi);
                        if (a == "-s") start = x;
                        if (a == "-e") end = x;
                        text = util::formatNumber(x);
                        break;
                    }
                    case Kind::Bool: text = parseBool(a, v) ? "1" : "0"; break;
                    case Kind::String:
                        if (v.empty()) bad(a, v, "is not an image name");
                        text = std::string(v);
                        break;
                    case Kind::Eaa: text = std::to_string(parseEaa(a, v)); break;
                    case Kind::Pft: text = std::to_string(parsePft(a, v)); break;
                    case Kind::Fnc: text = std::to_string(parseFnc(a, v)); break;
                    case Kind::Format:
                        try {
                            (void)imageFormatCodeFromName(v);
                        } catch (const Error& e) {
                            throw UsageError(std::string(a) + ": " + e.what());
                        }
                        text = lower(v);
                        break;
                    case Kind::Region: break;
                }
            }
            cl.overrides.push_back({std::string(a), std::move(text)});
        } else if (a == "-proj") {
            const std::string_view v = value();
            if (v.empty()) bad(a, v, "is not a folder");
            cl.project = std::string(v);
        } else if (a == "-iw" || a == "-ih") {
            // The old names of -x and -y.
            cl.overrides.push_back({a == "-iw" ? "-x" : "-y", std::to_string(parseInt(a, value(), 1, 32768))});
        } else if (const NotAppliedSpec* na = notAppliedSpec(a)) {
            std::string given(a);
            bool on = true;
            switch (na->arg) {
                case ArgKind::None: break;
                case ArgKind::OptionalBool:
                    if (bool ignored = false; i + 1 < args.size() && boolWord(args[i + 1], ignored))
                        given += " " + std::string(args[++i]);
                    break;
                case ArgKind::Bool: {
                    const std::string_view v = value();
                    on = parseBool(a, v);
                    given += std::string(" ") + (on ? "on" : "off");
                    break;
                }
                case ArgKind::Int: given += " " + std::to_string(parseInt(a, value(), -1e9, 1e9)); break;
                case ArgKind::Float: given += " " + util::formatNumber(parseFloat(a, value(), -1e9, 1e9)); break;
                case ArgKind::Word: {
                    const std::string_view v = value();
                    if (v.empty()) bad(a, v, "is empty");
                    given += " " + util::excerpt(v);
                    break;
                }
            }
            if (na->isSwitch) cl.featureSwitches.push_back({na->feature, std::move(given), on});
            else if (std::string_view(na->flag) == "-iip") cl.featureSwitches.push_back({na->feature, std::move(given), false});
            else cl.notApplied.push_back({na->feature, std::move(given)});
        } else if (isOption(a)) {
            throw UsageError("unknown option '" + util::excerpt(a) + "' (see pushpin --help)");
        } else {
            if (!cl.scene.empty())
                throw UsageError("more than one scene given: '" + util::excerpt(cl.scene) + "' and '" + util::excerpt(a) +
                                 "'");
            cl.scene = std::string(a);
        }
    }
    if (ss && mss && *mss < *ss)
        throw UsageError("-mss: '" + std::to_string(*mss) + "' is less than -ss " + std::to_string(*ss));
    if (start && end && *end < *start)
        throw UsageError("-e: '" + util::formatNumber(*end) + "' is before -s " + util::formatNumber(*start));
    return cl;
}

void applyOverrides(const CommandLine& commandLine, RenderSettings& s) {
    // Render keeps the pixel aspect when only the resolution changes: -x/-y without -ard give
    // deviceAspectRatio = pixelAspect · width / height with the scene's pixel aspect.
    const double pixelAspect = s.deviceAspectRatio * s.height / s.width;
    bool sizeGiven = false, aspectGiven = false, startGiven = false, endGiven = false;
    for (const CommandLine::Override& o : commandLine.overrides) {
        const std::string& f = o.flag;
        const std::string& v = o.value;
        auto asInt = [&] { return static_cast<int>(std::stoll(v)); };
        auto asDouble = [&] { return std::stod(v); };
        auto asBool = [&] { return v == "1"; };
        if (f == "-im" || f == "-p") s.imageFilePrefix = v;
        else if (f == "-of") {
            const ImageFormatCode code = imageFormatCodeFromName(v);
            s.imageFormat = code.imageFormat;
            s.imfPluginKey = code.imfPluginKey;
        } else if (f == "-fnc") {
            // render-globals.md, "File-name convention ↔ attributes".
            switch (asInt()) {
                case 1: s.animation = false; s.outFormatControl = 1; break;
                case 2: s.animation = false; s.outFormatControl = 0; break;
                case 3: s.animation = true; s.outFormatControl = 0; s.putFrameBeforeExt = true; s.periodInExt = 1; break;
                case 4: s.animation = true; s.outFormatControl = 0; s.putFrameBeforeExt = false; s.periodInExt = 1; break;
                case 5: s.animation = true; s.outFormatControl = 1; s.periodInExt = 1; break;
                case 6: s.animation = true; s.outFormatControl = 0; s.putFrameBeforeExt = true; s.periodInExt = 0; break;
                case 7: s.animation = true; s.outFormatControl = 0; s.putFrameBeforeExt = true; s.periodInExt = 2; break;
                default: break;
            }
        } else if (f == "-pad") s.extensionPadding = asInt();
        else if (f == "-s") { s.startFrame = asDouble(); s.animation = true; startGiven = true; }
        else if (f == "-e") { s.endFrame = asDouble(); s.animation = true; endGiven = true; }
        else if (f == "-b") { s.byFrameStep = asDouble(); s.animation = true; }
        else if (f == "-x") { s.width = asInt(); sizeGiven = true; }
        else if (f == "-y") { s.height = asInt(); sizeGiven = true; }
        else if (f == "-ard") { s.deviceAspectRatio = asDouble(); aspectGiven = true; }
        else if (f == "-reg") {
            std::istringstream in(v);
            in >> s.left >> s.rght >> s.bot >> s.top;
            s.useRenderRegion = true;
        } else if (f == "-eaa") s.edgeAntiAliasing = asInt();
        else if (f == "-ss") s.shadingSamples = asInt();
        else if (f == "-mss") s.maxShadingSamples = asInt();
        else if (f == "-ufil") s.useMultiPixelFilter = asBool();
        else if (f == "-pft") s.pixelFilterType = asInt();
        else if (f == "-pfx") s.pixelFilterWidthX = asDouble();
        else if (f == "-pfy") s.pixelFilterWidthY = asDouble();
        else if (f == "-rct") s.redThreshold = asDouble();
        else if (f == "-gct") s.greenThreshold = asDouble();
        else if (f == "-bct") s.blueThreshold = asDouble();
        else if (f == "-cct") s.coverageThreshold = asDouble();
        else if (f == "-g") s.gammaCorrection = asDouble();
        else if (f == "-n") s.numCpusToUse = asInt();
        else if (f == "-tw") { s.tileWidth = asInt(); s.forceTileSize = true; }
        else if (f == "-th") { s.tileHeight = asInt(); s.forceTileSize = true; }
        // -premul on asks for colour premultiplied over black, i.e. not composite rendering;
        // -premul off asks for composite rendering (render-globals.md: UI "Premultiply" = !composite).
        else if (f == "-premul") s.composite = !asBool();
        else if (f == "-rgb") s.image = asBool();
        else if (f == "-alpha") s.mask = asBool();
        else if (f == "-depth") s.depth = asBool();
        // -mm is the render's memory cap, never the scene's maximumMemory (render_settings.h).
        else if (f == "-mm") s.maximumMemoryBytes = uint64_t(std::stoll(v)) << 20;
    }
    if (sizeGiven && !aspectGiven && std::isfinite(pixelAspect) && pixelAspect > 0)
        s.deviceAspectRatio = pixelAspect * s.width / s.height;
    // A range flag that crosses the scene's other end moves that end along with it.
    if (s.endFrame < s.startFrame) {
        if (startGiven && !endGiven) s.endFrame = s.startFrame;
        else s.startFrame = s.endFrame;
    }
    if (s.maxShadingSamples < s.shadingSamples) s.maxShadingSamples = s.shadingSamples;
}

std::string commandLineHelp() {
    return R"(usage: pushpin [options] [-r sw] [render flags] scene.ma
       pushpin --demo [options] [render flags]

pushpin renders Maya ASCII scenes the way the Maya Software renderer does. Render flags take
the names of Maya's `Render -r sw`; each overrides the value stored in the scene. Flags and
their values are separate words. Booleans take on/yes/true/1 or off/no/false/0.

pushpin options:
  -h, -help, --help   show this help
  --version           print the version
  --info              print a JSON report of the scene instead of rendering
  --demo              use the built-in demo scene instead of a file
  --print-demo        write the demo scene's .ma text to stdout
  --no-references     do not load referenced files (file -r)
  --frame F           render (or report) frame F only; overrides -s/-e/-b
  --stats FILE        write render statistics as JSON to FILE
  --tile-pattern FILE draw the first image's tile plan, each tile coloured by its cost
  --quiet             no progress lines on stderr
  --allow-scene-output-paths
                      let an image prefix (the scene's imageFilePrefix or -im) put images
                      outside the output folder: an absolute path, or one climbing out with ..

renderer:
  -r sw               the Maya Software renderer (the only one; other names are refused)

cameras and output:
  -cam NAME           render this camera (repeatable); without -cam the renderable cameras
  -rd DIR             output folder (default: the images folder of the -proj project, else of
                      the Maya project holding the scene, found by its workspace.mel, else
                      the current folder)
  -proj DIR           the Maya project: images go to its images folder (its workspace.mel
                      rule, else DIR/images) unless -rd is given
  -im NAME, -p NAME   image file prefix (imageFilePrefix); tokens <Scene> <Camera> <RenderLayer>;
                      a relative path inside the output folder (.. may not leave it)
  -of FORMAT          image format: iff, iff16/maya16, tif/tiff, tif16/tiff16, sgi/rgb, sgi16,
                      jpg/jpeg, png, tga/targa, bmp, gif, rla, exr, hdr
  -fnc CONV           file name convention: 1 name, 2 name.ext, 3 name.#.ext, 4 name.ext.#,
                      5 name.#, 6 name#.ext, 7 name_#.ext (number or name)
  -pad N              frame number padding, 0..32 (extensionPadding)
  -s F, -e F, -b F    first frame, last frame, frame step (turn animation on)
  -rgb BOOL           write colour (camera image)
  -alpha BOOL         write alpha (camera mask)
  -depth BOOL         write depth (camera depth): a Z channel in EXR, else NAME_depth.exr
  -g GAMMA            gamma correction (gammaCorrection), 0.001..1000
  -premul BOOL        premultiply colour by alpha over black (on = composite off)

resolution:
  -x N, -y N          image width and height in pixels, 1..32768 (keeps the pixel aspect
                      unless -ard is given)
  -ard RATIO          device aspect ratio (deviceAspectRatio)
  -reg L R B T        render region in pixels: left right bottom top, y from the bottom

anti-aliasing and sampling (defaultRenderQuality):
  -eaa Q              edge anti-aliasing: 0 highest, 1 high, 2 medium, 3 low (or the words)
  -ss N               shading samples, 1..32
  -mss N              maximum adaptive shading samples, 1..32, at least -ss
  -ufil BOOL          multi-pixel filter
  -pft F              pixel filter: 0 box, 2 triangle, 4 gaussian, 5 quadraticbspline,
                      6 cubicbspline (pushpin's 3x3 cubic B-spline)
  -pfx W, -pfy W      pixel filter width in pixels, 1..3
  -rct -gct -bct T    red/green/blue contrast thresholds, 0..1
  -cct T              coverage contrast threshold, 0..1

performance:
  -n N                threads, 0 = all cores (numCpusToUse)
  -tw N, -th N        force the tile width/height, 16..256 pixels
  -mm MB              memory cap in MiB (default $SLURM_MEM_PER_NODE, else none): unused
                      tessellations are dropped and made again to stay under it; a frame
                      that cannot fit stops with exit 33 and writes no image

accepted, not rendered yet (each is reported once and listed under notRendered in --stats):
  ray tracing         -ert BOOL (off leaves nothing out), -rfl N, -rfr N, -sl N
  motion blur         -mb BOOL (off leaves nothing out), -mbf -sa -mb2d -bll -bls -smv -smc
                      -kmv -mvs -mvm
  depth-map shadows   -edm BOOL (off leaves nothing out), -sp BOOL, -rut BOOL
  image planes        -iip (ignore them: leaves nothing out)
  other features      -pss -vs -udb -rl -rp -rs -l -sel -field -pal -ntsc -ifg -par -ar
                      -percentRes -xl -xr -yl -yh -uf -oi -premulthr
  output and runs     -rfs -rfb -se -be -me -mf -skipExistingFrames -rep -amt -ipr
                      -keepPreImage -log FILE -verb -test -keepMel -listRenderers -rst
                      -rsp -rsa -cont -verbose
  MEL callbacks       -preRender -postRender -preLayer -postLayer -preFrame -postFrame
                      -pre -post (never run)
  -iw N, -ih N        the old names of -x and -y (applied)

exit status:
  0    every frame written            1    scene or input error (do not retry)
  2    usage error (do not retry)     33   over the memory cap (retry with more memory)
  75   an image could not be written (full disk, I/O error): retry; nothing partial is left
  130, 143  stopped by SIGINT, SIGTERM; temporary files are removed
Errors are one line on stderr starting "Error: ". A sequence stops at the first frame that
cannot be written.
)";
}

}  // namespace pushpin::render
