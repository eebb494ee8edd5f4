// Output formats, Maya's image file naming (reference/render-globals.md) and the atomic frame
// write through OpenImageIO.
#include "core/render/image_output.h"

#include "cache/error.h"

#include <OpenImageIO/imageio.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <mutex>

namespace pushpin::render {

namespace {

namespace fs = std::filesystem;

struct FormatEntry {
    int code;             // Maya's imageFormat (outf)
    const char* oiio;     // OpenImageIO writer; nullptr: no writer for this format
    const char* ext;
    bool floatPixels;
    int bits;
    const char* label;    // for messages
};

// Maya's outf codes (render-globals.md "imageFormat (outf) codes"). Movie formats and formats
// OpenImageIO has no writer for carry oiio == nullptr.
constexpr FormatEntry kFormats[] = {
    {0, "gif", "gif", false, 8, "GIF"},
    {1, nullptr, "si", false, 8, "SoftImage"},
    {2, "rla", "rla", false, 8, "Wavefront RLA"},
    {3, "tiff", "tif", false, 8, "TIFF"},
    {4, "tiff", "tif", false, 16, "TIFF16"},
    {5, "sgi", "sgi", false, 8, "SGI"},
    {6, nullptr, "pix", false, 8, "Alias PIX"},
    {7, "iff", "iff", false, 8, "Maya IFF"},
    {8, "jpeg", "jpg", false, 8, "JPEG"},
    {9, nullptr, "eps", false, 8, "EPS"},
    {10, "iff", "iff", false, 16, "Maya16 IFF"},
    {11, nullptr, "cin", false, 8, "Cineon"},
    {12, nullptr, "yuv", false, 8, "Quantel"},
    {13, "sgi", "sgi", false, 16, "SGI16"},
    {19, "targa", "tga", false, 8, "Targa"},
    {20, "bmp", "bmp", false, 8, "Windows BMP"},
    {21, nullptr, "", false, 8, "SGI Movie (a movie format)"},
    {22, nullptr, "", false, 8, "QuickTime (a movie format)"},
    {23, nullptr, "", false, 8, "AVI (a movie format)"},
    {30, nullptr, "", false, 8, "MacPaint"},
    {31, nullptr, "psd", false, 8, "PSD"},
    {32, "png", "png", false, 8, "PNG"},
    {33, nullptr, "", false, 8, "QuickDraw"},
    {34, nullptr, "", false, 8, "QuickTime image"},
    {35, nullptr, "dds", false, 8, "DDS"},
    {36, nullptr, "psd", false, 8, "PSD layered"},
    {40, "openexr", "exr", true, 32, "OpenEXR"},
};

struct NameEntry {
    const char* name;
    int code;          // index into kFormats by code; 51: a plug-in key with its own writer below
    const char* key;   // imfPluginKey for codes 40/51
};

// -of keywords (render-cli.md) and imfPluginKey values.
constexpr NameEntry kNames[] = {
    {"gif", 0, ""},       {"si", 1, ""},        {"soft", 1, ""},       {"softimage", 1, ""},
    {"rla", 2, ""},       {"wave", 2, ""},      {"wavefront", 2, ""},  {"tiff", 3, ""},
    {"tif", 3, ""},       {"tiff16", 4, ""},    {"tif16", 4, ""},      {"sgi", 5, ""},
    {"rgb", 5, ""},       {"alias", 6, ""},     {"als", 6, ""},        {"pix", 6, ""},
    {"iff", 7, ""},       {"tdi", 7, ""},       {"explore", 7, ""},    {"maya", 7, ""},
    {"jpeg", 8, ""},      {"jpg", 8, ""},       {"eps", 9, ""},        {"maya16", 10, ""},
    {"iff16", 10, ""},    {"cineon", 11, ""},   {"cin", 11, ""},       {"fido", 11, ""},
    {"qtl", 12, ""},      {"quantel", 12, ""},  {"sgi16", 13, ""},     {"rgb16", 13, ""},
    {"tga", 19, ""},      {"targa", 19, ""},    {"bmp", 20, ""},       {"avi", 23, ""},
    {"qt", 22, ""},       {"quicktime", 22, ""}, {"mov", 22, ""},      {"psd", 31, ""},
    {"png", 32, ""},      {"dds", 35, ""},      {"exr", 40, "exr"},    {"openexr", 40, "exr"},
    {"hdr", 51, "hdr"},
};

const FormatEntry* formatByCode(int code) {
    for (const FormatEntry& f : kFormats)
        if (f.code == code) return &f;
    return nullptr;
}

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

const NameEntry* nameEntry(std::string_view name) {
    const std::string key = lower(name);
    for (const NameEntry& n : kNames)
        if (key == n.name) return &n;
    return nullptr;
}

// Whether this OpenImageIO build can create a writer for `oiioName` (asked once per name).
bool writerAvailable(const std::string& oiioName) {
    static std::mutex mutex;
    static std::map<std::string, bool> known;
    std::lock_guard<std::mutex> lock(mutex);
    auto it = known.find(oiioName);
    if (it != known.end()) return it->second;
    const bool ok = OIIO::ImageOutput::create(oiioName) != nullptr;
    if (!ok) (void)OIIO::geterror();  // clear the message left by the failed create
    known.emplace(oiioName, ok);
    return ok;
}

OutputFormat checked(const FormatEntry& f, const std::string& what) {
    if (!f.oiio) throw Error(what + " (" + f.label + ") cannot be written: pushpin writes still images through OpenImageIO");
    if (!writerAvailable(f.oiio))
        throw Error(what + " (" + f.label + "): this OpenImageIO has no '" + f.oiio + "' writer");
    return OutputFormat{f.oiio, f.ext, f.floatPixels, f.bits};
}

OutputFormat fromNameEntry(const NameEntry& n, const std::string& what) {
    if (n.code == 51) {
        // Plug-in keys with no Maya code: formats OpenImageIO writes that Maya reaches via imf.
        if (std::string_view(n.key) == "hdr") {
            if (!writerAvailable("hdr")) throw Error(what + ": this OpenImageIO has no 'hdr' writer");
            return OutputFormat{"hdr", "hdr", true, 32};
        }
    }
    return checked(*formatByCode(n.code), what);
}

// Maya's file-name tokens, case-insensitive: <Scene> %s, <Camera> %c, <RenderLayer> <Layer> %l.
std::string expandTokens(std::string_view prefix, const std::string& scene, const std::string& camera,
                         bool* sawCamera) {
    static const std::pair<const char*, int> tokens[] = {
        {"<scene>", 0}, {"%s", 0}, {"<camera>", 1}, {"%c", 1}, {"<renderlayer>", 2}, {"<layer>", 2}, {"%l", 2}};
    const std::string low = lower(prefix);
    std::string out;
    size_t i = 0;
    while (i < prefix.size()) {
        bool matched = false;
        for (const auto& [token, kind] : tokens) {
            const size_t n = std::char_traits<char>::length(token);
            if (low.compare(i, n, token) == 0) {
                out += kind == 0 ? scene : kind == 1 ? camera : std::string("masterLayer");
                if (kind == 1) *sawCamera = true;
                i += n;
                matched = true;
                break;
            }
        }
        if (!matched) out += prefix[i++];
    }
    return out;
}

// A DAG or namespaced camera name as a file-name part: '|' and ':' become '_'.
std::string cameraFileName(std::string_view camera) {
    std::string s(camera);
    while (!s.empty() && s.front() == '|') s.erase(s.begin());
    for (char& c : s)
        if (c == '|' || c == ':') c = '_';
    return s;
}

// The frame number as Maya writes it: zero-padded to `padding` digits, a leading '-' for negative
// frames, and the fraction (up to 3 decimals) for sub-frames ("0012.5").
std::string frameText(double frame, int padding) {
    const double rounded = std::round(frame);
    const bool integral = std::abs(frame - rounded) < 1e-3;
    const double whole = integral ? rounded : std::trunc(frame);
    std::string digits = std::to_string(static_cast<long long>(std::abs(whole)));
    if (static_cast<int>(digits.size()) < padding) digits.insert(0, padding - digits.size(), '0');
    std::string text = (frame < 0 && (whole != 0 || !integral) ? "-" : "") + digits;
    if (!integral) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%.3f", std::abs(frame - whole));
        std::string fraction(buffer);  // "0.500"
        while (fraction.back() == '0') fraction.pop_back();
        text += fraction.substr(1);  // ".5"
    }
    return text;
}

// The file name without the format's extension when it ends with it, else the whole file name.
std::string stemFor(const fs::path& path, const OutputFormat& format) {
    const std::string name = path.filename().string();
    const std::string ext = "." + format.extension;
    if (name.size() > ext.size() && lower(name.substr(name.size() - ext.size())) == lower(ext))
        return name.substr(0, name.size() - ext.size());
    return name;
}

// A temporary file that is removed unless renamed into place: every failure path of writeImage leaves
// nothing behind.
struct TempFile {
    fs::path path;  // cleared once renamed into place
    ~TempFile() {
        if (!path.empty()) {
            std::error_code ec;
            fs::remove(path, ec);
        }
    }
};

fs::path temporaryPath(const fs::path& target, const std::string& stem, const std::string& ext) {
    static std::atomic<unsigned> counter{0};
    return target.parent_path() /
           (stem + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1)) + "." + ext);
}

