// penumbra-viewer: a GLFW window on the renderer of penumbra-render, with a Dear ImGui panel.
// Opens a level at its first glTF camera (spawn point) and cycles through the others; flies
// (WASD + QE, right mouse to look, wheel for speed) or orbits (O); switches method, light and
// debug view live; at each glTF camera hangs a lamp under the ceiling ahead (H: here);
// F1 stats overlay, F12/P screenshot, R reload shaders, Esc quit, drop a .glb.
// `--frames N [--screenshot FILE]` renders N frames and exits (scripted captures, CI).
#pragma once

#include <string>
#include <vector>

namespace viewer {

struct Options {
    std::string file;       // a .glb/.gltf (positional) or
    std::string scenePath;  // --scene FILE.json
    std::string size = "960x540";
    float renderScale = 1.0f;            // render at this fraction of the window, scaled up
    std::string method = "auto";
    std::vector<std::string> parameters; // --param NAME=VALUE
    int samples = 64;                    // reference / raytrace, and the error view's reference
    int camera = 0;                      // index into the file's views
    int frames = 0;                      // automation: render this many frames, then exit
    std::string screenshot;              // automation: write the last frame here
    std::string report;                  // automation: timings as JSON
    std::string visibility;              // automation: the last frame's V (PFM, NaN off-surface)
    bool flyThrough = false;             // move along the views, --leg-frames per leg
    int legFrames = 90;
    bool animateLight = false;
    bool sceneLight = false;             // keep the file's light at glTF cameras (no lamp per view)
    bool hideUi = false;
    // Scripted key presses: "FRAME:KEY,..." with KEY one of F1 F12 P R C O L V H Tab Esc (pressed)
    // or W A S D Q E (held for that frame), or drop=PATH (a file dropped on the window),
    // or wait=PATH (pause until that file exists: scripts synchronise with it).
    std::string keys;
    std::string debugView = "shaded"; // gpu::debugViews() name
    float simplify = 0.0f;            // --simplify E: stand-ins made under the light at load
};

// Throws geometry::InputError for bad options or input, gpu::ContextError when no window can
// be opened. Returns the process exit code.
int run(const Options& options);

} // namespace viewer
