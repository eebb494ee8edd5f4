// core/render/command_line.h: the pushpin command line: the `Render -r sw` flags that apply
// (reference/render-cli.md) plus pushpin's own long options, parsed into one value. Flags and
// arguments are separate tokens; booleans take on/yes/true/1 and off/no/false/0; `-eaa` and
// `-pft` take Maya's numbers or the old keywords. Unknown flags and bad values throw
// pushpin::Error naming the flag and the value.
// Pure functions; thread-safe.
#pragma once

#include "core/render/render_settings.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pushpin::render {


struct CommandLine {
    std::string scene;             // the .ma file (empty with --demo)
    bool demo = false;             // --demo: the built-in demo scene
    bool info = false;             // --info: JSON scene report instead of rendering
    bool printDemo = false;        // --print-demo
    bool help = false;             // -h, --help, -help
    bool version = false;          // --version
    bool loadReferences = true;    // --no-references turns it off
    std::optional<double> frame;   // --frame F: one frame (overrides -s/-e)
    std::vector<std::string> cameras;  // -cam (repeatable): only these cameras render
    std::string outputDir;         // -rd
    std::string statsPath;         // --stats out.json
    bool quiet = false;            // --quiet: no progress lines on stderr
    // Render-globals overrides, in the order given; see applyOverrides().
    struct Override {
        std::string flag;   // as written, for messages
        std::string value;  // validated text
    };
    std::vector<Override> overrides;
};

// Parses argv[1..]. Throws pushpin::Error("-x: 'abc' is not an integer"), ("unknown option '-zz'"),
// ("-reg needs 4 values") … A second scene file is an error.
CommandLine parseCommandLine(const std::vector<std::string_view>& args);

// Applies the command line's render-globals overrides (-x -y -eaa -ss -mss -ufil -pft -pfx -pfy
// -rct -gct -bct -cct -s -e -b -pad -im -of -fnc -g -n -tw -th -reg -premul -rgb -alpha -depth …)
// to settings read from the scene.
void applyOverrides(const CommandLine& commandLine, RenderSettings& settings);

// The --help text.
std::string commandLineHelp();

}  // namespace pushpin::render
