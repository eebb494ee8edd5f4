// pushpin: renders Maya ASCII scenes. This front end parses the command line, loads the scene,
// renders every requested frame and camera (or prints the --info report) and writes the images;
// every error ends here as one line on stderr starting "Error: " (farm.md §6: the line farm
// parsers look for) and the exit status of farm.md §6, with no partial image on disk:
//   0   every frame written
//   1   scene or input error: a missing, unreadable or malformed scene, a bad value in it, an
//       image prefix in the scene that leaves the output folder
//   2   usage error: the command line itself (render::UsageError), no scene given
//   33  over the memory cap (MemoryCapError, or an allocation that failed)
//   75  an image or the --stats file could not be written (OutputError: a full disk, an I/O
//       error); the sequence stops at that frame, and frames before it are whole
//   130, 143  SIGINT, SIGTERM: cache::installTemporaryFileCleanup() removes the temporary files
//   4   an unexpected internal exception
#include "cache/error.h"
#include "cache/output_file.h"
#include "core/render/camera.h"
#include "core/render/command_line.h"
#include "core/render/frame_scene.h"
#include "core/render/image_output.h"
#include "core/render/render_settings.h"
#include "core/render/renderer.h"
#include "core/scene/demo_scene.h"
#include "core/scene/evaluator.h"
#include "core/scene/ma_reader.h"
#include "core/scene/not_rendered.h"
#include "core/scene/render_setup.h"
#include "core/scene/scene_info.h"
#include "core/util/format.h"
#include "core/util/json_writer.h"
#include "core/util/process_memory.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace pushpin;

// The scene's notRendered list as the command line changes it: a switch turned off (-mb off,
// -ert off, -edm off, -iip) removes its feature, since nothing is then left out of the render; a
// switch turned on and every flag pushpin does not apply add theirs, naming the flag.
std::vector<scene::NotRendered> withCommandLine(std::vector<scene::NotRendered> list, const render::CommandLine& cl) {
    auto entry = [&](const std::string& feature) -> scene::NotRendered& {
        for (scene::NotRendered& n : list)
            if (n.feature == feature) return n;
        return list.emplace_back(scene::NotRendered{feature, {}, 0});
    };
    auto addFlag = [&](const std::string& feature, const std::string& flag) {
        scene::NotRendered& n = entry(feature);
        ++n.count;
        if (n.nodes.size() < scene::kMaxNotRenderedNodes) n.nodes.push_back(flag);
    };
    for (const render::CommandLine::FeatureSwitch& sw : cl.featureSwitches) {
        if (sw.on) {
            addFlag(sw.feature, sw.flag);
            continue;
        }
        std::erase_if(list, [&](const scene::NotRendered& n) {
            return n.feature == sw.feature || (sw.feature == "ray tracing" && n.feature.rfind("ray-traced", 0) == 0);
        });
    }
    for (const render::CommandLine::NotApplied& na : cl.notApplied) addFlag(na.feature, na.flag);
    return list;
}

constexpr int kExitInput = 1;
constexpr int kExitUsage = 2;
constexpr int kExitMemory = 33;
constexpr int kExitOutput = 75;
constexpr int kExitInternal = 4;

// One line, whatever the message holds, so scripts can read the first line of stderr. Messages
// quote tokens through util::excerpt already; the bound here keeps one line short even when a
// message is built from several of them.
std::string oneLine(std::string_view text) {
    constexpr size_t kMaxLineChars = 2000;
    std::string s = util::excerpt(text, kMaxLineChars);
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
}

