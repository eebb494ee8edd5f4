// pushpin: renders Maya ASCII scenes. This front end parses the command line, loads the scene,
// renders every requested frame and camera (or prints the --info report) and writes the images;
// every error ends here as one line on stderr and a non-zero exit, with no partial image on disk.
#include "cache/error.h"
#include "core/render/camera.h"
#include "core/render/command_line.h"
#include "core/render/frame_scene.h"
#include "core/render/image_output.h"
#include "core/render/render_settings.h"
#include "core/render/renderer.h"
#include "core/scene/demo_scene.h"
#include "core/scene/evaluator.h"
#include "core/scene/ma_reader.h"
#include "core/scene/render_setup.h"
#include "core/scene/scene_info.h"
#include "core/util/json_writer.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <string_view>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace pushpin;

constexpr int kExitUsage = 2;
constexpr int kExitInput = 2;

// One line, whatever the message holds, so scripts can read the first line of stderr.
std::string oneLine(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
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
                throw Error("-cam: no camera '" + name + "' in " + sceneName + " (cameras: " +
                            (known.empty() ? "none" : known) + ")");
            }
            out.push_back(found);
        }
        return out;
    }
    for (const scene::CameraInfo& c : setup.cameras)
        if (c.renderable) out.push_back(&c);
    if (out.empty()) throw Error(sceneName + ": no renderable camera (name one with -cam)");
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

void writeFileAtomically(const fs::path& path, const std::string& text) {
    fs::path tmp = path;
    tmp += ".tmp-" + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw IoError(tmp, "cannot create the file", errno);
        out << text;
        out.flush();
        if (!out) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw IoError(tmp, "cannot write the file", errno);
        }
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw IoError(path, "cannot rename the finished file into place: " + ec.message());
    }
}

int run(int argc, char** argv) {
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
    if (cl.demo && !cl.scene.empty()) throw Error("give either --demo or a scene file, not both");
    if (!cl.demo && cl.scene.empty()) {
        std::string help = render::commandLineHelp();
        std::fwrite(help.data(), 1, help.size(), stderr);
        return kExitUsage;
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
    const fs::path outputDir = cl.outputDir.empty() ? fs::path(".") : fs::path(cl.outputDir);
    const std::string sceneStem = fs::path(sceneName).stem().string();
    std::error_code ec;
    const fs::path scenePath = cl.demo ? fs::path() : fs::weakly_canonical(fs::path(cl.scene), ec);

    util::JsonWriter stats;
    stats.beginObject();
    stats.field("scene", sceneName).field("loadSeconds", loadSeconds);
    stats.key("images").beginArray();
    std::set<std::string> notesSeen;
    std::vector<std::string> notes;
    auto note = [&](const std::string& n) {
        if (notesSeen.insert(n).second) notes.push_back(n);
    };
    for (const auto& w : graph.warnings())
        note(w.file + ":" + std::to_string(w.line) + ": " + (w.node.empty() ? "" : "node '" + w.node + "': ") + w.message);
    for (const auto& [type, count] : graph.unsupportedTypes())
        note("unsupported node type '" + type + "' (" + std::to_string(count) + " node" + (count == 1 ? "" : "s") + ")");

    for (double frame : frames) {
        auto tScene = std::chrono::steady_clock::now();
        scene::Evaluator ev(graph, frame);
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

        for (const scene::CameraInfo* cameraInfo : cameras) {
            render::RenderCamera camera =
                render::makeRenderCamera(ev, cameraInfo->path, settings.width, settings.height, settings.deviceAspectRatio);
            render::RenderSettings cameraSettings = settings;
            if (!cameraSettings.depth) cameraSettings.depth = ev.getBool(cameraInfo->shape, "depth", false);
            fs::path path = render::imageFilePath(cameraSettings, format, outputDir, sceneStem, camera.name, frame,
                                                  cameras.size() > 1);
            if (!scenePath.empty() && fs::weakly_canonical(path, ec) == scenePath)
                throw Error("the image path " + path.string() + " is the scene file itself; choose another -im or -rd");

            render::RenderStats renderStats;
            auto tRender = std::chrono::steady_clock::now();
            render::Framebuffer image = render::renderFrame(frameScene, camera, cameraSettings, renderStats);
            const double renderSeconds = secondsSince(tRender);
            auto tWrite = std::chrono::steady_clock::now();
            render::writeImage(image, path, format, cameraSettings, cameraSettings.depth.value_or(false));
            const double writeSeconds = secondsSince(tWrite);

            if (!cl.quiet)
                std::fprintf(stderr, "pushpin: frame %g, camera %s: %dx%d in %.2f s -> %s\n", frame, camera.name.c_str(),
                             image.width, image.height, renderSeconds, path.string().c_str());
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
    }
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
    if (!cl.statsPath.empty()) writeFileAtomically(cl.statsPath, stats.str() + "\n");
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const scene::ParseError& e) {
        std::fprintf(stderr, "%s\n", oneLine(e.what()).c_str());
        return kExitInput;
    } catch (const Error& e) {
        std::fprintf(stderr, "pushpin: %s\n", oneLine(e.what()).c_str());
        return kExitInput;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "pushpin: out of memory\n");
        return 3;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pushpin: internal error: %s\n", oneLine(e.what()).c_str());
        return 4;
    }
}
