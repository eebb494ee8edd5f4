// core/render/image_output.h: writing finished frames through OpenImageIO (DESIGN.md step 8):
// the output format from imageFormat/imfPluginKey or -of, Maya's file naming (image prefix with
// <Scene>/<Camera> tokens, frame number, padding, name.#.ext and the other conventions), the final
// colour steps (gamma, clip, dither), the folder images go to (-rd, a Maya project's images folder)
// and the rule that keeps them inside it, and a whole-or-nothing write: each image is encoded in
// memory, copied into an exclusive temporary name in the target folder with every write checked,
// flushed, and renamed into place, so a frame on disk is always whole and a failed write leaves
// the folder as it was.
// Thread safety: functions are reentrant; concurrent writes (even to the same path, from any
// number of processes) are safe: the last rename wins and every file is whole.
// Memory: writeImage holds the encoded file(s) in memory (at most about 5 floats a pixel, an
// uncompressed float EXR with Z) and converts the frame a strip of rows at a time.
#pragma once

#include "core/render/framebuffer.h"
#include "core/render/render_settings.h"

#include <filesystem>
#include <optional>
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

// Why the file system cannot hold `path` (a name over 255 bytes, or a path over 4095), quoting at
// most util::kMaxQuotedChars of the name; the empty string when it can. Pure.
std::string imagePathProblem(const std::filesystem::path& path);

// The companion depth file writeImage() writes beside `imagePath` for formats without a Z channel:
// the file name without the format's extension, plus "_depth.exr" ("shot.0001.png" →
// "shot.0001_depth.exr").
std::filesystem::path depthImagePath(const std::filesystem::path& imagePath, const OutputFormat& format);

// Writes RGBA (and Z when `writeDepth` and the framebuffer has depth; EXR gets a "Z" channel, other
// formats a companion "<name>_depth.exr") after gamma (gammaCorrection), clipping
// (clipFinalShadedColor) and, for integer formats, a deterministic dither (jitterFinalColor).
// Channels: R G B, then A unless `settings.mask` is false or the format has no alpha (JPEG); NaN
// colour values are written as 0. Creates missing parent folders.
// The image (and the depth file) are encoded in memory first; then each is copied into a
// cache::OutputFile beside its final path, both are flushed, and they are renamed, depth first,
// so a run that sees the image also sees its depth. Failures:
//   - pushpin::IoError naming the path when the frame cannot be encoded (a malformed framebuffer,
//     a size the format cannot hold, a name longer than the file system allows, a codec error or
//     exception): nothing in the output folder is touched;
//   - pushpin::OutputError (errorCode() = errno) when the output folder cannot be created or
//     written (a full disk, an I/O error): every temporary file is removed and the files the final
//     paths held before are unchanged;
//   - std::bad_alloc passes through.
// No codec writes the output folder itself, and none can end the process.
void writeImage(const Framebuffer& frame, const std::filesystem::path& path, const OutputFormat& format,
                const RenderSettings& settings, bool writeDepth);

// The images folder of the Maya project that holds `sceneFile`, or an empty path when there is
// none. The project is the nearest of the scene's folder and its three parents that holds a
// `workspace.mel`; its images folder is that file's `workspace -fr "images" "<folder>";` rule
// (relative to the project, or absolute), and `images` when the file has no such rule. Never
// throws; an unreadable workspace.mel counts as one without a rule.
std::filesystem::path projectImagesFolder(const std::filesystem::path& sceneFile);
// The images folder of the Maya project at `projectDir` (Render's -proj): its workspace.mel rule,
// else `images` under it, as a project without a rule keeps it. Never throws.
std::filesystem::path imagesFolderOfProject(const std::filesystem::path& projectDir);

// The images rule of a workspace.mel text (`workspace -fr "images" "<folder>";`, also spelled
// -fileRule), or nullopt when it has none. The last rule wins, as when Maya sources the file.
std::optional<std::string> workspaceImagesRule(std::string_view workspaceMel);

// Whether `path` lies inside `folder` (or is it) once both are made absolute against the working
// folder and lexically normalised ("a/b/../c" → "a/c"). Symbolic links are not resolved: the
// check is about what a prefix spells, not about links the user made. Pure apart from reading the
// working folder.
bool isInsideFolder(const std::filesystem::path& path, const std::filesystem::path& folder);

}  // namespace pushpin::render
