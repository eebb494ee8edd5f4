// Output formats, Maya's image file naming (reference/render-globals.md) and the atomic frame
// write through OpenImageIO.
#include "core/render/image_output.h"

#include "cache/error.h"
#include "cache/output_file.h"
#include "core/util/format.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

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

// An encoded image held in memory until it is published. OpenImageIO's writers for several
// formats (PNG, Targa, BMP, SGI, GIF among them) do not check their own write calls, and the
// JPEG writer lets libjpeg end the process on one, so no codec writes a real file: a codec that
// takes an IOProxy (every writable format but SGI and RLA) writes a vector in memory
// (Filesystem::IOVecOutput), where a write cannot come up short; SGI and RLA write an anonymous
// memfd through its /proc/self/fd/<n> name, and are read back whole before they count as
// encoded, since a write there can still fail unseen (the file size limit applies to a memfd;
// memory can run out). Publishing is then a plain copy whose every write is checked
// (cache::OutputFile).
class EncodedImage {
public:
    explicit EncodedImage(const fs::path& finalPath) : m_final(finalPath) {}
    ~EncodedImage() {
        if (m_fd >= 0) ::close(m_fd);
    }
    EncodedImage(const EncodedImage&) = delete;
    EncodedImage& operator=(const EncodedImage&) = delete;

    // Encodes a w × h image of `spec` with writer `oiioName`; `fill(y0, y1, rows)` writes rows
    // [y0, y1) as floats, spec.nchannels per pixel, into `rows`. Converting a strip at a time
    // keeps the float copy of the frame to a few megabytes. Returns the empty string on success,
    // else the reason. Throws OutputError when the bytes were cut by the file size limit (an
    // output condition, like a full disk). Any exception a codec throws is caught here
    // (std::bad_alloc is passed on, so the tool reports memory).
    std::string encode(const std::string& oiioName, const OIIO::ImageSpec& spec,
                       const std::function<void(int, int, float*)>& fill) {
        try {
            return encodeUnchecked(oiioName, spec, fill);
        } catch (const std::bad_alloc&) {
            throw;
        } catch (const OutputError&) {
            throw;
        } catch (const std::exception& e) {
            return std::string("OpenImageIO's '") + oiioName + "' writer failed: " + util::excerpt(e.what());
        } catch (...) {
            return "OpenImageIO's '" + oiioName + "' writer failed with an unknown exception";
        }
    }

    // Copies the encoded bytes into `out` (every write checked; throws OutputError).
    void copyInto(cache::OutputFile& out) const {
        if (m_fd >= 0) out.copyFrom(m_fd, "the in-memory image of " + util::excerpt(m_final.string()));
        else out.write(m_bytes.data(), m_bytes.size());
    }

private:
    std::string encodeUnchecked(const std::string& oiioName, const OIIO::ImageSpec& spec,
                                const std::function<void(int, int, float*)>& fill) {
        // Declared before the writer so it outlives it: a writer's destructor closes the file,
        // and may still write through the proxy (the Targa writer does after a failed open).
        std::unique_ptr<OIIO::Filesystem::IOVecOutput> proxy;
        auto out = OIIO::ImageOutput::create(oiioName);
        if (!out) {
            const std::string message = OIIO::geterror();
            return "OpenImageIO has no '" + oiioName + "' writer" + (message.empty() ? "" : ": " + message);
        }
        std::string name;
        if (out->supports("ioproxy")) {
            proxy = std::make_unique<OIIO::Filesystem::IOVecOutput>(m_bytes);
            if (!out->set_ioproxy(proxy.get())) return "the '" + oiioName + "' writer refused an in-memory target";
            name = m_final.filename().string();
        } else {
            std::string problem = openMemfd();
            if (!problem.empty()) return problem;
            name = m_codecPath;
        }
        auto failure = [&](const char* step) {
            std::string message = out->geterror();
            if (message.empty()) message = OIIO::geterror();
            return std::string(step) + (message.empty() ? "" : ": " + util::excerpt(message, 400));
        };
        if (!out->open(name, spec)) return failure("cannot start the image");
        // About 64k pixels a strip: at most a few MB of floats however wide the frame is. A writer
        // that makes the file tiled (IFF picks 64 × 64 tiles in open()) takes whole rows of tiles.
        const int w = spec.width, h = spec.height, nch = spec.nchannels;
        const int tileRows = out->spec().tile_width > 0 ? std::max(out->spec().tile_height, 1) : 0;
        int rowsPerStrip = std::clamp(65536 / std::max(w, 1), 1, h);
        if (tileRows > 0) rowsPerStrip = (rowsPerStrip + tileRows - 1) / tileRows * tileRows;
        std::vector<float> strip(size_t(std::min(rowsPerStrip, h)) * size_t(w) * size_t(nch));
        for (int y0 = 0; y0 < h; y0 += rowsPerStrip) {
            const int y1 = std::min(h, y0 + rowsPerStrip);
            fill(y0, y1, strip.data());
            const bool written = tileRows > 0
                                     ? out->write_tiles(0, w, y0, y1, 0, 1, OIIO::TypeDesc::FLOAT, strip.data())
                                     : out->write_scanlines(y0, y1, 0, OIIO::TypeDesc::FLOAT, strip.data());
            if (!written) {
                std::string message = failure("cannot encode the image");
                (void)out->close();
                checkMemfd(oiioName, spec);
                return message;
            }
        }
        if (!out->close()) {
            std::string message = failure("cannot finish the image");
            checkMemfd(oiioName, spec);
            return message;
        }
        out.reset();
        if (m_fd >= 0) checkMemfd(oiioName, spec);
        if (size() == 0) return "the '" + oiioName + "' writer produced no bytes";
        return {};
    }