void reportError(int exitCode, std::string_view message) {
    std::fprintf(stderr, "Error: pushpin: %s%s\n", oneLine(message).c_str(),
                 exitCode == kExitOutput ? " (nothing partial was written; the frame can be retried)" : "");
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The cameras to render: those named by -cam (by transform name, shape name or DAG path), else
// every renderable camera. Throws when a named camera is missing or nothing is renderable.
std::vector<const scene::CameraInfo*> selectCameras(const scene::Graph& graph, const scene::RenderSetup& setup,
                                                    const std::vector<std::string>& names,
                                                    const std::string& sceneName) {
    std::vector<const scene::CameraInfo*> out;
    if (!names.empty()) {
        for (const std::string& name : names) {
            const scene::CameraInfo* found = nullptr;
            for (const scene::CameraInfo& c : setup.cameras)
                if (c.transformName == name || c.name == name || graph.dagPathName(c.path) == name ||
                    (!c.path.empty() && c.path.size() >= 2 && graph.dagPathName({c.path.begin(), c.path.end() - 1}) == name)) {
                    found = &c;
                    break;
                }
            if (!found) {
                std::string known;
                for (const scene::CameraInfo& c : setup.cameras) known += (known.empty() ? "" : ", ") + c.transformName;
                throw Error("-cam: no camera '" + util::excerpt(name) + "' in " + util::excerpt(sceneName) +
                            " (cameras: " + (known.empty() ? "none" : util::excerpt(known)) + ")");
            }
            out.push_back(found);
        }
        return out;
    }
    for (const scene::CameraInfo& c : setup.cameras)
        if (c.renderable) out.push_back(&c);
    if (out.empty()) throw Error(util::excerpt(sceneName) + ": no renderable camera (name one with -cam)");
    return out;
}

std::vector<double> framesToRender(const render::CommandLine& cl, const render::RenderSettings& s,
                                   const scene::Graph& graph) {
    if (cl.frame) return {*cl.frame};
    if (!s.animation) return {scene::sceneCurrentFrame(graph)};
    if (!(s.byFrameStep > 0.0)) throw Error("byFrameStep must be positive (got " + std::to_string(s.byFrameStep) + ")");
    std::vector<double> frames;
    for (double f = s.startFrame; f <= s.endFrame + 1e-9; f += s.byFrameStep) {
        frames.push_back(f);
        if (frames.size() > 1000000) throw Error("frame range " + std::to_string(s.startFrame) + ".." +
                                                 std::to_string(s.endFrame) + " is too long");
    }
    if (frames.empty()) throw Error("the frame range is empty (start " + std::to_string(s.startFrame) + ", end " +
                                    std::to_string(s.endFrame) + ")");
    return frames;
}

// Writes `text` to `path` whole or not at all (cache::OutputFile). Throws OutputError.
void writeWholeFile(const fs::path& path, const std::string& text) {
    cache::OutputFile out(path);
    out.write(text.data(), text.size());
    out.commit();
}

// The folder images go to: -rd, else the images folder of the -proj project, else of the Maya
// project holding the scene (render::projectImagesFolder: the nearest workspace.mel at or above
// the scene's folder), else the working folder.
fs::path outputFolder(const render::CommandLine& cl) {
    if (!cl.outputDir.empty()) return fs::path(cl.outputDir);
    if (!cl.project.empty()) return render::imagesFolderOfProject(cl.project);
    if (!cl.demo) {
        fs::path images = render::projectImagesFolder(cl.scene);
        if (!images.empty()) return images;
    }
    return fs::path(".");
}

// Where the image prefix came from, for messages: the command line (-im/-p) or the scene.
struct PrefixSource {
    bool commandLine = false;
    std::string flag;  // "-im" or "-p" when commandLine
};

PrefixSource prefixSource(const render::CommandLine& cl) {
    PrefixSource source;
    for (const render::CommandLine::Override& o : cl.overrides)
        if (o.flag == "-im" || o.flag == "-p") source = {true, o.flag};
    return source;
}

// Images go only under the output folder (see --help): a scene cannot aim a render at any file
// the user can write. An image prefix that is absolute, or that climbs out of the folder with "..",
// after token expansion, is refused unless --allow-scene-output-paths is given; one from the
// scene is a scene error (exit 1) naming defaultRenderGlobals.imageFilePrefix, one from -im a
// usage error (exit 2). "..", inside the folder ("shots/../a"), is fine. The path is also one the
// file system can hold.
void checkImagePath(const fs::path& path, const fs::path& outputDir, const render::CommandLine& cl,
                    const render::RenderSettings& settings) {
    const PrefixSource source = prefixSource(cl);
    const std::string what = source.commandLine ? source.flag + " '" + util::excerpt(settings.imageFilePrefix) + "'"
                                                : "defaultRenderGlobals.imageFilePrefix '" +
                                                      util::excerpt(settings.imageFilePrefix) + "'";
    auto fail = [&](const std::string& message) {
        if (source.commandLine) throw render::UsageError(message);
        throw Error(message);
    };
    const std::string problem = render::imagePathProblem(path);
    if (!problem.empty()) fail(what + " gives an image path the file system cannot hold: " + problem);
    if (!cl.allowSceneOutputPaths && !render::isInsideFolder(path, outputDir))
        fail(what + " puts images at " + util::excerpt(path.string()) + ", outside the output folder " +
             util::excerpt(outputDir.string()) +
             (source.commandLine ? "; choose the folder with -rd, or give --allow-scene-output-paths"
                                 : "; override the prefix with -im, or give --allow-scene-output-paths to allow it"));
}

int run(int argc, char** argv) {
    // What the process holds before any scene: the loaded scene is charged for what it adds.
    const uint64_t heapBeforeScene = util::heapBytesInUse();
    std::vector<std::string_view> args(argv + 1, argv + argc);
    render::CommandLine cl = render::parseCommandLine(args);
    if (cl.help) {
        std::string help = render::commandLineHelp();
        std::fwrite(help.data(), 1, help.size(), stdout);
        return 0;
    }
    if (cl.version) {
        std::puts("pushpin 0.1.0");
        return 0;
    }
    if (cl.printDemo) {
        std::string_view text = scene::demoSceneText();
        std::fwrite(text.data(), 1, text.size(), stdout);
        return 0;
    }
    if (cl.demo && !cl.scene.empty()) throw render::UsageError("give either --demo or a scene file, not both");
    if (!cl.demo && cl.scene.empty()) {
        reportError(kExitUsage, "no scene file given (name a .ma file, or --demo)");
        std::string help = render::commandLineHelp();
        std::fwrite(help.data(), 1, help.size(), stderr);
        return kExitUsage;
    }
    if (!cl.statsPath.empty()) {
        const std::string problem = render::imagePathProblem(cl.statsPath);
        if (!problem.empty()) throw render::UsageError("--stats: " + problem);
    }
    if (!cl.tilePatternPath.empty()) {
        const std::string problem = render::imagePathProblem(cl.tilePatternPath);
        if (!problem.empty()) throw render::UsageError("--tile-pattern: " + problem);
    }
    bool tilePatternWritten = false;
    if (!cl.demo) {
        // A folder (or a device, a FIFO) given as the scene is an input error, not an empty scene.
        std::error_code ec;
        const fs::file_status status = fs::status(cl.scene, ec);
        if (!ec && fs::exists(status) && !fs::is_regular_file(status))
            throw IoError(util::excerpt(cl.scene),
                          fs::is_directory(status) ? "is a folder, not a scene file" : "is not a regular file");
    }

    auto tLoad = std::chrono::steady_clock::now();
    scene::ReadOptions readOptions;
    readOptions.loadReferences = cl.loadReferences;
    const std::string sceneName = cl.demo ? std::string(scene::kDemoSceneName) : cl.scene;
    scene::Graph graph = cl.demo ? scene::MaReader::readString(scene::demoSceneText(), sceneName, readOptions)
                                 : scene::MaReader::readFile(cl.scene, readOptions);
    const double loadSeconds = secondsSince(tLoad);

    if (cl.info) {
        double frame = cl.frame ? *cl.frame : scene::sceneCurrentFrame(graph);
        std::string json = scene::sceneInfoJson(graph, frame);
        std::fwrite(json.data(), 1, json.size(), stdout);
        std::fflush(stdout);
        return 0;
    }

    const scene::RenderSetup setup = scene::extractRenderSetup(graph);
    std::vector<double> frames;
    {
        scene::Evaluator ev(graph, scene::sceneCurrentFrame(graph));
        std::vector<std::string> ignored;
        render::RenderSettings s = render::readRenderSettings(ev, setup, ignored);
        render::applyOverrides(cl, s);
        frames = framesToRender(cl, s, graph);
    }
    const fs::path outputDir = outputFolder(cl);
    const std::string sceneStem = fs::path(sceneName).stem().string();
    std::optional<uint64_t> storedBytes;  // what the loaded scene holds, measured when a cap needs it
    std::error_code ec;
    const fs::path scenePath = cl.demo ? fs::path() : fs::weakly_canonical(fs::path(cl.scene), ec);

    util::JsonWriter stats;
    stats.beginObject();
    stats.field("scene", sceneName).field("loadSeconds", loadSeconds);
    stats.key("images").beginArray();
    std::vector<scene::NotRendered> notRendered;  // what the scene turns on and pushpin does not render
    std::set<std::string> notesSeen;
    std::vector<std::string> notes;
    auto note = [&](const std::string& n) {
        if (notesSeen.insert(n).second) notes.push_back(n);
    };
    for (const auto& w : graph.warnings())
        note(w.file + ":" + std::to_string(w.line) + ": " + (w.node.empty() ? "" : "node '" + w.node + "': ") + w.message);
    for (const std::string& n : setup.notes) note(n);
    for (const auto& [type, count] : graph.unsupportedTypes())
        note("unsupported node type '" + type + "' (" + std::to_string(count) + " node" + (count == 1 ? "" : "s") + ")");

    for (double frame : frames) {
        auto tScene = std::chrono::steady_clock::now();
        scene::Evaluator ev(graph, frame);
        for (scene::NotRendered& n : withCommandLine(scene::notRenderedFeatures(ev, setup), cl)) {
            note("not rendered: " + scene::describeNotRendered(n));
            auto same = std::find_if(notRendered.begin(), notRendered.end(),
                                     [&](const scene::NotRendered& o) { return o.feature == n.feature; });
            if (same == notRendered.end()) notRendered.push_back(std::move(n));
        }
        std::vector<std::string> settingNotes;
        render::RenderSettings settings = render::readRenderSettings(ev, setup, settingNotes);
        render::applyOverrides(cl, settings);
        for (const std::string& n : settingNotes) note(n);
        const render::OutputFormat format = render::outputFormat(settings);
        const std::vector<const scene::CameraInfo*> cameras = selectCameras(graph, setup, cl.cameras, sceneName);
        render::FrameScene frameScene = render::buildFrameScene(ev, setup, settings);
        for (const std::string& n : frameScene.notes) note(n);
        for (const scene::Diagnostic& d : ev.diagnostics())
            note((d.node.empty() ? "" : "node '" + d.node + "': ") + d.message);
        const double sceneSeconds = secondsSince(tScene);

        // A camera whose values cannot be used (render::makeRenderCamera says which) is an error
        // when -cam names it; among the scene's renderable cameras it is skipped with a note, and
        // it is an error only when no camera is left.
        std::string unusableCamera;
        size_t usableCameras = 0;
        for (const scene::CameraInfo* cameraInfo : cameras) {
            render::RenderCamera camera;
            try {
                camera = render::makeRenderCamera(ev, cameraInfo->path, settings.width, settings.height,
                                                  settings.deviceAspectRatio);
            } catch (const MemoryCapError&) {
                throw;
            } catch (const Error& e) {
                if (!cl.cameras.empty()) throw;
                note("camera '" + util::excerpt(cameraInfo->transformName) + "' not rendered: " + e.what());
                if (unusableCamera.empty()) unusableCamera = e.what();
                continue;
            }
            ++usableCameras;
            render::RenderSettings cameraSettings = settings;
            if (!cameraSettings.depth) cameraSettings.depth = ev.getBool(cameraInfo->shape, "depth", false);
            fs::path path = render::imageFilePath(cameraSettings, format, outputDir, sceneStem, camera.name, frame,
                                                  cameras.size() > 1);
            checkImagePath(path, outputDir, cl, cameraSettings);
            if (!scenePath.empty() && fs::weakly_canonical(path, ec) == scenePath)
                throw Error("the image path " + util::excerpt(path.string()) +
                            " is the scene file itself; choose another -im or -rd");

            render::RenderStats renderStats;
            auto tRender = std::chrono::steady_clock::now();
            render::TilePlan plan;
            render::RenderOptions renderOptions;
            if (!cl.tilePatternPath.empty() && !tilePatternWritten) renderOptions.tilePlan = &plan;
            // Under a cap the loaded scene's stored values count against it too.
            std::optional<cache::MemoryBudget> budget;
            cache::MemoryCharge sceneCharge;
            if (const uint64_t capBytes = render::memoryCapBytes(cameraSettings); capBytes != 0) {
                budget.emplace(capBytes);
                // The stored values, or all the heap the loaded scene and its frame scene added
                // when the allocator says more (their tables and small blocks).
                if (!storedBytes) {
                    const uint64_t heap = util::heapBytesInUse();
                    storedBytes = std::max(graph.storedBytes(), heap > heapBeforeScene ? heap - heapBeforeScene : 0);
                }
                sceneCharge = render::chargeScene(*budget, *storedBytes, cameraSettings);
                renderOptions.memoryBudget = &*budget;
            }
            render::Framebuffer image = render::renderFrame(frameScene, camera, cameraSettings, renderStats, renderOptions);
            const double renderSeconds = secondsSince(tRender);
            auto tWrite = std::chrono::steady_clock::now();
            // Throws OutputError when the image cannot be written: the sequence stops here (exit 75)
            // with this frame's files as they were and every earlier frame whole.
            render::writeImage(image, path, format, cameraSettings, cameraSettings.depth.value_or(false));
            const double writeSeconds = secondsSince(tWrite);
            if (renderOptions.tilePlan) {
                render::writeTilePattern(plan, image.width, image.height, cl.tilePatternPath);
                tilePatternWritten = true;
            }

            // Printed only once the image is renamed into place (writeImage has returned).
            if (!cl.quiet)
                std::fprintf(stderr, "pushpin: frame %g, camera %s: %dx%d in %.2f s -> %s\n", frame,
                             util::excerpt(camera.name).c_str(), image.width, image.height, renderSeconds,
                             util::excerpt(path.string(), 1000).c_str());
            stats.beginObject();
            stats.field("frame", frame).field("camera", camera.name).field("path", path.string());
            stats.field("width", image.width).field("height", image.height);
            stats.field("sceneSeconds", sceneSeconds).field("renderSeconds", renderSeconds);
            stats.field("writeSeconds", writeSeconds);
            stats.field("objects", uint64_t(frameScene.objects.size()))
                .field("skippedShapes", uint64_t(frameScene.skippedShapes));
            stats.key("render");
            render::writeRenderStats(stats, renderStats);
            stats.endObject();
        }
        if (usableCameras == 0) throw Error(unusableCamera);
    }
    stats.endArray();
    stats.key("notRendered").beginArray();
    for (const scene::NotRendered& n : notRendered) scene::writeNotRendered(stats, n);
    stats.endArray();
    stats.key("notes").beginArray();
    for (const std::string& n : notes) stats.value(n);
    stats.endArray();
    stats.endObject();

    if (!cl.quiet && !notes.empty()) {
        constexpr size_t kShown = 20;
        for (size_t i = 0; i < notes.size() && i < kShown; ++i)
            std::fprintf(stderr, "pushpin: note: %s\n", oneLine(notes[i]).c_str());
        if (notes.size() > kShown)
            std::fprintf(stderr, "pushpin: note: ... and %zu more (see --stats)\n", notes.size() - kShown);
    }
    if (!cl.statsPath.empty()) writeWholeFile(cl.statsPath, stats.str() + "\n");
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    // First: from here on SIGINT, SIGTERM and exit() remove every temporary file still open.
    cache::installTemporaryFileCleanup();
    try {
        return run(argc, argv);
    } catch (const render::UsageError& e) {
        reportError(kExitUsage, e.what());
        return kExitUsage;
    } catch (const OutputError& e) {
        reportError(kExitOutput, e.what());
        return kExitOutput;
    } catch (const MemoryCapError& e) {
        reportError(kExitMemory, e.what());
        return kExitMemory;
    } catch (const scene::ParseError& e) {
        // The message begins with file:line:column.
        std::fprintf(stderr, "Error: %s\n", oneLine(e.what()).c_str());
        return kExitInput;
    } catch (const Error& e) {
        reportError(kExitInput, e.what());
        return kExitInput;
    } catch (const std::bad_alloc&) {
        // An allocation the cap did not foresee failed: the frame needs more memory than this
        // process could get, which a scheduler treats like the cap (retry with more memory).
        reportError(kExitMemory, "out of memory: an allocation failed (run with more memory, or a smaller -x/-y)");
        return kExitMemory;
    } catch (const std::exception& e) {
        reportError(kExitInternal, std::string("internal error: ") + e.what());
        return kExitInternal;
    }
}