uint64_t mix64(uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// A dither offset in (−0.5, 0.5) fixed by the pixel position and channel, so the same frame
// always writes the same bytes.
double ditherOffset(int x, int y, int channel) {
    const uint64_t h = mix64((static_cast<uint64_t>(static_cast<uint32_t>(y)) << 32) ^ static_cast<uint32_t>(x) ^
                             (static_cast<uint64_t>(channel) << 61));
    return (static_cast<double>(h >> 40) + 0.5) / 16777216.0 - 0.5;
}

// Writes `pixels` (float, `spec.nchannels` per pixel) to `tmp` with writer `oiioName`. Returns
// the empty string on success, else OpenImageIO's message.
std::string writeWithOiio(const std::string& oiioName, const fs::path& tmp, const OIIO::ImageSpec& spec,
                          const std::vector<float>& pixels) {
    auto out = OIIO::ImageOutput::create(oiioName);
    if (!out) {
        const std::string message = OIIO::geterror();
        return "OpenImageIO has no '" + oiioName + "' writer" + (message.empty() ? "" : ": " + message);
    }
    if (!out->open(tmp.string(), spec)) {
        const std::string message = out->geterror();
        return message.empty() ? "cannot open for writing" : message;
    }
    bool ok = out->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
    std::string message = ok ? std::string() : out->geterror();
    if (!out->close() && ok) {
        ok = false;
        message = out->geterror();
    }
    if (!ok && message.empty()) message = "write failed";
    return ok ? std::string() : message;
}

}  // namespace