    std::string openMemfd() {
        m_fd = ::memfd_create("pushpin-image", MFD_CLOEXEC);
        if (m_fd < 0) return std::string("cannot make an in-memory file to encode into: ") + std::strerror(errno);
        m_codecPath = "/proc/self/fd/" + std::to_string(m_fd);
        if (::access(m_codecPath.c_str(), W_OK) != 0)
            return "this format is encoded through /proc/self/fd, and /proc is not available";
        return {};
    }

    // A memfd's bytes count as the image only when they read back as the whole image: the SGI
    // and RLA writers ignore failed writes. Cut bytes are an output failure (OutputError): the
    // file size limit (`ulimit -f`, EFBIG) or memory ran out, as a full disk would.
    void checkMemfd(const std::string& oiioName, const OIIO::ImageSpec& spec) const {
        if (m_fd < 0) return;
        struct rlimit limit;
        const bool limited = ::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY;
        if (limited && size() >= uint64_t(limit.rlim_cur))
            throw OutputError(m_final, "the image is larger than the file size limit (ulimit -f) of " +
                                           std::to_string(uint64_t(limit.rlim_cur)) + " bytes",
                              EFBIG);
        auto in = OIIO::ImageInput::create(oiioName);
        OIIO::ImageSpec opened;
        bool whole = in && in->open(m_codecPath, opened) && opened.width == spec.width && opened.height == spec.height;
        if (whole) {
            const int w = spec.width, nch = opened.nchannels;
            const int rowsPerStrip = std::clamp(65536 / std::max(w, 1), 1, spec.height);
            std::vector<float> strip(size_t(rowsPerStrip) * size_t(w) * size_t(nch));
            for (int y0 = 0; whole && y0 < spec.height; y0 += rowsPerStrip)
                whole = in->read_scanlines(0, 0, y0, std::min(spec.height, y0 + rowsPerStrip), 0, 0, nch,
                                           OIIO::TypeDesc::FLOAT, strip.data());
        }
        if (in) (void)in->geterror();
        (void)OIIO::geterror();
        if (!whole)
            throw OutputError(m_final, "the encoded image does not read back whole (a write into memory failed)",
                              limited ? EFBIG : ENOMEM);
    }

    uint64_t size() const {
        if (m_fd < 0) return m_bytes.size();
        struct stat st;
        return ::fstat(m_fd, &st) == 0 ? uint64_t(st.st_size) : 0;
    }

    fs::path m_final;
    int m_fd = -1;                         // the memfd of a format without IOProxy support
    std::string m_codecPath;               // "/proc/self/fd/<m_fd>"
    std::vector<unsigned char> m_bytes;    // the IOProxy target
};

