// core/render/command_line.h: the pushpin command line: the `Render -r sw` flags that apply
// (reference/render-cli.md) plus pushpin's own long options, parsed into one value. Flags and
// arguments are separate tokens; booleans take on/yes/true/1 and off/no/false/0; `-eaa` and
// `-pft` take Maya's numbers or the old keywords. Unknown flags and bad values throw UsageError
// naming the flag and the value (at most util::kMaxQuotedChars of it).
// Pure functions; thread-safe.
#pragma once

#include "cache/error.h"
#include "core/render/render_settings.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pushpin::render {

// The command line itself is wrong: an unknown flag, a missing or bad value, no scene. The tools
// exit 2 for it (farm.md §6: a usage error, not worth a retry), where a bad scene exits 1.
class UsageError : public Error {
public:
    using Error::Error;
};

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
    std::string project;           // -proj: the Maya project whose images folder images go to
    std::string statsPath;         // --stats out.json
    std::string tilePatternPath;   // --tile-pattern out.png
    bool quiet = false;            // --quiet: no progress lines on stderr
    // --allow-scene-output-paths: images may go where the image prefix says even outside the
    // output folder (an absolute imageFilePrefix, or one that climbs out with "..").
    bool allowSceneOutputPaths = false;
    // Render-globals overrides, in the order given; see applyOverrides().
    struct Override {
        std::string flag;   // as written, for messages
        std::string value;  // validated text
    };
    std::vector<Override> overrides;
    // Render flags for features pushpin does not render yet: accepted so that a farm's command
    // line runs, and reported under notRendered with the feature they belong to.
    struct NotApplied {
        std::string feature;  // "motion blur", "ray tracing", … (the features of scene::NotRendered)
        std::string flag;     // "-mbf 0.5" as given
    };
    std::vector<NotApplied> notApplied;
    // Flags that turn a feature pushpin does not render on or off (-mb, -ert, -edm, -iip …): off
    // takes effect (nothing is missing from the render any more); on is reported like the scene's.
    struct FeatureSwitch {
        std::string feature;
        std::string flag;  // "-mb on"
        bool on = false;
    };
    std::vector<FeatureSwitch> featureSwitches;
};

// Parses argv[1..]. Throws UsageError("-x: 'abc' is not an integer"), ("unknown option '-zz'"),
// ("-reg needs 4 values") … A second scene file is an error.
CommandLine parseCommandLine(const std::vector<std::string_view>& args);

// Applies the command line's render-globals overrides (-x -y -eaa -ss -mss -ufil -pft -pfx -pfy
// -rct -gct -bct -cct -s -e -b -pad -im -of -fnc -g -n -tw -th -reg -premul -rgb -alpha -depth
// -mm …) to settings read from the scene. -mm MB sets maximumMemoryBytes (MB · 2^20).
void applyOverrides(const CommandLine& commandLine, RenderSettings& settings);

// The --help text.
std::string commandLineHelp();

}  // namespace pushpin::render