OutputFormat outputFormatFromName(std::string_view name) {
    const NameEntry* n = nameEntry(name);
    if (!n) throw Error("unknown image format '" + std::string(name) + "'");
    return fromNameEntry(*n, "image format '" + std::string(name) + "'");
}

ImageFormatCode imageFormatCodeFromName(std::string_view name) {
    (void)outputFormatFromName(name);  // throws for unknown and unwritable names
    const NameEntry* n = nameEntry(name);
    return ImageFormatCode{n->code, n->key};
}

OutputFormat outputFormat(const RenderSettings& settings) {
    const int code = settings.imageFormat;
    if (code == 40 || code == 51) {
        // 40 is EXR through the imf plug-in; 51 names any imf plug-in by key.
        const std::string key = lower(settings.imfPluginKey);
        if (key.empty()) {
            if (code == 40) return outputFormatFromName("exr");
            throw Error("imageFormat 51 needs an imfPluginKey naming the format");
        }
        const NameEntry* n = nameEntry(key);
        if (!n) throw Error("imageFormat " + std::to_string(code) + ": unknown imfPluginKey '" + settings.imfPluginKey + "'");
        return fromNameEntry(*n, "imageFormat " + std::to_string(code) + " with imfPluginKey '" + settings.imfPluginKey + "'");
    }
    const FormatEntry* f = formatByCode(code);
    if (!f) throw Error("imageFormat " + std::to_string(code) + " is not a known Maya image format code");
    return checked(*f, "imageFormat " + std::to_string(code));
}

