// penumbra-viewer [FILE.glb | --scene FILE.json] [--size WxH] [--method NAME] ...
// Exit codes: 0 success, 2 bad input or no display/window (a clear message), 1 internal error.
#include "Viewer.h"

#include <apps/AppCommon.h>
#include <apps/Flags.h>
#include <geometry/core/Error.h>
#include <gpu/gl/Context.h>
#include <gpu/Methods.h>
#include <gpu/Renderer.h>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    CLI::App app{"penumbra-viewer: fly through a level with soft shadows from an area light"};
    viewer::Options opt;
    app.add_option("file", opt.file, "a .glb/.gltf to open (at its first glTF camera)");
    app.add_option("--scene", opt.scenePath, "a scene JSON instead of a glTF file");
    apps::addSizeOption(app, opt.size, "window size WIDTHxHEIGHT");
    app.add_option("--render-scale", opt.renderScale,
                   "render at this fraction of the window (0.125..1), scaled up when shown")
        ->capture_default_str();
    apps::addMethodOption(app, opt.method,
                          "visibility method at start (" + gpu::methodNameList(true) + ")")
        ->capture_default_str();
    apps::addParamOption(app, opt.parameters);
    apps::addSamplesOption(app, opt.samples);
    app.add_option("--camera", opt.camera, "start at this glTF camera (0 = the first)")
        ->capture_default_str();
    app.add_option("--frames", opt.frames,
                   "render this many frames, then exit (scripted captures; time steps 1/30 s)");
    app.add_option("--screenshot", opt.screenshot, "with --frames: write the last frame (PNG)");
    app.add_option("--report", opt.report, "with --frames: write timings as JSON");
    app.add_option("--visibility", opt.visibility,
                   "with --frames: write the last frame's visibility V (PFM)");
    app.add_flag("--fly-through", opt.flyThrough,
                 "move the camera from each glTF camera to the next");
    app.add_option("--leg-frames", opt.legFrames, "frames per leg of --fly-through")
        ->capture_default_str();
    app.add_flag("--scene-light", opt.sceneLight,
                 "keep the file's light at glTF cameras (default: a lamp under the ceiling ahead "
                 "of each)");
    app.add_flag("--animate-light", opt.animateLight, "move the light on a circle in its plane");
    app.add_option("--keys", opt.keys,
                   "with --frames: scripted keys, FRAME:KEY,... (F1 F12 P R C O L V H Tab Esc, W A S D "
                   "Q E held one frame, drop=FILE, wait=FILE)");
    std::string views;
    for (const gpu::DebugViewInfo& v : gpu::debugViews()) views += (views.empty() ? "" : ", ") + std::string(v.name);
    app.add_option("--debug-view", opt.debugView, "debug view at start (" + views + ")")
        ->capture_default_str();
    app.add_flag("--hide-ui", opt.hideUi, "start without the panel and overlay (Tab, F1)");
    // As penumbra-render's, made once under the light the file is loaded with (a JSON scene's
    // light, a glTF's framed light; dropped files too): a smaller or farther light later is not
    // covered by the bound.
    apps::addSimplifyOption(app, opt.simplify);
    return apps::runCommandLine(app, argc, argv, "penumbra-viewer",
                                apps::ParseErrorStyle::Cli11, [&] {
        try {
            return viewer::run(opt);
        } catch (const gpu::ContextError& e) { // not an InputError: no display is no bad input
            std::fprintf(stderr, "penumbra-viewer: error: cannot open a window: %s\n", e.what());
            return apps::kExitInputError;
        }
    });
}
