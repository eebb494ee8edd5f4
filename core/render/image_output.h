// core/render/image_output.h: writing finished frames through OpenImageIO (DESIGN.md step 8):
// the output format from imageFormat/imfPluginKey or -of, Maya's file naming (image prefix with
// <Scene>/<Camera> tokens, frame number, padding, name.#.ext and the other conventions), the final
// colour steps (gamma, clip, dither), and an atomic write: the image goes to a temporary name in
// the target folder and is renamed when complete, so a frame on disk is always whole.
// Thread safety: functions are reentrant; concurrent writes to different paths are safe.
#pragma once

#include "core/render/framebuffer.h"
#include "core/render/render_settings.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace pushpin::render {

struct OutputFormat {
    std::string oiioName;   // OpenImageIO format name: "openexr", "tiff", "png", "iff", "jpeg" …
    std::string extension;  // file extension without the dot: "exr", "tif", "png", "iff" …
    bool floatPixels = false;  // written as half/float (EXR) rather than 8/16-bit integers
    int bitsPerChannel = 8;    // 8, 16 or 32
};

// The format the settings ask for. Throws pushpin::Error naming the code or key when OpenImageIO
// cannot write it (movie formats, unknown codes).
OutputFormat outputFormat(const RenderSettings& settings);
// The format named on the command line (-of): Maya's keywords (iff, tif, tiff16, sgi, jpg, exr,
// png, tga, bmp …). Throws pushpin::Error for an unknown or unwritable name.
OutputFormat outputFormatFromName(std::string_view name);

// Maya's imageFormat code and imfPluginKey for a format name as -of takes it (the keywords of
// outputFormatFromName): "iff" → 7, "tif" → 3, "png" → 32, "exr" → 40 with key "exr", names with no
// code of their own (e.g. "hdr") → 51 with the name as key. Throws pushpin::Error like
// outputFormatFromName.
struct ImageFormatCode {
    int imageFormat = 7;
    std::string imfPluginKey;
};
ImageFormatCode imageFormatCodeFromName(std::string_view name);

// The image path of one frame: `dir` / prefix (tokens <Scene>, <Camera>, <RenderLayer> → "masterLayer"
// expanded; empty prefix = scene name without extension; with several cameras rendered and no
// <Camera> token the camera name is appended as a folder, as Maya does) + frame part and extension
// by outFormatControl / putFrameBeforeExt / periodInExt / extensionPadding. Frame numbers are used
// only when `settings.animation` is on.
std::filesystem::path imageFilePath(const RenderSettings& settings, const OutputFormat& format,
                                    const std::filesystem::path& dir, std::string_view sceneName,
                                    std::string_view cameraName, double frame, bool severalCameras);

// The companion depth file writeImage() writes beside `imagePath` for formats without a Z channel:
// the file name without the format's extension, plus "_depth.exr" ("shot.0001.png" →
// "shot.0001_depth.exr").
std::filesystem::path depthImagePath(const std::filesystem::path& imagePath, const OutputFormat& format);

// Writes RGBA (and Z when `writeDepth` and the framebuffer has depth; EXR gets a "Z" channel, other
// formats a companion "<name>_depth.exr") after gamma (gammaCorrection), clipping
// (clipFinalShadedColor) and, for integer formats, a deterministic dither (jitterFinalColor).
// Writes to a temporary file beside `path` and renames it; on any failure removes the temporary
// file and throws pushpin::IoError naming the path and OpenImageIO's message. Creates missing
// parent folders. Channels: R G B, then A unless `settings.mask` is false or the format has no
// alpha (JPEG); NaN colour values are written as 0.
void writeImage(const Framebuffer& frame, const std::filesystem::path& path, const OutputFormat& format,
                const RenderSettings& settings, bool writeDepth);

}  // namespace pushpin::render