fs::path imageFilePath(const RenderSettings& settings, const OutputFormat& format, const fs::path& dir,
                       std::string_view sceneName, std::string_view cameraName, double frame, bool severalCameras) {
    std::string scene = fs::path(std::string(sceneName)).filename().string();
    const std::string sceneLower = lower(scene);
    if (sceneLower.size() > 3 &&
        (sceneLower.ends_with(".ma") || sceneLower.ends_with(".mb")))
        scene.resize(scene.size() - 3);
    if (scene.empty()) scene = "untitled";
    const std::string camera = cameraFileName(cameraName);

    bool sawCamera = false;
    const std::string prefix = settings.imageFilePrefix.empty()
                                   ? scene
                                   : expandTokens(settings.imageFilePrefix, scene, camera, &sawCamera);
    fs::path base(prefix);
    std::string name = base.filename().string();
    fs::path folder = base.parent_path();
    // Several cameras and no <Camera> token: each camera's frames go into a folder of its own,
    // placed just above the file name.
    if (severalCameras && !sawCamera) folder /= camera;
    if (name.empty()) name = scene;

    std::string ext;
    if (settings.outFormatControl == 0) ext = format.extension;
    else if (settings.outFormatControl == 2) {
        ext = settings.outFormatExt;
        while (!ext.empty() && ext.front() == '.') ext.erase(ext.begin());
    }

    // The naming table of render-globals.md: periodInExt picks the separator before the frame
    // number ("" / "." / "_"), putFrameBeforeExt whether the number precedes the extension.
    if (!settings.animation) {
        if (!ext.empty()) name += "." + ext;
    } else {
        const char* sep = settings.periodInExt == 0 ? "" : settings.periodInExt == 2 ? "_" : ".";
        const std::string number = frameText(frame, settings.extensionPadding);
        if (ext.empty()) name += sep + number;
        else if (settings.putFrameBeforeExt) name += sep + number + "." + ext;
        else name += "." + ext + sep + number;
    }
    return dir / folder / name;
}

fs::path depthImagePath(const fs::path& imagePath, const OutputFormat& format) {
    return imagePath.parent_path() / (stemFor(imagePath, format) + "_depth.exr");
}

