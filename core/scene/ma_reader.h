// core/scene/ma_reader.h: reads Maya ASCII (.ma) text into a scene::Graph.
// The reader tokenises the restricted MEL a .ma file is, one command at a time, without holding
// more than one copy of the file (it streams through a fixed-size buffer). scriptNode bodies and
// any MEL/Python are stored as strings and never executed. Unknown commands, node types and
// attributes are kept or skipped with a warning, never fatal.
// Thread safety: each call builds its own Graph; concurrent calls are independent.
#pragma once

#include "cache/error.h"
#include "core/scene/graph.h"

#include <filesystem>
#include <istream>
#include <string>
#include <string_view>

namespace pushpin::scene {

// A .ma file that cannot be read: `file:line:column: message`, plus the node it concerned (if any).
class ParseError : public Error {
public:
    ParseError(std::string file, uint32_t line, uint32_t column, std::string node, const std::string& message);
    const std::string& file() const { return m_file; }
    uint32_t line() const { return m_line; }
    uint32_t column() const { return m_column; }
    const std::string& node() const { return m_node; }
    const std::string& message() const { return m_message; }  // without the position and node

private:
    std::string m_file;
    uint32_t m_line, m_column;
    std::string m_node;
    std::string m_message;
};

// How a load treats references (`file -r`). A reference to a file that is already being loaded
// (compared by canonical path, so `./a.ma` and `a.ma` are one file) is refused with a warning, as
// Maya refuses a recursive reference. The totals bound a fan-out (A references B ten times, B
// references C ten times, …): past either one the load stops with a ParseError naming the file and
// line of the reference that crossed it.
struct ReadOptions {
    bool loadReferences = true;               // load the referenced .ma relative to the scene when found
    int maxReferenceDepth = 8;                // references nested deeper are not loaded (a warning)
    uint64_t maxReferences = 10000;           // references loaded in one load, all depths together
    uint64_t maxReferenceBytes = uint64_t(4) << 30;  // bytes of referenced files read in one load (4 GiB)
};

class MaReader {
public:
    // Reads a file. Throws IoError (naming the path) when it is not a regular file (a directory, a
    // device) or cannot be opened, and ParseError on malformed content or a reference budget crossed.
    // A file that starts with Maya's `//Maya ASCII` header but lacks the closing `// End of <name>`
    // comment Maya writes last gets a warning that it may be truncated; what it holds is kept.
    static Graph readFile(const std::filesystem::path& path, const ReadOptions& options = {});
    // Reads text already in memory; `name` stands for the file in messages and for resolving references.
    static Graph readString(std::string_view text, const std::string& name = "<string>",
                            const ReadOptions& options = {});
    // Reads from a stream (the general entry point the others use).
    static Graph readStream(std::istream& in, const std::string& name, const ReadOptions& options = {});
};

}  // namespace pushpin::scene