// writeImage's guard: a path the file system cannot hold is refused before any work.
void checkPathLength(const fs::path& path) {
    const std::string problem = imagePathProblem(path);
    if (!problem.empty()) throw IoError(util::excerpt(path.string()), problem);
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

std::string imagePathProblem(const fs::path& path) {
    // Linux's NAME_MAX and PATH_MAX (less the terminating NUL), which the file systems farms use
    // share. A longer name fails every system call with ENAMETOOLONG, so it is reported up front
    // and quoted short instead of repeated whole in every message on the way.
    constexpr size_t kNameMax = 255, kPathMax = 4095;
    if (path.native().size() > kPathMax)
        return "the path is " + std::to_string(path.native().size()) + " bytes long; a path holds at most " +
               std::to_string(kPathMax);
    for (const fs::path& part : path)
        if (part.native().size() > kNameMax)
            return "the name '" + util::excerpt(part.string()) + "' in the path is " +
                   std::to_string(part.native().size()) + " bytes long; a file or folder name holds at most " +
                   std::to_string(kNameMax);
    return {};
}

fs::path depthImagePath(const fs::path& imagePath, const OutputFormat& format) {
    return imagePath.parent_path() / (stemFor(imagePath, format) + "_depth.exr");
}

void writeImage(const Framebuffer& frame, const fs::path& path, const OutputFormat& format,
                const RenderSettings& settings, bool writeDepth) {
    const int w = frame.width, h = frame.height;
    const size_t count = static_cast<size_t>(std::max(w, 0)) * static_cast<size_t>(std::max(h, 0));
    checkPathLength(path);
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
    const fs::path depthPath = depthWanted && !exr ? depthImagePath(path, format) : fs::path();
    if (!depthPath.empty()) checkPathLength(depthPath);

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
    auto fillColour = [&](int y0, int y1, float* rows) {
        for (int y = y0; y < y1; ++y) {
            for (int x = 0; x < w; ++x) {
                const size_t i = static_cast<size_t>(y) * w + x;
                const float* src = frame.rgba.data() + i * 4;
                float* dst = rows + (static_cast<size_t>(y - y0) * w + x) * nch;
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
    };

    // Both files are encoded in memory before anything is created in the output folder, so a
    // frame OpenImageIO cannot encode (a size the format cannot hold) leaves the folder as it was.
    EncodedImage image(path);
    std::string message = image.encode(format.oiioName, spec, fillColour);
    if (!message.empty()) throw IoError(path, message);
    std::unique_ptr<EncodedImage> depth;
    if (!depthPath.empty()) {
        OIIO::ImageSpec zspec(w, h, 1, OIIO::TypeDesc::FLOAT);
        zspec.channelnames = {"Z"};
        zspec.z_channel = 0;
        zspec.attribute("compression", "zip");
        zspec.attribute("Software", "pushpin");
        depth = std::make_unique<EncodedImage>(depthPath);
        message = depth->encode("openexr", zspec, [&](int y0, int y1, float* rows) {
            std::copy(frame.depth.begin() + static_cast<ptrdiff_t>(y0) * w,
                      frame.depth.begin() + static_cast<ptrdiff_t>(y1) * w, rows);
        });
        if (!message.empty()) throw IoError(depthPath, message);
    }

    std::error_code ec;
    if (!path.parent_path().empty()) {
        fs::create_directories(path.parent_path(), ec);
        if (ec || !fs::is_directory(path.parent_path()))
            throw OutputError(path, "cannot create folder '" + util::excerpt(path.parent_path().string()) + "'",
                              ec ? ec.value() : ENOTDIR);
    }

    // Publishing: each file is copied whole into its own exclusive temporary name and flushed to
    // disk before either is renamed, so a full disk or an I/O error stops the frame with nothing
    // published and the previous files untouched. The depth file is renamed first: once the image
    // (what -skipExistingFrames and a farm look for) is in place, so is its depth. Only a failed
    // rename of the image after the depth's succeeded, which needs the folder to change under
    // us, can leave the new depth beside the old image.
    cache::OutputFile imageOut(path);
    image.copyInto(imageOut);
    std::unique_ptr<cache::OutputFile> depthOut;
    if (depth) {
        depthOut = std::make_unique<cache::OutputFile>(depthPath);
        depth->copyInto(*depthOut);
    }
    for (cache::OutputFile* out : {&imageOut, depthOut.get()})
        if (out && ::fsync(out->fd()) != 0)
            throw OutputError(out->path(), "cannot flush " + util::excerpt(out->temporaryPath().string()) + " to disk", errno);
    if (depthOut) depthOut->commit();
    imageOut.commit();
}

std::optional<std::string> workspaceImagesRule(std::string_view text) {
    // MEL statements split into words: bare words, and "quoted strings" with backslash escapes.
    std::optional<std::string> rule;
    std::vector<std::string> words;
    std::vector<bool> quoted;
    auto statement = [&] {
        if (words.size() >= 4 && !quoted[0] && words[0] == "workspace")
            for (size_t i = 1; i + 2 < words.size(); ++i)
                if (!quoted[i] && (words[i] == "-fr" || words[i] == "-fileRule") && quoted[i + 1] && quoted[i + 2] &&
                    words[i + 1] == "images")
                    rule = words[i + 2];
        words.clear();
        quoted.clear();
    };
    size_t i = 0;
    while (i < text.size()) {
        const char c = text[i];
        if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {  // a comment to the end of the line
            while (i < text.size() && text[i] != '\n') ++i;
        } else if (c == ';') {
            statement();
            ++i;
        } else if (c == '"') {
            std::string word;
            for (++i; i < text.size() && text[i] != '"'; ++i) {
                if (text[i] == '\\' && i + 1 < text.size()) ++i;
                word += text[i];
            }
            ++i;
            words.push_back(std::move(word));
            quoted.push_back(true);
        } else if (std::isspace(static_cast<unsigned char>(c))) {
            ++i;
        } else {
            std::string word;
            while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i])) && text[i] != ';' &&
                   text[i] != '"')
                word += text[i++];
            words.push_back(std::move(word));
            quoted.push_back(false);
        }
    }
    statement();
    return rule;
}