void writeImage(const Framebuffer& frame, const fs::path& path, const OutputFormat& format,
                const RenderSettings& settings, bool writeDepth) {
    const int w = frame.width, h = frame.height;
    const size_t count = static_cast<size_t>(std::max(w, 0)) * static_cast<size_t>(std::max(h, 0));
    if (w < 1 || h < 1 || frame.rgba.size() != count * 4)
        throw IoError(path, "framebuffer " + std::to_string(w) + "x" + std::to_string(h) + " holds " +
                                std::to_string(frame.rgba.size()) + " values, not a whole RGBA image");
    // libjpeg ends the process instead of reporting an error past its size limit.
    constexpr int kJpegMaxSize = 65500;
    if (format.oiioName == "jpeg" && (w > kJpegMaxSize || h > kJpegMaxSize))
        throw IoError(path, "JPEG images are at most " + std::to_string(kJpegMaxSize) + " pixels across, not " +
                                std::to_string(w) + "x" + std::to_string(h));
    const bool depthWanted = writeDepth && frame.depth.size() == count;
    const bool exr = format.oiioName == "openexr";

    std::error_code ec;
    if (!path.parent_path().empty()) {
        fs::create_directories(path.parent_path(), ec);
        if (ec || !fs::is_directory(path.parent_path()))
            throw IoError(path, "cannot create folder '" + path.parent_path().string() + "': " +
                                    (ec ? ec.message() : std::string("not a folder")));
    }

    bool alpha = settings.mask.value_or(true);
    if (alpha) {
        auto probe = OIIO::ImageOutput::create(format.oiioName);
        if (!probe) {
            const std::string message = OIIO::geterror();
            throw IoError(path, "OpenImageIO has no '" + format.oiioName + "' writer" +
                                    (message.empty() ? "" : ": " + message));
        }
        alpha = probe->supports("alpha") != 0;
    }
    const bool zChannel = depthWanted && exr;
    const int nch = 3 + (alpha ? 1 : 0) + (zChannel ? 1 : 0);

    OIIO::TypeDesc type = format.floatPixels ? (format.bitsPerChannel == 16 ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT)
                          : format.bitsPerChannel == 16 ? OIIO::TypeDesc::UINT16
                                                        : OIIO::TypeDesc::UINT8;
    OIIO::ImageSpec spec(w, h, nch, type);
    spec.channelnames = {"R", "G", "B"};
    if (alpha) {
        spec.channelnames.push_back("A");
        spec.alpha_channel = 3;
    }
    if (zChannel) {
        spec.channelnames.push_back("Z");
        spec.z_channel = nch - 1;
        if (type != OIIO::TypeDesc::FLOAT) {
            spec.channelformats.assign(nch, type);
            spec.channelformats.back() = OIIO::TypeDesc::FLOAT;
        }
    }
    if (exr) spec.attribute("compression", "zip");
    // The colour is stored as rendered, as Maya does: OpenImageIO must not un-premultiply it for
    // formats whose alpha is by definition unassociated (PNG, TGA), so every format holds the same
    // numbers and a reader that premultiplies can be told not to.
    if (alpha) spec.attribute("oiio:UnassociatedAlpha", 1);
    spec.attribute("Software", "pushpin");

    // Final colour (render-globals.md): gamma v^(1/g) on colour, clip to [0,1], then for integer
    // formats a ±0.5 LSB dither on colour so smooth gradients do not band. Alpha is coverage and
    // gets neither gamma nor dither. NaN never reaches the file.
    const double gamma = settings.gammaCorrection;
    const bool applyGamma = std::isfinite(gamma) && gamma > 0.0 && gamma != 1.0;
    const double invGamma = applyGamma ? 1.0 / gamma : 1.0;
    const bool dither = settings.jitterFinalColor && !format.floatPixels;
    const double lsb = format.bitsPerChannel == 16 ? 1.0 / 65535.0 : 1.0 / 255.0;
    std::vector<float> pixels(count * nch);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const size_t i = static_cast<size_t>(y) * w + x;
            const float* src = frame.rgba.data() + i * 4;
            float* dst = pixels.data() + i * nch;
            for (int c = 0; c < 4; ++c) {
                if (c == 3 && !alpha) break;
                double v = src[c];
                if (std::isnan(v)) v = 0.0;
                if (c < 3 && applyGamma && v > 0.0) v = std::pow(v, invGamma);
                if (settings.clipFinalShadedColor) v = std::clamp(v, 0.0, 1.0);
                if (c < 3 && dither) v += ditherOffset(x, y, c) * lsb;
                dst[c] = static_cast<float>(v);
            }
            if (zChannel) dst[nch - 1] = frame.depth[i];
        }
    }

    const std::string stem = stemFor(path, format);
    TempFile imageTmp{temporaryPath(path, stem, format.extension)};
    std::string message = writeWithOiio(format.oiioName, imageTmp.path, spec, pixels);
    if (!message.empty()) throw IoError(path, message);

    fs::path depthPath;
    TempFile depthTmp;
    if (depthWanted && !zChannel) {
        depthPath = depthImagePath(path, format);
        depthTmp.path = temporaryPath(path, stem + "_depth", "exr");
        OIIO::ImageSpec zspec(w, h, 1, OIIO::TypeDesc::FLOAT);
        zspec.channelnames = {"Z"};
        zspec.z_channel = 0;
        zspec.attribute("compression", "zip");
        zspec.attribute("Software", "pushpin");
        message = writeWithOiio("openexr", depthTmp.path, zspec, frame.depth);
        if (!message.empty()) throw IoError(depthPath, message);
    }

    // Both files are complete; the renames make them visible whole.
    if (!depthPath.empty()) {
        fs::rename(depthTmp.path, depthPath, ec);
        if (ec) throw IoError(depthPath, "cannot rename '" + depthTmp.path.string() + "': " + ec.message());
        depthTmp.path.clear();
    }
    fs::rename(imageTmp.path, path, ec);
    if (ec) throw IoError(path, "cannot rename '" + imageTmp.path.string() + "': " + ec.message());
    imageTmp.path.clear();
}

}  // namespace pushpin::render
