// libFuzzer entry point for the whole frame: any .ma input that loads must evaluate, build its
// frame scene and render every renderable camera at a small size without crashing, with finite
// pixels; bad content may only end in pushpin::Error. References are not followed.
#include "core/render/camera.h"
#include "core/render/frame_scene.h"
#include "core/render/render_settings.h"
#include "core/render/renderer.h"
#include "core/scene/ma_reader.h"
#include "core/scene/render_setup.h"
#include "core/scene/scene_info.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace pushpin;
    scene::ReadOptions options;
    options.loadReferences = false;
    try {
        scene::Graph graph = scene::MaReader::readString(
            std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.ma", options);
        scene::Evaluator ev(graph, scene::sceneCurrentFrame(graph));
        scene::RenderSetup setup = scene::extractRenderSetup(graph);
        std::vector<std::string> notes;
        render::RenderSettings s = render::readRenderSettings(ev, setup, notes);
        // Small frames keep each input fast; the quality settings stay as the scene says.
        s.width = 24;
        s.height = 18;
        s.deviceAspectRatio = 24.0 / 18.0;
        s.numCpusToUse = 1;
        render::FrameScene frame = render::buildFrameScene(ev, setup, s);
        size_t cameras = 0;
        for (const scene::CameraInfo& c : setup.cameras) {
            if (!c.renderable || ++cameras > 2) continue;
            try {
                render::RenderCamera camera = render::makeRenderCamera(ev, c.path, s.width, s.height, s.deviceAspectRatio);
                render::RenderStats stats;
                render::Framebuffer image = render::renderFrame(frame, camera, s, stats);
                for (float v : image.rgba)
                    if (!std::isfinite(v)) std::abort();
            } catch (const Error&) {
            }
        }
    } catch (const Error&) {
    }
    return 0;
}