namespace {

// The images folder a workspace.mel at `dir` names, or nullopt when `dir` has none.
std::optional<fs::path> workspaceImagesFolder(const fs::path& dir) {
    std::error_code ec;
    const fs::path workspace = dir / "workspace.mel";
    if (!fs::is_regular_file(workspace, ec)) return std::nullopt;
    std::string text;
    std::ifstream in(workspace, std::ios::binary);
    // workspace.mel holds a few dozen short rules; a larger file is not one Maya wrote.
    constexpr size_t kMaxWorkspaceBytes = size_t(1) << 20;
    text.resize(kMaxWorkspaceBytes);
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
    const std::optional<std::string> rule = workspaceImagesRule(text);
    // An empty rule names the project folder itself, as `workspace -fre` resolves it.
    if (!rule) return dir / "images";
    return rule->empty() ? dir : dir / *rule;
}

}  // namespace

fs::path imagesFolderOfProject(const fs::path& projectDir) {
    if (std::optional<fs::path> images = workspaceImagesFolder(projectDir)) return *images;
    return projectDir / "images";
}

fs::path projectImagesFolder(const fs::path& sceneFile) {
    std::error_code ec;
    fs::path dir = fs::absolute(sceneFile, ec).parent_path();
    if (ec) return {};
    // The scene's folder and three above it: scenes usually sit in <project>/scenes, sometimes a
    // level or two deeper (scenes/shot/v003).
    for (int level = 0; level < 4 && !dir.empty(); ++level) {
        if (std::optional<fs::path> images = workspaceImagesFolder(dir)) return *images;
        const fs::path parent = dir.parent_path();
        if (parent == dir) break;
        dir = parent;
    }
    return {};
}

bool isInsideFolder(const fs::path& path, const fs::path& folder) {
    std::error_code ec;
    const fs::path p = fs::absolute(path, ec).lexically_normal();
    if (ec) return false;
    const fs::path f = fs::absolute(folder, ec).lexically_normal();
    if (ec) return false;
    // Component-wise prefix: "/out" holds "/out/a.png" but not "/outside/a.png". The empty last
    // component of a folder spelled with a trailing separator ("/out/") is no part of the name.
    auto pi = p.begin();
    for (const fs::path& part : f) {
        if (part.empty()) continue;
        if (pi == p.end() || *pi != part) return false;
        ++pi;
    }
    return true;
}

}  // namespace pushpin::render
