// Maya ASCII reader: a command-at-a-time interpreter of the restricted MEL that .ma files are
// (reference/ma-format.md). Commands that build the graph are decoded; everything else is skipped
// with one warning per command name. Nothing is ever executed.
//
// Choices worth knowing:
// - A non-shared `createNode` whose name is taken is renamed the way Maya does (trailing number
//   incremented) with a warning, except when it names one of the implicit default nodes of
//   the same type, which is then reused (older files create `lightLinker1` without `-s`).
// - `:name` (root namespace) that does not exist yet is created as an implicit default node.
// - When a reference could not be loaded, edits and connections naming missing nodes become
//   warnings instead of errors, since those nodes live in the missing file.
// - Sizes written in the file (`-s`, array counts, ranges) are validated against the values that
//   follow and only ever reserve memory in proportion to the bytes left in the input.
#include "core/scene/ma_reader.h"

#include "core/scene/detail/ma_lexer.h"
#include "core/scene/detail/ma_number.h"
#include "core/util/format.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cerrno>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <unordered_set>

namespace pushpin::scene {

namespace {

std::string formatParseError(const std::string& file, uint32_t line, uint32_t column, const std::string& node,
                             const std::string& message) {
    std::string s = file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + message;
    if (!node.empty()) s += " (node '" + node + "')";
    return s;
}

// Text that is not Maya ASCII at all, or a load that must stop: a lexical error (binary bytes, an
// unterminated string), a statement cut off by the end of the file, a malformed expression, a
// reference budget crossed. Any other ParseError concerns one statement, which is skipped with
// a warning while the load goes on, as Maya goes on after a command fails.
class FatalParseError : public ParseError {
public:
    using ParseError::ParseError;
};

}  // namespace

ParseError::ParseError(std::string file, uint32_t line, uint32_t column, std::string node, const std::string& message)
    : Error(formatParseError(file, line, column, node, message)),
      m_file(std::move(file)),
      m_line(line),
      m_column(column),
      m_node(std::move(node)),
      m_message(message) {}

namespace {

using detail::MaLexer;
using detail::MaLexError;
using detail::MaNumber;
using detail::MaNumberStatus;
using detail::MaToken;
using detail::MaTokenKind;

// Largest multi index / array count accepted; MultiStore indexes elements with uint32.
constexpr int64_t kMaxIndex = 0x7fffffff;
// Arguments of one command other than setAttr values; guards against junk that never ends.
constexpr size_t kMaxArgs = size_t(1) << 20;

// Nodes every scene has that Graph() does not create; files name them as `:name`.
const char* implicitNodeType(std::string_view name) {
    static const std::pair<const char*, const char*> known[] = {
        {"defaultRenderingList1", "defaultRenderingList"},
        {"defaultLightList1", "defaultLightList"},
        {"defaultColorMgtGlobals", "colorManagementGlobals"},
        {"characterPartition", "partition"},
        {"sequenceManager1", "sequenceManager"},
        {"shaderGlow1", "shaderGlow"},
        {"initialMaterialInfo", "materialInfo"},
        {"standardSurface1", "standardSurface"},
        {"hyperGraphLayout", "hyperLayout"},
        {"globalCacheControl", "globalCacheControl"},
        {"dynController1", "dynController"},
        {"defaultViewColorManager", "viewColorManager"},
        {"dof1", "dof"},
        {"defaultLayer", "displayLayer"},
        {"defaultRenderLayer", "renderLayer"},
        {"renderLayerManager", "renderLayerManager"},
        {"layerManager", "displayLayerManager"},
    };
    for (auto& [n, t] : known)
        if (name == n) return t;
    return "unknown";
}

// Data types setAttr -type knows but pushpin keeps as tokens.
bool isRawDataType(std::string_view t) {
    static const char* const raw[] = {
        "attributeAlias", "dataPolyComponent", "dataReferenceEdits", "mesh", "lattice", "sphere", "cone",
        "reflectanceRGB", "spectrumRGB", "nurbsTrimface", "subd", "Int64Array", "matrixArray", "polyFace",
        "dynArrayAttrsData", "particleData", "nObject", "nId", "characterMapping", "componentArray",
    };
    for (const char* r : raw)
        if (t == r) return true;
    return false;
}

// The `-type` name of a data-typed attribute whose values are not plain numbers, or nullptr.
const char* dataTypeName(AttrType type) {
    switch (type) {
        case AttrType::PolyFaces: return "polyFaces";
        case AttrType::Mesh: return "mesh";
        case AttrType::NurbsCurve: return "nurbsCurve";
        case AttrType::NurbsSurface: return "nurbsSurface";
        case AttrType::ComponentList: return "componentList";
        case AttrType::StringArray: return "stringArray";
        default: return nullptr;
    }
}

// The flags of the commands a .ma file holds, from Maya's command documentation, with the number
// of arguments each takes in create mode. kBoolArg: a boolean that files may write or omit
// (`-k true`, `-k`). Commands look their flags up here; a flag that is not listed is skipped with
// its arguments by their shape (Parser::unknownFlagArgs).
constexpr int kBoolArg = -1;
struct FlagSpec {
    std::string_view shortName, longName;
    int args;
};
constexpr FlagSpec kCreateNodeFlags[] = {
    {"-n", "-name", 1}, {"-p", "-parent", 1}, {"-s", "-shared", 0}, {"-ss", "-skipSelect", 0}};
constexpr FlagSpec kAddAttrFlags[] = {
    {"-at", "-attributeType", 1}, {"-bt", "-binaryTag", 1}, {"-ci", "-cachedInternally", kBoolArg},
    {"-ct", "-category", 1}, {"-dt", "-dataType", 1}, {"-dv", "-defaultValue", 1},
    {"-dcb", "-disconnectBehaviour", 1}, {"-en", "-enumName", 1}, {"-ex", "-exists", 0},
    {"-fp", "-fromPlugin", kBoolArg}, {"-hxv", "-hasMaxValue", kBoolArg}, {"-hnv", "-hasMinValue", kBoolArg},
    {"-hsx", "-hasSoftMaxValue", kBoolArg}, {"-hsn", "-hasSoftMinValue", kBoolArg}, {"-h", "-hidden", kBoolArg},
    {"-im", "-indexMatters", kBoolArg}, {"-is", "-internalSet", kBoolArg}, {"-k", "-keyable", kBoolArg},
    {"-ln", "-longName", 1}, {"-max", "-maxValue", 1}, {"-min", "-minValue", 1}, {"-m", "-multi", 0},
    {"-nn", "-niceName", 1}, {"-nc", "-numberOfChildren", 1}, {"-p", "-parent", 1}, {"-pxy", "-proxy", 1},
    {"-r", "-readable", kBoolArg}, {"-sn", "-shortName", 1}, {"-smx", "-softMaxValue", 1},
    {"-smn", "-softMinValue", 1}, {"-s", "-storable", kBoolArg}, {"-uac", "-usedAsColor", 0},
    {"-uaf", "-usedAsFilename", 0}, {"-uap", "-usedAsProxy", 0}, {"-w", "-writable", kBoolArg},
    {"-c", "-cachedInternally", kBoolArg}};
constexpr FlagSpec kConnectAttrFlags[] = {
    {"-f", "-force", 0}, {"-l", "-lock", kBoolArg}, {"-na", "-nextAvailable", 0}, {"-rd", "-referenceDest", 1}};
constexpr FlagSpec kParentFlags[] = {
    {"-a", "-absolute", 0}, {"-add", "-addObject", 0}, {"-nc", "-noConnections", 0}, {"-nis", "-noInvScale", 0},
    {"-r", "-relative", 0}, {"-rm", "-removeObject", 0}, {"-s", "-shape", 0}, {"-w", "-world", 0}};
constexpr FlagSpec kSelectFlags[] = {
    {"-add", "-add", 0}, {"-af", "-addFirst", 0}, {"-all", "-all", 0}, {"-ado", "-allDagObjects", 0},
    {"-adn", "-allDependencyNodes", 0}, {"-cl", "-clear", 0}, {"-cc", "-containerCentric", 0},
    {"-d", "-deselect", 0}, {"-hi", "-hierarchy", 0}, {"-ne", "-noExpand", 0}, {"-r", "-replace", 0},
    {"-sym", "-symmetry", 0}, {"-sys", "-symmetrySide", 1}, {"-tgl", "-toggle", 0}, {"-vis", "-visible", 0}};
constexpr FlagSpec kRenameFlags[] = {{"-is", "-ignoreShape", 0}, {"-uid", "-uuid", 0}};
constexpr FlagSpec kRequiresFlags[] = {{"-nt", "-nodeType", 1}, {"-dt", "-dataType", 1}};
constexpr FlagSpec kFileFlags[] = {
    {"-r", "-reference", 0}, {"-rdi", "-referenceDepthInfo", 1}, {"-ns", "-namespace", 1},
    {"-rfn", "-referenceNode", 1}, {"-dr", "-deferReference", kBoolArg}, {"-rpr", "-renamingPrefix", 1},
    {"-typ", "-type", 1}, {"-op", "-options", 1}, {"-gl", "-groupLocator", 0}, {"-gr", "-groupReference", 0},
    {"-gn", "-groupName", 1}, {"-shd", "-sharedNodes", 1}, {"-mnc", "-mergeNamespacesOnClash", kBoolArg},
    {"-lrd", "-loadReferenceDepth", 1}, {"-iv", "-ignoreVersion", 0}, {"-dns", "-defaultNamespace", 0},
    {"-i", "-import", 0}, {"-o", "-open", 0}, {"-f", "-force", 0}, {"-pmt", "-prompt", kBoolArg},
    {"-lck", "-lockReference", 0}, {"-srf", "-sharedReferenceFile", 0}, {"-rnn", "-returnNewNodes", 0},
    {"-uc", "-usingNamespaces", kBoolArg}, {"-pr", "-preserveReferences", 0}, {"-rdi0", "-rdi0", 0}};
// fileInfo [-q] [-rm keyword] keyword value; relationship [-b] [-q] type node plugs… (its flags
// in Maya's files are query forms without arguments).
constexpr FlagSpec kFileInfoFlags[] = {{"-q", "-query", 0}, {"-rm", "-remove", 1}};
constexpr FlagSpec kRelationshipFlags[] = {{"-b", "-both", 0}, {"-q", "-query", 0}};
constexpr FlagSpec kLockNodeFlags[] = {
    {"-l", "-lock", kBoolArg}, {"-lu", "-lockUnpublished", kBoolArg}, {"-ic", "-ignoreComponents", 0},
    {"-lockName", "-lockName", kBoolArg}};

template <size_t N>
const FlagSpec* findFlag(const FlagSpec (&table)[N], std::string_view flag) {
    for (const FlagSpec& f : table)
        if (flag == f.shortName || flag == f.longName) return &f;
    return nullptr;
}

// Numeric tuple types and their component counts.
int tupleWidth(std::string_view t) {
    if (t == "double2" || t == "float2" || t == "long2" || t == "short2" || t == "int2") return 2;
    if (t == "double3" || t == "float3" || t == "long3" || t == "short3" || t == "int3") return 3;
    if (t == "double4") return 4;
    return 0;
}

bool isIdentifier(std::string_view w) {
    if (w.empty()) return false;
    auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
    if (!alpha(w.front())) return false;
    for (char c : w)
        if (!alpha(c) && !(c >= '0' && c <= '9')) return false;
    return true;
}

// Maya node names: letters, digits and '_', namespaces separated by ':'; not starting with a digit.
// A part of a node name: letters, digits and '_', not starting with a digit. Bytes above 0x7F
// count as letters: files from Maya 2013 and earlier carry names in the system's 8-bit encoding
// (Latin-1 `St\xfctzen`), newer ones in UTF-8; both are kept byte for byte.
bool isNamePart(std::string_view w) {
    if (w.empty()) return false;
    auto letter = [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || static_cast<unsigned char>(c) >= 0x80;
    };
    if (!letter(w.front())) return false;
    for (char c : w)
        if (!letter(c) && !(c >= '0' && c <= '9')) return false;
    return true;
}

bool isValidNodeName(std::string_view name) {
    if (name.empty()) return false;
    size_t start = 0;
    while (start <= name.size()) {
        size_t colon = name.find(':', start);
        if (colon == std::string_view::npos) colon = name.size();
        std::string_view part = name.substr(start, colon - start);
        if (part.empty()) {
            if (start != 0) return false;  // a leading ':' means the root namespace
        } else if (!isNamePart(part)) {
            return false;
        }
        start = colon + 1;
    }
    return true;
}

// State shared by a scene and the references it loads.
struct ReadContext {
    Graph& graph;
    const ReadOptions& options;
    std::set<std::string> warnedCommands;
    std::set<std::string> knownDataTypes;  // from `requires -dataType` and `addAttr -dt`
    std::set<std::string> skippedDataTypes;  // data types met and not modelled (reported once each)
    std::set<std::string> unknownFlags;      // "command -flag" met and not known (reported once each)
    // The -type of typed values given to an element of a multi, by (node, attribute): a later
    // statement continuing the same multi may omit it.
    std::map<std::pair<NodeId, std::string>, std::string, std::less<>> elementTypes;
    bool missingReferences = false;
    // Canonical paths of the files being loaded, outermost first: a reference to one of them is a cycle.
    std::vector<std::filesystem::path> loading;
    uint64_t referencesLoaded = 0;
    uint64_t referenceBytes = 0;
    // Next trailing number to try per base name when renaming (see Parser::freeName).
    std::unordered_map<std::string, uint64_t> nextSuffix;
    // The entry of nextSuffix used last, and its base: renames come in runs of one base.
    const std::string* lastSuffixBase = nullptr;
    uint64_t* lastSuffix = nullptr;
    uint64_t renamesReported = 0;
    uint64_t renamesUnreported = 0;
    uint64_t statementsSkipped = 0;  // statements that failed, in this file and its references
};

// Failed statements reported one by one; past this many, a load reports how many more it skipped.
constexpr uint64_t kMaxSkipWarnings = 200;

// Renames reported one by one; past this many, a load reports how many more it made.
constexpr uint64_t kMaxRenameWarnings = 100;

struct ResolvedPlug {
    NodeId node = kNoNode;
    std::vector<PlugSegment> segments;  // empty for a plain node name
};

class Parser {
public:
    Parser(ReadContext& ctx, MaLexer& lex, std::string fileName, std::filesystem::path sceneDir,
           std::string nsPrefix, int depth, uint64_t totalBytes)
        : m_ctx(ctx),
          m_g(ctx.graph),
          m_lex(lex),
          m_file(std::move(fileName)),
          m_sceneDir(std::move(sceneDir)),
          m_ns(std::move(nsPrefix)),
          m_depth(depth),
          m_totalBytes(totalBytes) {}

    void run();

private:
    // ---- tokens
    void lexNext(MaToken& t);
    void rawNext(MaToken& t);
    void peekRaw();
    void nextArg(MaToken& t);
    void appendConcatenation(MaToken& t);
    void advance() { nextArg(m_tok); }
    bool atCommandEnd();  // true at ';'; throws at end of input
    void collectArgs();
    void skipCommand();

    // ---- errors and warnings
    [[noreturn]] void fail(uint32_t line, uint32_t column, const std::string& message) const;
    [[noreturn]] void failAt(const MaToken& t, const std::string& message) const { fail(t.line, t.column, message); }
    // Ends the load: the text is not Maya ASCII here (see FatalParseError).
    [[noreturn]] void failSyntax(uint32_t line, uint32_t column, const std::string& message) const;
    [[noreturn]] void failSyntaxAt(const MaToken& t, const std::string& message) const {
        failSyntax(t.line, t.column, message);
    }
    // The number of arguments after the flag at m_args[i], of the collected command `command`:
    // from `table` for a known flag (a kBoolArg flag takes the next word only if it is a boolean);
    // else see unknownFlagArgs.
    template <size_t N>
    size_t flagArgs(const FlagSpec (&table)[N], std::string_view command, size_t i, size_t needed) {
        const FlagSpec* f = findFlag(table, m_args[i].text);
        if (!f) return unknownFlagArgs(command, i, needed);
        if (f->args != kBoolArg) {
            if (i + size_t(f->args) >= m_argc) failAt(m_args[i], std::string(command) + ": " + util::excerpt(m_args[i].text) + " needs a value");
            return size_t(f->args);
        }
        bool ignored = false;
        return i + 1 < m_argc && m_args[i + 1].kind == MaTokenKind::Word && detail::parseMaBool(m_args[i + 1].text, ignored) ? 1 : 0;
    }
    size_t unknownFlagArgs(std::string_view command, size_t i, size_t needed);
    // Warns once per command and flag that an unknown flag is skipped.
    void warnUnknownFlag(std::string_view command, std::string_view flag, uint32_t line, uint32_t column);
    // After a statement failed: warns (the first kMaxSkipWarnings times) and reads to its ';'.
    void skipFailedStatement(const std::string& command, const ParseError& e);
    void warn(uint32_t line, uint32_t column, const std::string& message);
    std::string describe(const MaToken& t) const;

    // ---- names
    std::string qualify(std::string_view name) const;
    NodeId lookupNode(std::string_view name, uint32_t line, uint32_t column, bool* tolerated);
    std::string freeName(const std::string& base);
    void nameFreed(const std::string& name);
    // midRange: a range may also stand before the last segment (`.wl[0:7].w`, setAttr only).
    bool resolvePlug(const MaToken& t, bool requireAttr, ResolvedPlug& out, bool midRange = false);
    void indexInstancePlug(const MaToken& written, ResolvedPlug& plug);
    void setAcrossMidRange(const MaToken& plug, ResolvedPlug& target, size_t range, UnitKind unit, double factor);
    void setCurrent(NodeId id);

    // ---- commands
    void dispatch(std::string_view command, uint32_t line, uint32_t column);
    void cmdRequires();
    void cmdCurrentUnit();
    void cmdFileInfo();
    void cmdCreateNode(uint32_t line);
    void cmdRename();
    void cmdSetAttr();
    void cmdAddAttr();
    void cmdConnectAttr(bool connect);
    void cmdParent();
    void cmdSelect();
    void cmdRelationship();
    void cmdLockNode();
    void cmdFile();
    void loadReference(const std::string& path, const std::string& ns, const std::string& type, uint32_t line,
                       uint32_t column);

    // ---- setAttr values
    double readNumber(UnitKind unit, double factor, const char* what);
    int64_t readInteger(const char* what, int64_t min, int64_t max);
    int64_t readIntegerNoAdvance(const char* what, int64_t min, int64_t max);
    size_t readPlainNumbers(std::vector<double>& out, size_t most, double factor);
    size_t readPlainIntegers(std::vector<int32_t>& out, size_t most, const char* what);
    size_t readNumberThenPlain(std::vector<double>& out, UnitKind unit, double factor, const char* what, size_t most);
    int64_t readCount(const char* what);
    bool readBoolWord(const char* what);
    void readNumbersUntilEnd(std::vector<double>& out, UnitKind unit, double factor);
    void readExactNumbers(std::vector<double>& out, int64_t count, UnitKind unit, double factor, const char* what);
    // `done` values of the list were read already (for the count in messages).
    void readInts(std::vector<int32_t>& out, int64_t count, const char* what, int64_t done = 0);
    // Just after the current token: the next value when it is a plain integer in [min, max] (the
    // current token is then stale until advanceAfterPlain()); false leaves it to the token path.
    bool plainIntegerAfterToken(int64_t& v, int64_t min, int64_t max, const char* what);
    // After plainIntegerAfterToken(): `count` integers, then the token after them is current.
    void readIntsAfterPlain(std::vector<int32_t>& out, int64_t count, const char* what);
    std::string readStringValue(const char* what);
    size_t plausibleCount(int64_t n) const;
    Value readPolyFaces(int64_t elements);
    Value readNurbsCurve();
    Value readNurbsSurface();
    Value readRawData(const std::string& type);

    ReadContext& m_ctx;
    Graph& m_g;
    MaLexer& m_lex;
    std::string m_file;
    std::filesystem::path m_sceneDir;
    std::string m_ns;  // namespace prefix of a referenced file ("ns:"), empty for the scene itself
    int m_depth;
    uint64_t m_totalBytes;  // 0 when unknown
    Units m_units;          // this file's currentUnit

    MaToken m_tok;   // current argument
    MaToken m_peek;  // one token of lookahead for string concatenation
    MaToken m_tmp;
    MaToken m_plug;  // plug of the current setAttr
    bool m_hasPeek = false;
    std::vector<MaToken> m_args;  // arguments of the current command (capacity reused)
    size_t m_argc = 0;

    NodeId m_current = kNoNode;
    bool m_currentMissing = false;  // the selected node lives in a reference that was not loaded
    // The node named in errors: a node of the graph, else a name as written (quoted short when used).
    NodeId m_errorNodeId = kNoNode;
    std::string m_errorNode;
    std::string errorNodeName() const {
        return util::excerpt(m_errorNodeId != kNoNode ? std::string_view(m_g.node(m_errorNodeId).name) : std::string_view(m_errorNode));
    }
    void setErrorNode(NodeId id) {
        m_errorNodeId = id;
        m_errorNode.clear();
    }
    void setErrorNode(std::string_view name) {
        m_errorNodeId = kNoNode;
        m_errorNode.assign(name);
    }
    std::vector<PlugSegment> m_segScratch;
};

// ------------------------------------------------------------------ tokens

void Parser::lexNext(MaToken& t) {
    try {
        m_lex.next(t);
    } catch (const MaLexError& e) {
        failSyntax(e.line, e.column, e.message);
    }
}

void Parser::rawNext(MaToken& t) {
    if (m_hasPeek) {
        std::swap(t, m_peek);
        m_hasPeek = false;
    } else {
        lexNext(t);
    }
}

void Parser::peekRaw() {
    if (!m_hasPeek) {
        lexNext(m_peek);
        m_hasPeek = true;
    }
}

// `"a" + "b"` continues a string; MEL needs it inside parentheses, but files written by hand omit them.
void Parser::appendConcatenation(MaToken& t) {
    for (;;) {
        peekRaw();
        if (!m_peek.isWord("+")) return;
        m_hasPeek = false;
        lexNext(m_tmp);
        if (m_tmp.kind != MaTokenKind::String) failSyntaxAt(m_tmp, "expected a string after '+', found " + describe(m_tmp));
        t.text += m_tmp.text;
    }
}

void Parser::nextArg(MaToken& t) {
    rawNext(t);
    if (t.kind == MaTokenKind::String) {
        appendConcatenation(t);
    } else if (t.kind == MaTokenKind::LParen) {
        const uint32_t line = t.line, column = t.column;
        rawNext(t);
        if (t.kind == MaTokenKind::String) {
            appendConcatenation(t);
        } else if (t.kind != MaTokenKind::Word) {
            failSyntaxAt(t, "expected a string expression after '(', found " + describe(t));
        }
        rawNext(m_tmp);
        if (m_tmp.kind != MaTokenKind::RParen) failSyntaxAt(m_tmp, "expected ')' to close the '(' at line " +
                                                                std::to_string(line) + ", found " + describe(m_tmp));
        t.line = line;
        t.column = column;
    }
}

bool Parser::atCommandEnd() {
    if (m_tok.kind == MaTokenKind::Semicolon) return true;
    if (m_tok.kind == MaTokenKind::End) failSyntaxAt(m_tok, "unexpected end of file: the last command has no ';'");
    return false;
}

void Parser::collectArgs() {
    m_argc = 0;
    for (;;) {
        advance();
        if (atCommandEnd()) return;
        if (m_argc == kMaxArgs) failAt(m_tok, "command has more than " + std::to_string(kMaxArgs) + " arguments");
        if (m_argc == m_args.size()) m_args.emplace_back();
        std::swap(m_args[m_argc++], m_tok);
    }
}

void Parser::skipCommand() {
    do advance();
    while (!atCommandEnd());
}

// ------------------------------------------------------------------ errors

void Parser::fail(uint32_t line, uint32_t column, const std::string& message) const {
    throw ParseError(m_file, line, column, errorNodeName(), message);
}

void Parser::failSyntax(uint32_t line, uint32_t column, const std::string& message) const {
    throw FatalParseError(m_file, line, column, errorNodeName(), message);
}

// A flag the command table does not list: warned once per command and flag, and skipped with the
// arguments its following tokens look like. Numbers and booleans are its arguments; one name or
// string is, only when enough non-flag tokens remain after it for the `needed` positional
// arguments the command has yet to see, so that an unknown flag never takes the node or plug.
void Parser::warnUnknownFlag(std::string_view command, std::string_view flag, uint32_t line, uint32_t column) {
    const std::string key = std::string(command) + " " + util::excerpt(flag);
    if (m_ctx.unknownFlags.size() < kMaxSkipWarnings && m_ctx.unknownFlags.insert(key).second)
        warn(line, column, std::string(command) + ": unknown flag " + util::excerpt(flag) +
                               " is skipped with its arguments (reported once)");
}

size_t Parser::unknownFlagArgs(std::string_view command, size_t i, size_t needed) {
    const MaToken& flag = m_args[i];
    warnUnknownFlag(command, flag.text, flag.line, flag.column);
    size_t n = 0;
    for (size_t j = i + 1; j < m_argc && !m_args[j].isFlag(); ++j) {
        const MaToken& t = m_args[j];
        if (t.kind == MaTokenKind::Word &&
            detail::parseMaNumber(t.text, UnitKind::None, m_units).status != MaNumberStatus::NotANumber) {
            ++n;
            continue;
        }
        size_t after = 0;
        for (size_t k = j + 1; k < m_argc; ++k)
            if (!m_args[k].isFlag()) ++after;
        if (n == 0 && after >= needed) n = 1;
        break;
    }
    return n;
}

void Parser::skipFailedStatement(const std::string& command, const ParseError& e) {
    if (m_ctx.statementsSkipped++ < kMaxSkipWarnings)
        m_g.warn(Diagnostic{e.file(), e.line(), e.column(), e.node(), e.message() + "; the statement is skipped"});
    if (command == "createNode") {
        // Statements that follow edit the node that was not made: they go with it, quietly.
        m_current = kNoNode;
        m_currentMissing = true;
    }
    while (!atCommandEnd()) rawNext(m_tok);
}

void Parser::warn(uint32_t line, uint32_t column, const std::string& message) {
    m_g.warn(Diagnostic{m_file, line, column, errorNodeName(), message});
}

std::string Parser::describe(const MaToken& t) const {
    switch (t.kind) {
        case MaTokenKind::Word: return "'" + t.text.substr(0, 40) + (t.text.size() > 40 ? "…'" : "'");
        case MaTokenKind::String: return "string \"" + t.text.substr(0, 40) + (t.text.size() > 40 ? "…\"" : "\"");
        case MaTokenKind::End: return "end of file";
        default: return "'" + util::excerpt(t.text) + "'";
    }
}

// ------------------------------------------------------------------ names

// Applies the namespace of a referenced file to a name or DAG path (`|a|b` → `|ns:a|ns:b`).
// `:name` stays in the root namespace.
std::string Parser::qualify(std::string_view name) const {
    if (m_ns.empty() || name.empty()) return std::string(name);
    if (name.front() == ':') return std::string(name);
    std::string out;
    size_t start = 0;
    while (start <= name.size()) {
        size_t bar = name.find('|', start);
        if (bar == std::string_view::npos) bar = name.size();
        std::string_view part = name.substr(start, bar - start);
        if (!part.empty()) {
            if (part.front() == ':') out += part.substr(1);
            else out += m_ns + std::string(part);
        }
        if (bar < name.size()) out += '|';
        start = bar + 1;
    }
    return out;
}

// `base` followed by the smallest number k >= 1 that no node is named with, as Maya numbers new
// and clashing nodes (mesh1, mesh2, …). Names are only ever freed by `rename`, which lowers the
// counter again (nameFreed), so each base resumes where it stopped: 20,000 nodes named "x" cost
// 20,000 lookups, not 200 million.
std::string Parser::freeName(const std::string& base) {
    if (!m_ctx.lastSuffixBase || *m_ctx.lastSuffixBase != base) {
        auto it = m_ctx.nextSuffix.try_emplace(base, 1).first;  // entries stay put as the map grows
        m_ctx.lastSuffixBase = &it->first;
        m_ctx.lastSuffix = &it->second;
    }
    uint64_t& next = *m_ctx.lastSuffix;
    std::string candidate;
    for (;; ++next) {
        char digits[24];
        const char* end = std::to_chars(digits, digits + sizeof digits, next).ptr;
        candidate.assign(base).append(digits, size_t(end - digits));
        if (m_g.find(candidate) == kNoNode) break;
    }
    ++next;
    return candidate;
}

void Parser::nameFreed(const std::string& name) {
    size_t digits = name.size();
    while (digits > 0 && name[digits - 1] >= '0' && name[digits - 1] <= '9') --digits;
    if (digits == name.size() || name[digits] == '0' || name.size() - digits > 18) return;  // not base + k
    auto it = m_ctx.nextSuffix.find(name.substr(0, digits));
    if (it == m_ctx.nextSuffix.end()) return;
    it->second = std::min<uint64_t>(it->second, std::stoull(name.substr(digits)));
}

// Finds a node by name or DAG path. `:name` that does not exist becomes an implicit default
// node. A missing node is an error unless a reference failed to load (then *tolerated is set).
NodeId Parser::lookupNode(std::string_view name, uint32_t line, uint32_t column, bool* tolerated) {
    if (tolerated) *tolerated = false;
    const std::string full = qualify(name);
    NodeId id = m_g.find(full);
    if (id != kNoNode) return id;
    if (const size_t arrow = full.find("->"); arrow != std::string::npos) {
        // An underworld path, `|curve1|curveShape1->|projectionCurve18`: the nodes below the arrow
        // live under the shape's own DAG (curves on a surface, projections), found child by child.
        id = m_g.find(std::string_view(full).substr(0, arrow));
        std::string_view rest = std::string_view(full).substr(arrow + 2);
        while (id != kNoNode && !rest.empty()) {
            const size_t bar = rest.find('|');
            std::string_view part = rest.substr(0, bar);
            if (part.size() >= 2 && part.substr(part.size() - 2) == "->") part.remove_suffix(2);  // a deeper underworld
            if (!part.empty()) id = m_g.childNamed(id, part);
            rest = bar == std::string_view::npos ? std::string_view() : rest.substr(bar + 1);
        }
        if (id != kNoNode) return id;
    }
    if (name.size() > 1 && name.front() == ':' && name.find('|') == std::string_view::npos &&
        isValidNodeName(name.substr(1))) {
        std::string_view bare = name.substr(1);
        id = m_g.createNode(implicitNodeType(bare), bare, kNoNode, 0);
        m_g.node(id).shared = true;
        return id;
    }
    if (tolerated && m_ctx.missingReferences) {
        *tolerated = true;
        warn(line, column, "no node named '" + util::excerpt(full) + "' (it may live in a reference that was not loaded); ignored");
        return kNoNode;
    }
    setErrorNode(full);
    fail(line, column, "no node named '" + util::excerpt(full) + "'");
}

// Splits "node.attr[1].child" / ".attr" into node and attribute path.
bool Parser::resolvePlug(const MaToken& t, bool requireAttr, ResolvedPlug& out, bool midRange) {
    if (t.kind != MaTokenKind::String && t.kind != MaTokenKind::Word)
        failAt(t, "expected a plug (\"node.attribute\"), found " + describe(t));
    std::string_view text = t.text;
    const size_t dot = text.find('.');
    std::string_view nodePart = dot == std::string_view::npos ? text : text.substr(0, dot);
    std::string_view attrPart = dot == std::string_view::npos ? std::string_view() : text.substr(dot);
    if (requireAttr && attrPart.empty()) failAt(t, "malformed plug \"" + util::excerpt(t.text) + "\": no attribute");
    out.segments.clear();
    if (!attrPart.empty()) {
        auto segs = parsePlugPath(attrPart);
        if (!segs || segs->empty()) failAt(t, "malformed plug \"" + util::excerpt(t.text) + "\"");
        for (size_t i = 0; i < segs->size(); ++i) {
            const PlugSegment& s = (*segs)[i];
            if (!s.indexed()) continue;
            if (s.last > kMaxIndex) failAt(t, "index out of range in plug \"" + util::excerpt(t.text) + "\"");
            if (s.last != s.first && i + 1 != segs->size() && (!midRange || i + 2 != segs->size() || segs->back().indexed()))
                failAt(t, "malformed plug \"" + util::excerpt(t.text) + "\": a range may only end the path or the parent of its last attribute");
        }
        out.segments = std::move(*segs);
    }
    if (nodePart.empty()) {
        if (m_current == kNoNode) {
            if (m_currentMissing) return false;
            failAt(t, "plug \"" + util::excerpt(t.text) + "\" names no node and no node is selected");
        }
        out.node = m_current;
        setErrorNode(m_current);
        return true;
    }
    bool tolerated = false;
    out.node = lookupNode(nodePart, t.line, t.column, &tolerated);
    if (tolerated) return false;
    setErrorNode(out.node);
    return true;
}

void Parser::setCurrent(NodeId id) {
    m_current = id;
    m_currentMissing = false;
    setErrorNode(id);
}

// ------------------------------------------------------------------ driver

void Parser::run() {
    for (;;) {
        const uint32_t lastLine = m_tok.line;  // where the previous command ended
        advance();
        if (m_tok.kind == MaTokenKind::End) {
            // Maya ends every .ma it writes with "// End of <name>"; without it the file was most
            // likely cut short at a command boundary (reference/ma-format.md).
            if (m_lex.hasMayaHeader() && !m_lex.endsWithEndComment())
                warn(lastLine, 0,
                     "the file starts with Maya's '//Maya ASCII' header but lacks the closing '// End of' comment "
                     "Maya writes last; it may be truncated (its last command ends on line " +
                         std::to_string(lastLine) + ")");
            return;
        }
        if (m_tok.kind == MaTokenKind::Semicolon) continue;
        if (m_tok.kind != MaTokenKind::Word || !isIdentifier(m_tok.text))
            failSyntaxAt(m_tok, "expected a command, found " + describe(m_tok));
        const std::string command = m_tok.text;
        const uint32_t line = m_tok.line, column = m_tok.column;
        setErrorNode(m_current);
        try {
            dispatch(command, line, column);
        } catch (const FatalParseError&) {
            throw;
        } catch (const ParseError& e) {
            skipFailedStatement(command, e);
        } catch (const Error& e) {
            // The Graph refused an operation (name clash, cycle…): report it where the command starts.
            skipFailedStatement(command, ParseError(m_file, line, column, errorNodeName(), command + ": " + e.what()));
        }
    }
}

void Parser::dispatch(std::string_view c, uint32_t line, uint32_t column) {
    if (c == "setAttr") return cmdSetAttr();
    if (c == "connectAttr") return cmdConnectAttr(true);
    if (c == "createNode") return cmdCreateNode(line);
    if (c == "addAttr") return cmdAddAttr();
    if (c == "rename") return cmdRename();
    if (c == "select") return cmdSelect();
    if (c == "relationship") return cmdRelationship();
    if (c == "disconnectAttr") return cmdConnectAttr(false);
    if (c == "parent") return cmdParent();
    if (c == "requires") return cmdRequires();
    if (c == "currentUnit") return cmdCurrentUnit();
    if (c == "fileInfo") return cmdFileInfo();
    if (c == "lockNode") return cmdLockNode();
    if (c == "file") return cmdFile();
    // dataStructure, applyMetadata, workspace, MEL procedures…: not part of the graph.
    if (m_ctx.warnedCommands.insert(std::string(c)).second)
        warn(line, column, "command '" + util::excerpt(c) + "' is not supported; skipped (reported once)");
    skipCommand();
}

// ------------------------------------------------------------------ simple commands

void Parser::cmdRequires() {
    collectArgs();
    std::vector<std::string> positional;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (a.isFlag()) {
            const size_t n = flagArgs(kRequiresFlags, "requires", i, positional.empty() ? 1 : 0);
            if ((a.text == "-dataType" || a.text == "-dt") && n == 1) m_ctx.knownDataTypes.insert(m_args[i + 1].text);
            i += n;
            continue;
        }
        positional.push_back(a.text);
    }
    if (positional.empty()) failAt(m_tok, "requires: no plug-in named");
    std::string entry;
    for (const std::string& p : positional) entry += (entry.empty() ? "" : " ") + p;
    m_g.requirements.push_back(std::move(entry));
}

void Parser::cmdCurrentUnit() {
    collectArgs();
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (!a.isFlag()) failAt(a, "currentUnit: unexpected argument " + describe(a));
        const std::string_view f = a.text;
        const bool linear = f == "-l" || f == "-linear";
        const bool angle = f == "-a" || f == "-angle";
        const bool time = f == "-t" || f == "-time";
        if (!linear && !angle && !time) {
            // -f/-fullName, -ua/-updateAnimation: query/animation options with a value or none.
            if (i + 1 < m_argc && !m_args[i + 1].isFlag()) ++i;
            continue;
        }
        if (i + 1 >= m_argc) failAt(a, "currentUnit: " + util::excerpt(f) + " needs a unit");
        const MaToken& v = m_args[++i];
        if (linear) {
            auto cm = linearUnitInCm(v.text);
            if (!cm) failAt(v, "currentUnit: unknown linear unit " + describe(v));
            m_units.cmPerLinearUnit = *cm;
        } else if (angle) {
            auto rad = angleUnitInRadians(v.text);
            if (!rad) failAt(v, "currentUnit: unknown angle unit " + describe(v));
            m_units.radiansPerAngleUnit = *rad;
        } else {
            auto fps = timeUnitFps(v.text);
            if (!fps) failAt(v, "currentUnit: unknown time unit " + describe(v));
            m_units.framesPerSecond = *fps;
        }
    }
    if (m_depth == 0) m_g.units = m_units;
}

void Parser::cmdFileInfo() {
    collectArgs();
    std::vector<const MaToken*> positional;
    bool removes = false;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (a.isFlag()) {
            const size_t n = flagArgs(kFileInfoFlags, "fileInfo", i, positional.empty() ? 2 : 1);
            if (a.text == "-rm" || a.text == "-remove") {
                removes = true;
                if (m_depth == 0 && n == 1)
                    std::erase_if(m_g.fileInfo, [&](const auto& kv) { return kv.first == m_args[i + 1].text; });
            }
            i += n;
            continue;
        }
        positional.push_back(&a);
    }
    if (removes && positional.empty()) return;
    if (positional.size() != 2)
        failAt(m_tok, "fileInfo: expected a key and a value, found " + std::to_string(positional.size()) + " arguments");
    if (m_depth == 0) m_g.fileInfo.emplace_back(positional[0]->text, positional[1]->text);
}

void Parser::cmdCreateNode(uint32_t line) {
    collectArgs();
    const MaToken* type = nullptr;
    const MaToken* name = nullptr;
    const MaToken* parent = nullptr;
    bool shared = false;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (!a.isFlag()) {
            if (type) failAt(a, "createNode: unexpected argument " + describe(a));
            type = &a;
            continue;
        }
        const std::string_view f = a.text;
        if (f == "-s" || f == "-shared") {
            shared = true;
        } else if (f == "-n" || f == "-name" || f == "-p" || f == "-parent") {
            if (i + 1 >= m_argc || m_args[i + 1].isFlag()) failAt(a, "createNode: " + util::excerpt(f) + " needs a value");
            (f[1] == 'n' ? name : parent) = &m_args[++i];
        } else {
            i += flagArgs(kCreateNodeFlags, "createNode", i, type ? 0 : 1);
        }
    }
    if (!type) failAt(m_tok, "createNode: no node type given");
    if (!isIdentifier(type->text)) failAt(*type, "createNode: invalid node type " + describe(*type));

    NodeId parentId = kNoNode;
    if (parent) {
        bool tolerated = false;
        parentId = lookupNode(parent->text, parent->line, parent->column, &tolerated);
        if (tolerated) parent = nullptr;  // its parent is in a missing reference: keep the node at world level
    }
    std::string nodeName;
    if (name) {
        if (!isValidNodeName(name->text) || name->text.front() == ':')
            failAt(*name, "createNode: invalid node name " + describe(*name));
        nodeName = qualify(name->text);
    } else {
        // Maya names an unnamed node after its type: mesh1, mesh2, …
        nodeName = freeName(qualify(type->text));
    }
    setErrorNode(nodeName);

    // An existing node of that name at that place in the DAG: reused for -s and implicit defaults.
    // Without a parent, none of that name means no clash either.
    bool mayClash = true;
    {
        NodeId existing = parent ? m_g.childNamed(parentId, nodeName) : m_g.find(nodeName);
        if (!parent && existing == kNoNode) mayClash = false;
        if (existing != kNoNode && !parent && !m_g.node(existing).parents().empty()) existing = kNoNode;
        if (existing != kNoNode) {
            const Node& n = m_g.node(existing);
            const bool implicitDefault = n.line == 0 && n.shared && n.type == type->text;
            if (shared || implicitDefault) {
                if (n.type != type->text)
                    warn(type->line, type->column,
                         "createNode -s: '" + util::excerpt(nodeName) + "' exists with type " + util::excerpt(n.type) + ", not " + util::excerpt(type->text));
                setCurrent(existing);
                return;
            }
        }
    }
    if (mayClash && m_g.clashingNode(type->text, nodeName, parentId)) {
        // Name taken: Maya renames the new node by incrementing its trailing number.
        std::string base = nodeName;
        while (!base.empty() && base.back() >= '0' && base.back() <= '9') base.pop_back();
        const std::string candidate = freeName(base);
        if (m_ctx.renamesReported < kMaxRenameWarnings) {
            ++m_ctx.renamesReported;
            warn(name ? name->line : type->line, name ? name->column : type->column,
                 "a node named '" + util::excerpt(nodeName) + "' already exists; the new " + util::excerpt(type->text) +
                     " is renamed '" + util::excerpt(candidate) + "'");
        } else {
            ++m_ctx.renamesUnreported;
        }
        nodeName = candidate;
    }
    const NodeId id = m_g.createNode(type->text, nodeName, parentId, line);
    if (shared) m_g.node(id).shared = true;
    setCurrent(id);
}

void Parser::cmdRename() {
    collectArgs();
    std::vector<const MaToken*> positional;
    bool uid = false;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (a.text == "-uid" || a.text == "-uuid") {
            uid = true;  // the name given is the node's UUID (Maya 2016+), which pushpin does not use
        } else if (a.isFlag()) {
            i += flagArgs(kRenameFlags, "rename", i, positional.empty() ? 1 : 0);
        } else {
            positional.push_back(&a);
        }
    }
    if (uid) return;
    if (positional.empty() || positional.size() > 2) failAt(m_tok, "rename: expected [node] newName");
    NodeId id = m_current;
    if (positional.size() == 2) {
        id = lookupNode(positional[0]->text, positional[0]->line, positional[0]->column, nullptr);
    } else if (id == kNoNode) {
        if (m_currentMissing) return;
        failAt(*positional[0], "rename: no node selected");
    }
    const MaToken& newName = *positional.back();
    if (!isValidNodeName(newName.text)) failAt(newName, "rename: invalid node name " + describe(newName));
    const std::string full = qualify(newName.text);
    if (m_g.find(full) != kNoNode && m_g.find(full) != id) failAt(newName, "rename: a node named '" + util::excerpt(full) + "' exists");
    const std::string oldName = m_g.node(id).name;
    m_g.rename(id, full);
    if (m_g.find(oldName) == kNoNode) nameFreed(oldName);
    if (id == m_current) setErrorNode(full);
}

void Parser::cmdFile() {
    collectArgs();
    std::string ns, type, renamingPrefix;
    const MaToken* path = nullptr;
    bool reference = false;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (!a.isFlag()) {
            path = &a;
            continue;
        }
        const std::string_view f = a.text;
        if (f == "-r" || f == "-reference") reference = true;
        if (f == "-rdi" || f == "-referenceDepthInfo") return;  // depth bookkeeping for Maya's UI
        const size_t n = flagArgs(kFileFlags, "file", i, path ? 0 : 1);
        if (n == 1) {
            const MaToken& v = m_args[i + 1];
            if (f == "-ns" || f == "-namespace") ns = v.text;
            else if (f == "-typ" || f == "-type") type = v.text;
            else if (f == "-rpr" || f == "-renamingPrefix") renamingPrefix = v.text;
        }
        i += n;
    }
    if (!reference) {
        if (m_ctx.warnedCommands.insert("file").second)
            warn(m_tok.line, m_tok.column, "file: only -r (reference) is supported; skipped (reported once)");
        return;
    }
    if (!path) failAt(m_tok, "file -r: no file named");
    if (ns.empty()) ns = renamingPrefix;
    if (ns.empty()) ns = std::filesystem::path(path->text).stem().string();
    loadReference(path->text, ns, type, path->line, path->column);
}

void Parser::loadReference(const std::string& pathText, const std::string& ns, const std::string& type,
                           uint32_t line, uint32_t column) {
    auto missing = [&](const std::string& why) {
        m_ctx.missingReferences = true;
        warn(line, column, "reference \"" + util::excerpt(pathText) + "\" not loaded: " + why +
                               "; its nodes are missing and edits to them are ignored");
    };
    if (!m_ctx.options.loadReferences) return missing("loading references is turned off");
    if (m_depth + 1 > m_ctx.options.maxReferenceDepth) return missing("reference depth limit reached");
    if (!isValidNodeName(ns)) return missing("invalid namespace '" + util::excerpt(ns) + "'");
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path given(pathText);
    std::vector<fs::path> candidates;
    if (given.is_absolute()) candidates.push_back(given);
    candidates.push_back(m_sceneDir / given);
    candidates.push_back(m_sceneDir / given.filename());
    fs::path found;
    for (const fs::path& c : candidates)
        if (!c.filename().empty() && fs::is_regular_file(c, ec)) {
            found = c;
            break;
        }
    if (found.empty()) return missing("file not found (looked next to the scene)");
    if (type == "mayaBinary" || found.extension() == ".mb") return missing("Maya binary files are not supported");
    // A file that is already being loaded (this one or one that references it): Maya refuses a
    // recursive reference, and loading it again would repeat without end.
    const fs::path canonical = fs::weakly_canonical(found, ec);
    const fs::path& identity = ec ? found : canonical;
    if (auto it = std::find(m_ctx.loading.begin(), m_ctx.loading.end(), identity); it != m_ctx.loading.end()) {
        std::string chain;
        for (; it != m_ctx.loading.end(); ++it) chain += util::excerpt(it->filename().string()) + " -> ";
        chain += util::excerpt(identity.filename().string());
        return missing("it is already being loaded (" + chain + "), a recursive reference");
    }
    const uint64_t size = fs::file_size(found, ec);
    if (m_ctx.referencesLoaded + 1 > m_ctx.options.maxReferences)
        failSyntax(line, column, "reference \"" + util::excerpt(pathText) + "\": more than " +
                               std::to_string(m_ctx.options.maxReferences) +
                               " references loaded in this scene (ReadOptions::maxReferences); the load stops here");
    if (!ec && size > m_ctx.options.maxReferenceBytes - std::min(m_ctx.referenceBytes, m_ctx.options.maxReferenceBytes))
        failSyntax(line, column, "reference \"" + util::excerpt(pathText) + "\": the referenced files would exceed " +
                               std::to_string(m_ctx.options.maxReferenceBytes) +
                               " bytes in this scene (ReadOptions::maxReferenceBytes); the load stops here");
    std::ifstream in(found, std::ios::binary);
    if (!in) return missing("cannot open " + util::excerpt(found.string()));
    ++m_ctx.referencesLoaded;
    m_ctx.referenceBytes += ec ? 0 : size;
    MaLexer lex(in);
    Parser sub(m_ctx, lex, found.string(), found.parent_path(), m_ns + ns + ":", m_depth + 1, ec ? 0 : size);
    m_ctx.loading.push_back(identity);
    struct PopLoading {
        std::vector<fs::path>& loading;
        ~PopLoading() { loading.pop_back(); }
    } pop{m_ctx.loading};
    sub.run();
    m_g.references.push_back(found.string());
}

// ------------------------------------------------------------------ connections, DAG, selection

// A per-instance attribute (instObjGroups, worldMatrix, worldMesh, …) of a DAG node named by one
// of its instance paths, without an index, is that instance's element: Maya writes
// "|group1|inst2|shape.iog" for the second instance's shading assignment.
void Parser::indexInstancePlug(const MaToken& written, ResolvedPlug& plug) {
    if (plug.segments.empty() || plug.segments.front().indexed() || plug.node == kNoNode) return;
    const std::string_view text = written.text;
    const std::string_view nodePart = text.substr(0, text.find('.'));
    if (nodePart.find('|') == std::string_view::npos) return;
    const Node& node = m_g.node(plug.node);
    if (!node.isDag()) return;
    const std::string_view attr = plug.segments.front().name;
    static constexpr std::string_view kPerInstance[] = {
        "iog", "instObjGroups", "wm", "worldMatrix", "wim", "worldInverseMatrix",
        "pm", "parentMatrix", "pim", "parentInverseMatrix"};
    bool perInstance = std::find(std::begin(kPerInstance), std::end(kPerInstance), attr) != std::end(kPerInstance);
    if (!perInstance && node.schema) {
        if (node.schema->isA("mesh")) perInstance = attr == "w" || attr == "worldMesh";
        else if (node.schema->isA("nurbsSurface") || node.schema->isA("nurbsCurve"))
            perInstance = attr == "ws" || attr == "worldSpace";
    }
    if (!perInstance) return;
    DagPathBudget budget;
    const std::vector<std::vector<NodeId>> paths = m_g.dagPaths(plug.node, &budget);
    if (paths.size() < 2) return;
    const std::string full = qualify(nodePart);
    for (size_t k = 0; k < paths.size(); ++k) {
        const std::string name = m_g.dagPathName(paths[k]);
        const bool match = full.front() == '|'
                               ? name == full
                               : name.size() > full.size() && name.compare(name.size() - full.size(), full.size(), full) == 0 &&
                                     name[name.size() - full.size() - 1] == '|';
        if (match) {
            plug.segments.front().first = plug.segments.front().last = int64_t(k);
            return;
        }
    }
}

void Parser::cmdConnectAttr(bool connect) {
    collectArgs();
    const char* cmd = connect ? "connectAttr" : "disconnectAttr";
    const MaToken* plugs[2] = {nullptr, nullptr};
    int count = 0;
    bool nextAvailable = false;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (a.isFlag()) {
            const std::string_view f = a.text;
            if (f == "-na" || f == "-nextAvailable") nextAvailable = true;
            else i += flagArgs(kConnectAttrFlags, cmd, i, size_t(2 - std::min(count, 2)));
            continue;
        }
        if (count == 2) failAt(a, std::string(cmd) + ": more than two plugs");
        plugs[count++] = &a;
    }
    if (count != 2) failAt(m_tok, std::string(cmd) + ": expected a source and a destination plug");
    ResolvedPlug src, dst;
    if (!resolvePlug(*plugs[0], true, src)) return;
    if (!resolvePlug(*plugs[1], true, dst)) return;
    for (const ResolvedPlug* p : {&src, &dst})
        if (p->segments.back().last != p->segments.back().first)
            failAt(*plugs[p == &src ? 0 : 1], std::string(cmd) + ": a plug cannot name a range");
    indexInstancePlug(*plugs[0], src);
    indexInstancePlug(*plugs[1], dst);
    Plug s{src.node, m_g.canonicalPath(src.node, src.segments)};
    Plug d{dst.node, m_g.canonicalPath(dst.node, dst.segments)};
    if (connect) {
        m_g.connect(std::move(s), std::move(d), nextAvailable);
    } else if (!m_g.disconnect(s, d)) {
        warn(plugs[0]->line, plugs[0]->column, "disconnectAttr: no connection " + util::excerpt(plugs[0]->text) + " -> " + util::excerpt(plugs[1]->text));
    }
}

void Parser::cmdParent() {
    collectArgs();
    bool add = false, world = false, remove = false;
    std::vector<const MaToken*> objects;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (!a.isFlag()) {
            objects.push_back(&a);
            continue;
        }
        const std::string_view f = a.text;
        if (f == "-add" || f == "-addObject") add = true;
        else if (f == "-w" || f == "-world") world = true;
        else if (f == "-rm" || f == "-removeObject") remove = true;
        else i += flagArgs(kParentFlags, "parent", i, objects.size() < 2 ? 2 - objects.size() : 0);
    }
    if (remove) {
        warn(m_tok.line, m_tok.column, "parent -rm (remove instance) is not supported; skipped");
        return;
    }
    if (objects.size() < (world ? 1u : 2u)) failAt(m_tok, "parent: expected child objects and a parent");
    NodeId parentId = kNoNode;
    size_t childCount = objects.size();
    if (!world) {
        const MaToken& p = *objects.back();
        bool tolerated = false;
        parentId = lookupNode(p.text, p.line, p.column, &tolerated);
        if (tolerated) return;
        --childCount;
    }
    for (size_t i = 0; i < childCount; ++i) {
        const MaToken& c = *objects[i];
        bool tolerated = false;
        NodeId child = lookupNode(c.text, c.line, c.column, &tolerated);
        if (tolerated) continue;
        setErrorNode(child);
        if (add && parentId != kNoNode) {
            const auto& ps = m_g.node(child).parents();
            if (std::find(ps.begin(), ps.end(), parentId) != ps.end()) {
                warn(c.line, c.column, "parent -add: '" + util::excerpt(c.text) + "' already is a child of '" + util::excerpt(objects.back()->text) + "'");
                continue;
            }
        }
        try {
            m_g.setParent(child, parentId, add && !world);
        } catch (const ParseError&) {
            throw;
        } catch (const Error& e) {
            failAt(c, std::string("parent: ") + e.what());
        }
    }
}

void Parser::cmdSelect() {
    collectArgs();
    bool clear = false;
    const MaToken* first = nullptr;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (a.isFlag()) {
            if (a.text == "-cl" || a.text == "-clear") clear = true;
            else i += flagArgs(kSelectFlags, "select", i, first ? 0 : 1);
            continue;
        }
        if (!first) first = &a;
    }
    if (!first) {
        if (clear) setCurrent(kNoNode);
        return;
    }
    bool tolerated = false;
    NodeId id = lookupNode(first->text, first->line, first->column, &tolerated);
    if (tolerated) {
        setCurrent(kNoNode);
        m_currentMissing = true;
        return;
    }
    setCurrent(id);
}

void Parser::cmdRelationship() {
    collectArgs();
    Relationship r;
    bool typed = false;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (a.isFlag()) {
            i += flagArgs(kRelationshipFlags, "relationship", i, 0);
            continue;
        }
        if (!typed) {
            r.type = a.text;
            typed = true;
            continue;
        }
        ResolvedPlug p;
        if (!resolvePlug(a, false, p)) return;
        r.plugs.push_back(Plug{p.node, p.segments.empty() ? std::string() : m_g.canonicalPath(p.node, p.segments)});
    }
    if (!typed || r.plugs.empty()) failAt(m_tok, "relationship: expected a type and plugs");
    m_g.addRelationship(std::move(r));
}

void Parser::cmdLockNode() {
    collectArgs();
    bool lock = true;
    std::vector<const MaToken*> nodes;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (!a.isFlag()) {
            nodes.push_back(&a);
            continue;
        }
        // lockUnpublished, ignoreComponents and lockName lock nothing a render reads; any other
        // flag is reported.
        const size_t n = flagArgs(kLockNodeFlags, "lockNode", i, nodes.empty() ? 1 : 0);
        if (a.text == "-l" || a.text == "-lock") {
            bool value = true;
            if (n == 1) detail::parseMaBool(m_args[i + 1].text, value);
            lock = value;
        }
        i += n;
    }
    if (nodes.empty()) {
        if (m_current != kNoNode) m_g.node(m_current).locked = lock;
        return;
    }
    for (const MaToken* n : nodes) {
        bool tolerated = false;
        NodeId id = lookupNode(n->text, n->line, n->column, &tolerated);
        if (!tolerated) m_g.node(id).locked = lock;
    }
}

// ------------------------------------------------------------------ addAttr

namespace {

struct AttributeType {
    AttrType type;
    UnitKind unit;
};

std::optional<AttributeType> attributeTypeFromAt(std::string_view t) {
    using A = AttrType;
    using U = UnitKind;
    static const std::pair<const char*, AttributeType> table[] = {
        {"bool", {A::Bool, U::None}},        {"long", {A::Int, U::None}},
        {"short", {A::Int, U::None}},        {"byte", {A::Int, U::None}},
        {"char", {A::Int, U::None}},         {"enum", {A::Enum, U::None}},
        {"float", {A::Float, U::None}},      {"double", {A::Double, U::None}},
        {"doubleLinear", {A::Double, U::Distance}}, {"floatLinear", {A::Float, U::Distance}},
        {"doubleAngle", {A::Double, U::Angle}},     {"floatAngle", {A::Float, U::Angle}},
        {"time", {A::Double, U::Time}},      {"float2", {A::Float2, U::None}},
        {"float3", {A::Float3, U::None}},    {"double2", {A::Double2, U::None}},
        {"double3", {A::Double3, U::None}},  {"double4", {A::Double4, U::None}},
        {"long2", {A::Long2, U::None}},      {"long3", {A::Long3, U::None}},
        {"short2", {A::Short2, U::None}},    {"short3", {A::Short3, U::None}},
        {"compound", {A::Compound, U::None}}, {"message", {A::Message, U::None}},
        {"matrix", {A::Matrix, U::None}},    {"fltMatrix", {A::Matrix, U::None}},
        {"reflectance", {A::Float3, U::None}}, {"spectrum", {A::Float3, U::None}},
        {"typed", {A::Generic, U::None}},    {"generic", {A::Generic, U::None}},
    };
    for (auto& [name, at] : table)
        if (t == name) return at;
    return std::nullopt;
}

AttrType attributeTypeFromDt(std::string_view t) {
    using A = AttrType;
    static const std::pair<const char*, AttrType> table[] = {
        {"string", A::String},          {"stringArray", A::StringArray}, {"matrix", A::Matrix},
        {"Int32Array", A::Int32Array},  {"doubleArray", A::DoubleArray}, {"floatArray", A::DoubleArray},
        {"pointArray", A::PointArray},  {"vectorArray", A::VectorArray}, {"mesh", A::Mesh},
        {"nurbsCurve", A::NurbsCurve},  {"nurbsSurface", A::NurbsSurface}, {"componentList", A::ComponentList},
        {"double2", A::Double2},        {"double3", A::Double3},         {"float2", A::Float2},
        {"float3", A::Float3},          {"long2", A::Long2},             {"long3", A::Long3},
        {"short2", A::Short2},          {"short3", A::Short3},
    };
    for (auto& [name, at] : table)
        if (t == name) return at;
    return A::Generic;
}

}  // namespace

void Parser::cmdAddAttr() {
    collectArgs();
    AttrSpec spec;
    std::string parentName;
    const MaToken* targetNode = nullptr;
    bool hasType = false, hasDefault = false;
    double defaultValue = 0.0;
    for (size_t i = 0; i < m_argc; ++i) {
        const MaToken& a = m_args[i];
        if (!a.isFlag()) {
            if (targetNode) failAt(a, "addAttr: unexpected argument " + describe(a));
            targetNode = &a;
            continue;
        }
        const std::string_view f = a.text;
        auto value = [&]() -> const MaToken& {
            if (i + 1 >= m_argc) failAt(a, "addAttr: " + util::excerpt(f) + " needs a value");
            return m_args[++i];
        };
        if (f == "-ln" || f == "-longName") {
            spec.longName = value().text;
        } else if (f == "-sn" || f == "-shortName") {
            spec.shortName = value().text;
        } else if (f == "-at" || f == "-attributeType") {
            const MaToken& v = value();
            auto at = attributeTypeFromAt(v.text);
            if (!at) failAt(v, "addAttr: unknown attribute type " + describe(v));
            spec.type = at->type;
            spec.unit = at->unit;
            hasType = true;
        } else if (f == "-dt" || f == "-dataType") {
            const MaToken& v = value();
            spec.type = attributeTypeFromDt(v.text);
            m_ctx.knownDataTypes.insert(v.text);
            hasType = true;
        } else if (f == "-p" || f == "-parent") {
            parentName = value().text;
        } else if (f == "-dv" || f == "-defaultValue") {
            const MaToken& v = value();
            MaNumber n = detail::parseMaNumber(v.text, UnitKind::None, m_units);
            if (n.status != MaNumberStatus::Ok) failAt(v, "addAttr: -dv needs a finite number, found " + describe(v));
            defaultValue = n.value;
            hasDefault = true;
        } else if (f == "-m" || f == "-multi" || f == "-uac" || f == "-usedAsColor" || f == "-uaf" ||
                   f == "-usedAsFilename") {
            if (f == "-m" || f == "-multi") spec.multi = true;
        } else if (f == "-min" || f == "-minValue" || f == "-max" || f == "-maxValue" || f == "-smn" ||
                   f == "-softMinValue" || f == "-smx" || f == "-softMaxValue" || f == "-nc" ||
                   f == "-numberOfChildren" || f == "-dcb" || f == "-disconnectBehaviour") {
            const MaToken& v = value();
            if (detail::parseMaNumber(v.text, UnitKind::None, m_units).status != MaNumberStatus::Ok)
                failAt(v, "addAttr: " + util::excerpt(f) + " needs a finite number, found " + describe(v));
        } else if (f == "-nn" || f == "-niceName" || f == "-en" || f == "-enumName" || f == "-bt" ||
                   f == "-ct" || f == "-category") {
            value();
        } else {
            // Boolean options (-ci, -k, -h, -is, -im, -r, -w, -s, …) and flags pushpin has no use for.
            i += flagArgs(kAddAttrFlags, "addAttr", i, 0);
        }
    }
    if (spec.longName.empty()) spec.longName = spec.shortName;
    if (spec.shortName.empty()) spec.shortName = spec.longName;
    if (spec.longName.empty()) failAt(m_tok, "addAttr: no attribute name (-ln/-sn)");
    if (!isIdentifier(spec.longName) || !isIdentifier(spec.shortName))
        failAt(m_tok, "addAttr: invalid attribute name '" + util::excerpt(spec.longName) + "'");
    if (!hasType) spec.type = AttrType::Double;  // Maya's default attribute type

    NodeId nodeId = m_current;
    if (targetNode) {
        bool tolerated = false;
        nodeId = lookupNode(targetNode->text, targetNode->line, targetNode->column, &tolerated);
        if (tolerated) return;
    } else if (nodeId == kNoNode) {
        if (m_currentMissing) return;
        failAt(m_tok, "addAttr: no node selected");
    }
    Node& node = m_g.node(nodeId);
    setErrorNode(node.id);
    if (const AttrSpec* existing = node.findAttr(spec.longName) ? node.findAttr(spec.longName) : node.findAttr(spec.shortName)) {
        // Attributes some Maya versions add dynamically may be part of pushpin's schema already.
        bool dynamic = false;
        for (const AttrSpec& d : node.dynamicAttrs()) dynamic = dynamic || &d == existing;
        if (dynamic) warn(m_tok.line, m_tok.column, "addAttr: attribute '" + util::excerpt(spec.longName) + "' already exists; ignored");
        return;
    }
    if (hasDefault) spec.defaults = {defaultValue, defaultValue, defaultValue, defaultValue};
    if (!parentName.empty()) {
        AttrSpec* parent = nullptr;
        for (AttrSpec& s : node.mutableLinks().dynamicAttrs)
            if (s.longName == parentName || s.shortName == parentName) parent = &s;
        if (!parent) failAt(m_tok, "addAttr: parent attribute '" + util::excerpt(parentName) + "' does not exist");
        spec.parent = parent->longName;
        if (componentCount(parent->type) > 1) {
            int index = 0;
            for (const AttrSpec& s : node.dynamicAttrs())
                if (s.parent == parent->longName) ++index;
            if (index >= componentCount(parent->type))
                failAt(m_tok, "addAttr: '" + util::excerpt(parent->longName) + "' already has all its children");
            spec.component = index;
            if (parent->unit == UnitKind::None) parent->unit = spec.unit;
            if (hasDefault) parent->defaults[size_t(index)] = defaultValue;
        }
    }
    node.mutableLinks().dynamicAttrs.push_back(std::move(spec));
}

// ------------------------------------------------------------------ setAttr

size_t Parser::plausibleCount(int64_t n) const {
    // Every number takes at least two bytes ("0 "); never reserve more than the input can hold.
    const uint64_t left = m_totalBytes > m_lex.offset() ? (m_totalBytes - m_lex.offset()) / 2 + 16 : 4096;
    return size_t(std::min<uint64_t>(uint64_t(std::max<int64_t>(n, 0)), left));
}

double Parser::readNumber(UnitKind unit, double factor, const char* what) {
    if (atCommandEnd()) failAt(m_tok, std::string(what) + ": missing value");
    if (m_tok.kind != MaTokenKind::Word) failAt(m_tok, std::string(what) + ": expected a number, found " + describe(m_tok));
    MaNumber n = detail::parseMaNumber(m_tok.text, unit, m_units);
    switch (n.status) {
        case MaNumberStatus::Ok: break;
        case MaNumberStatus::NotANumber:
            failAt(m_tok, std::string(what) + ": expected a number, found " + describe(m_tok));
        case MaNumberStatus::NotFinite:
            failAt(m_tok, std::string(what) + ": value " + describe(m_tok) + " is not finite");
        case MaNumberStatus::OutOfRange:
            failAt(m_tok, std::string(what) + ": value " + describe(m_tok) + " is out of range");
    }
    advance();
    return n.hasUnit ? n.value : n.value * factor;
}

int64_t Parser::readIntegerNoAdvance(const char* what, int64_t min, int64_t max) {
    if (atCommandEnd()) failAt(m_tok, std::string(what) + ": missing value");
    int64_t v = 0;
    if (m_tok.kind != MaTokenKind::Word || !detail::parseMaInteger(m_tok.text, v))
        failAt(m_tok, std::string(what) + ": expected an integer, found " + describe(m_tok));
    if (v < min || v > max)
        failAt(m_tok, std::string(what) + ": " + std::to_string(v) + " is outside [" + std::to_string(min) + ", " +
                          std::to_string(max) + "]");
    return v;
}

int64_t Parser::readInteger(const char* what, int64_t min, int64_t max) {
    const int64_t v = readIntegerNoAdvance(what, min, max);
    advance();
    return v;
}

int64_t Parser::readCount(const char* what) { return readInteger(what, 0, kMaxIndex); }

bool Parser::readBoolWord(const char* what) {
    if (atCommandEnd()) failAt(m_tok, std::string(what) + ": missing value");
    bool b = false;
    if (m_tok.kind != MaTokenKind::Word || !detail::parseMaBool(m_tok.text, b))
        failAt(m_tok, std::string(what) + ": expected yes or no, found " + describe(m_tok));
    advance();
    return b;
}

// Long lists of plain numbers skip the token path: after the current token, the lexer reads each
// following plain number in place (MaLexer::nextPlainNumber); anything else goes back to tokens.
size_t Parser::readPlainNumbers(std::vector<double>& out, size_t most, double factor) {
    if (m_hasPeek) return 0;
    size_t n = 0;
    double v = 0.0;
    try {
        while (n < most && m_lex.nextPlainNumber(v)) {
            out.push_back(v * factor);
            ++n;
        }
    } catch (const MaLexError& e) {
        failSyntax(e.line, e.column, e.message);
    }
    return n;
}

size_t Parser::readPlainIntegers(std::vector<int32_t>& out, size_t most, const char* what) {
    if (m_hasPeek) return 0;
    size_t n = 0;
    int64_t v = 0;
    try {
        while (n < most && m_lex.nextPlainInteger(v)) {
            if (v < INT32_MIN || v > INT32_MAX)
                failSyntax(m_lex.line(), m_lex.column(), std::string(what) + ": " + std::to_string(v) + " is outside [" +
                                                              std::to_string(INT32_MIN) + ", " + std::to_string(INT32_MAX) + "]");
            out.push_back(int32_t(v));
            ++n;
        }
    } catch (const MaLexError& e) {
        failSyntax(e.line, e.column, e.message);
    }
    return n;
}

size_t Parser::readNumberThenPlain(std::vector<double>& out, UnitKind unit, double factor, const char* what,
                                   size_t most) {
    // The current token by the full rules, then plain numbers straight from the lexer.
    if (atCommandEnd()) failAt(m_tok, std::string(what) + ": missing value");
    if (m_tok.kind != MaTokenKind::Word) failAt(m_tok, std::string(what) + ": expected a number, found " + describe(m_tok));
    MaNumber n = detail::parseMaNumber(m_tok.text, unit, m_units);
    if (n.status != MaNumberStatus::Ok) {
        readNumber(unit, factor, what);  // fails with the token's own error
        return 0;
    }
    out.push_back(n.hasUnit ? n.value : n.value * factor);
    const size_t more = most > 1 ? readPlainNumbers(out, most - 1, factor) : 0;
    advance();
    return 1 + more;
}

void Parser::readNumbersUntilEnd(std::vector<double>& out, UnitKind unit, double factor) {
    while (!atCommandEnd()) readNumberThenPlain(out, unit, factor, "setAttr", SIZE_MAX);
}

void Parser::readExactNumbers(std::vector<double>& out, int64_t count, UnitKind unit, double factor, const char* what) {
    out.reserve(out.size() + plausibleCount(count));
    for (int64_t i = 0; i < count;) {
        if (atCommandEnd())
            failAt(m_tok, std::string(what) + ": expected " + std::to_string(count) + " numbers, found " + std::to_string(i));
        i += int64_t(readNumberThenPlain(out, unit, factor, what, size_t(count - i)));
    }
}

void Parser::readInts(std::vector<int32_t>& out, int64_t count, const char* what, int64_t done) {
    out.reserve(std::min<size_t>(plausibleCount(count), 64));
    for (int64_t i = 0; i < count;) {
        if (atCommandEnd())
            failAt(m_tok, std::string(what) + ": expected " + std::to_string(done + count) + " values, found " +
                              std::to_string(done + i));
        out.push_back(int32_t(readIntegerNoAdvance(what, INT32_MIN, INT32_MAX)));
        ++i;
        i += int64_t(readPlainIntegers(out, size_t(count - i), what));
        advance();
    }
}

bool Parser::plainIntegerAfterToken(int64_t& v, int64_t min, int64_t max, const char* what) {
    if (m_hasPeek) return false;
    try {
        if (!m_lex.nextPlainInteger(v)) return false;
    } catch (const MaLexError& e) {
        failSyntax(e.line, e.column, e.message);
    }
    if (v < min || v > max)
        failSyntax(m_lex.line(), m_lex.column(), std::string(what) + ": " + std::to_string(v) + " is outside [" +
                                                      std::to_string(min) + ", " + std::to_string(max) + "]");
    return true;
}

void Parser::readIntsAfterPlain(std::vector<int32_t>& out, int64_t count, const char* what) {
    out.reserve(std::min<size_t>(plausibleCount(count), 64));
    const int64_t got = int64_t(readPlainIntegers(out, size_t(count), what));
    advance();
    if (got < count) readInts(out, count - got, what, got);
}

std::string Parser::readStringValue(const char* what) {
    if (atCommandEnd()) failAt(m_tok, std::string(what) + ": missing string");
    if (m_tok.kind != MaTokenKind::String) failAt(m_tok, std::string(what) + ": expected a string, found " + describe(m_tok));
    std::string s = std::move(m_tok.text);
    advance();
    return s;
}

Value Parser::readPolyFaces(int64_t elements) {
    PolyFaces::Builder faces;
    // A face record takes at least 10 bytes ("f 3 0 1 2 "), which bounds what the range may reserve.
    faces.reserve(plausibleCount(elements * 5) / 5);
    std::vector<int32_t> ids;  // the ids of one record, as read
    auto room = [&](uint32_t line, uint32_t column, int64_t n) {
        if (!faces.fits(size_t(n)))
            fail(line, column, "polyFaces: more than " + std::to_string(PolyFaces::Builder::kMaxIds) + " ids in one value");
    };
    while (!atCommandEnd()) {
        if (m_tok.kind != MaTokenKind::Word)
            failAt(m_tok, "polyFaces: expected f, h, mu, mf, mh or fc, found " + describe(m_tok));
        const uint32_t line = m_tok.line, column = m_tok.column;
        const std::string key = m_tok.text;
        // Counts and ids are read straight from the lexer while they are plain integers.
        if (key == "f" || key == "h") {
            if (key == "h" && faces.faceCount() == 0) fail(line, column, "polyFaces: hole 'h' before any face 'f'");
            int64_t n = 0;
            const bool plain = plainIntegerAfterToken(n, 1, kMaxIndex, "polyFaces: edge count");
            if (!plain) {
                advance();
                n = readInteger("polyFaces: edge count", 1, kMaxIndex);
            }
            room(line, column, n);
            const char* what = key == "f" ? "polyFaces: face edges" : "polyFaces: hole edges";
            ids.clear();
            if (plain) readIntsAfterPlain(ids, n, what);
            else readInts(ids, n, what);
            if (key == "f") faces.addFace(ids);
            else faces.addHole(ids);
        } else if (key == "mu" || key == "mf" || key == "mh" || key == "fc") {
            // mu and fc belong to the last loop, mf to the last face's outer loop, mh to its last hole.
            const size_t loops = faces.loopCount();
            if (key == "mh" ? loops < 2 : loops == 0)
                fail(line, column, "polyFaces: '" + key + "' before the loop it belongs to");
            const size_t loop = key == "mf" ? 0 : loops - 1;
            const char* countWhat = key == "mu" ? "polyFaces: mu count" : key == "mf" ? "polyFaces: mf count"
                                    : key == "mh" ? "polyFaces: mh count" : "polyFaces: fc count";
            int64_t uvSet = 0, n = 0;
            const bool setPlain = key != "mu" || plainIntegerAfterToken(uvSet, 0, kMaxIndex, "polyFaces: uv set");
            const bool plain = setPlain && plainIntegerAfterToken(n, 0, kMaxIndex, countWhat);
            if (!plain) {
                // The token path from wherever the plain reads stopped.
                advance();
                if (!setPlain) uvSet = readInteger("polyFaces: uv set", 0, kMaxIndex);
                n = readCount(countWhat);
            }
            const size_t edges = faces.edgeCount(loop);
            if (n != int64_t(edges))
                fail(line, column, "polyFaces: '" + key + "' has " + std::to_string(n) + " values for a loop of " +
                                       std::to_string(edges) + " edges");
            if (key == "fc" && faces.hasColors(loop)) fail(line, column, "polyFaces: second 'fc' for the same loop");
            room(line, column, n);
            const char* what = key == "fc" ? "polyFaces: colour ids" : "polyFaces: uv ids";
            ids.clear();
            if (plain) readIntsAfterPlain(ids, n, what);
            else readInts(ids, n, what);
            if (key == "fc") faces.setColors(loop, ids);
            else faces.addUvs(loop, int32_t(uvSet), ids);
        } else {
            fail(line, column, "polyFaces: unknown keyword '" + key.substr(0, 40) + "'");
        }
    }
    if (elements > 0 && int64_t(faces.faceCount()) != elements)
        failAt(m_tok, "polyFaces: the range holds " + std::to_string(elements) + " faces but " +
                          std::to_string(faces.faceCount()) + " are given");
    return std::make_shared<const PolyFaces>(faces.finish());
}

Value Parser::readNurbsCurve() {
    auto c = std::make_shared<NurbsCurveData>();
    const uint32_t line = m_tok.line, column = m_tok.column;
    c->degree = int(readInteger("nurbsCurve: degree", 1, 64));
    c->spans = int(readInteger("nurbsCurve: spans", 0, kMaxIndex));
    c->form = int(readInteger("nurbsCurve: form", 0, 2));
    c->rational = readBoolWord("nurbsCurve: rational");
    c->dimension = int(readInteger("nurbsCurve: dimension", 2, 3));
    const int64_t knots = readCount("nurbsCurve: knot count");
    readExactNumbers(c->knots, knots, UnitKind::None, 1.0, "nurbsCurve: knots");
    const int64_t cvs = readCount("nurbsCurve: CV count");
    if (knots != cvs + c->degree - 1)
        fail(line, column, "nurbsCurve: " + std::to_string(knots) + " knots do not fit " + std::to_string(cvs) +
                               " CVs of degree " + std::to_string(c->degree) + " (expected CVs + degree - 1 = " +
                               std::to_string(cvs + c->degree - 1) + ")");
    readExactNumbers(c->cvs, cvs * (c->dimension + (c->rational ? 1 : 0)), UnitKind::None, 1.0, "nurbsCurve: CVs");
    if (!atCommandEnd()) failAt(m_tok, "nurbsCurve: unexpected value " + describe(m_tok) + " after the CVs");
    return std::shared_ptr<const NurbsCurveData>(std::move(c));
}

Value Parser::readNurbsSurface() {
    auto s = std::make_shared<NurbsSurfaceData>();
    const uint32_t line = m_tok.line, column = m_tok.column;
    s->degreeU = int(readInteger("nurbsSurface: degree U", 1, 64));
    s->degreeV = int(readInteger("nurbsSurface: degree V", 1, 64));
    s->formU = int(readInteger("nurbsSurface: form U", 0, 2));
    s->formV = int(readInteger("nurbsSurface: form V", 0, 2));
    s->rational = readBoolWord("nurbsSurface: rational");
    const int64_t knotsU = readCount("nurbsSurface: knot count U");
    readExactNumbers(s->knotsU, knotsU, UnitKind::None, 1.0, "nurbsSurface: knots U");
    const int64_t knotsV = readCount("nurbsSurface: knot count V");
    readExactNumbers(s->knotsV, knotsV, UnitKind::None, 1.0, "nurbsSurface: knots V");
    if (m_tok.isWord("TRIM") || m_tok.isWord("NOTRIM")) {
        s->trimmed = m_tok.text == "TRIM";
        advance();
    }
    const int64_t cvs = readCount("nurbsSurface: CV count");
    const int64_t nu = knotsU - s->degreeU + 1, nv = knotsV - s->degreeV + 1;
    if (nu < s->degreeU + 1 || nv < s->degreeV + 1 || nu * nv != cvs)
        fail(line, column, "nurbsSurface: " + std::to_string(knotsU) + " × " + std::to_string(knotsV) +
                               " knots of degree " + std::to_string(s->degreeU) + " × " + std::to_string(s->degreeV) +
                               " need " + std::to_string(std::max<int64_t>(nu, 0)) + " × " +
                               std::to_string(std::max<int64_t>(nv, 0)) + " CVs, the data has " + std::to_string(cvs));
    s->cvCountU = int(nu);
    s->cvCountV = int(nv);
    readExactNumbers(s->cvs, cvs * (s->rational ? 4 : 3), UnitKind::None, 1.0, "nurbsSurface: CVs");
    if (!atCommandEnd()) {
        if (!s->trimmed) failAt(m_tok, "nurbsSurface: unexpected value " + describe(m_tok) + " after the CVs");
        warn(m_tok.line, m_tok.column, "nurbsSurface: trim data is not read; the surface is kept untrimmed");
        while (!atCommandEnd()) advance();
    }
    return std::shared_ptr<const NurbsSurfaceData>(std::move(s));
}

Value Parser::readRawData(const std::string& type) {
    RawData raw;
    raw.type = type;
    while (!atCommandEnd()) {
        if (m_tok.kind == MaTokenKind::Word || m_tok.kind == MaTokenKind::String) raw.tokens.push_back(m_tok.text);
        // The raw token stream keeps `{ , }` and parentheses of nested data out of the value.
        rawNext(m_tok);
    }
    return raw;
}

// `.wl[0:7].w` n0 i v … n1 i v …: a range of compound elements, each given its child multi as a
// count and that many (index, value) pairs, the way Maya writes skin weights. Values that do
// not read that way are spread evenly over the elements (`.uvst[0:1].uvsp` …).
void Parser::setAcrossMidRange(const MaToken& plug, ResolvedPlug& target, size_t range, UnitKind unit, double factor) {
    // Read without units so that counts and indices stay whole; values are scaled when stored.
    std::vector<double> values;
    readNumbersUntilEnd(values, UnitKind::None, 1.0);
    if (unit != UnitKind::Distance && unit != UnitKind::Angle) factor = 1.0;
    const PlugSegment spanned = target.segments[range];
    const size_t elements = size_t(spanned.last - spanned.first + 1);
    auto isIndex = [](double v) { return v >= 0 && v <= double(kMaxIndex) && v == std::trunc(v); };
    // The sparse form: every element's count and pairs use up the values exactly.
    bool sparse = true;
    size_t pos = 0;
    for (size_t e = 0; e < elements && sparse; ++e) {
        if (pos >= values.size() || !isIndex(values[pos])) {
            sparse = false;
            break;
        }
        const size_t n = size_t(values[pos]);
        if (n > (values.size() - pos - 1) / 2) {
            sparse = false;
            break;
        }
        for (size_t k = 0; k < n && sparse; ++k) sparse = isIndex(values[pos + 1 + 2 * k]);
        pos += 1 + 2 * n;
    }
    std::vector<PlugSegment> one = target.segments;
    if (sparse && pos == values.size()) {
        pos = 0;
        for (size_t i = 0; i < elements; ++i) {
            const size_t n = size_t(values[pos++]);
            one[range].first = one[range].last = spanned.first + int64_t(i);
            for (size_t k = 0; k < n; ++k, pos += 2) {
                one.back().first = one.back().last = int64_t(values[pos]);
                Numbers v;
                v.values.push_back(values[pos + 1] * factor);
                m_g.setValue(target.node, one, std::move(v));
            }
        }
        return;
    }
    if (values.empty() || values.size() % elements != 0)
        failAt(plug, "setAttr \"" + util::excerpt(plug.text) + "\": " + std::to_string(values.size()) +
                         " values fit neither counted (index, value) pairs nor an even share for each of the " +
                         std::to_string(elements) + " elements");
    const size_t width = values.size() / elements;
    for (size_t i = 0; i < elements; ++i) {
        one[range].first = one[range].last = spanned.first + int64_t(i);
        Numbers v;
        for (size_t k = 0; k < width; ++k) v.values.push_back(values[i * width + k] * factor);
        m_g.setValue(target.node, one, std::move(v));
    }
}

void Parser::cmdSetAttr() {
    int64_t sizeHint = -1;
    int keyable = -1, locked = -1;
    std::string type;
    bool hasType = false;
    bool afterPlug = false;
    MaToken& plug = m_plug;  // a member, so that its text keeps its capacity between commands

    // Flags may come before and after the plug; values start at the first token that is neither.
    auto flag = [&]() -> bool {
        if (!m_tok.isFlag()) return false;
        const std::string f = m_tok.text;
        const uint32_t flagLine = m_tok.line, flagColumn = m_tok.column;
        auto boolArg = [&](int& out) {
            advance();
            bool b = true;
            if (m_tok.kind == MaTokenKind::Word && detail::parseMaBool(m_tok.text, b)) advance();
            out = b ? 1 : 0;
        };
        int ignored = 0;
        if (f == "-s" || f == "-size") {
            advance();
            sizeHint = readInteger("setAttr -s", 0, kMaxIndex);
        } else if (f == "-ch" || f == "-capacityHint") {
            advance();
            readInteger("setAttr -ch", 0, kMaxIndex);
        } else if (f == "-type" || f == "-typ") {
            advance();
            if (m_tok.kind != MaTokenKind::String && m_tok.kind != MaTokenKind::Word)
                failAt(m_tok, "setAttr -type: expected a type name, found " + describe(m_tok));
            type = m_tok.text;
            hasType = true;
            advance();
        } else if (f == "-k" || f == "-keyable") {
            boolArg(keyable);
        } else if (f == "-l" || f == "-lock") {
            boolArg(locked);
        } else if (f == "-cb" || f == "-channelBox" || f == "-ca" || f == "-caching") {
            boolArg(ignored);
        } else if (f == "-av" || f == "-alteredValue" || f == "-c" || f == "-clamp") {
            advance();
        } else {
            if (afterPlug) return false;  // after the plug an unknown `-word` is a value (and fails as one)
            // Before the plug: skipped with the numbers and booleans that follow it; the plug, a
            // string, is never its argument.
            warnUnknownFlag("setAttr", f, flagLine, flagColumn);
            advance();
            while (m_tok.kind == MaTokenKind::Word && !m_tok.isFlag() &&
                   detail::parseMaNumber(m_tok.text, UnitKind::None, m_units).status != MaNumberStatus::NotANumber)
                advance();
        }
        return true;
    };

    advance();
    while (flag()) {}
    if (atCommandEnd()) failAt(m_tok, "setAttr: no attribute given");
    std::swap(plug, m_tok);
    afterPlug = true;
    advance();
    while (flag()) {}

    ResolvedPlug target;
    if (!resolvePlug(plug, true, target, !hasType)) {
        while (!atCommandEnd()) rawNext(m_tok);
        return;
    }
    std::vector<PlugSegment>& segs = target.segments;
    const PlugSegment& last = segs.back();
    const int64_t elements = last.indexed() ? last.last - last.first + 1 : 0;
    Node& node = m_g.node(target.node);
    const AttrSpec* spec = node.findAttr(last.name);
    const UnitKind unit = spec ? spec->unit : UnitKind::None;
    const double factor = (unit == UnitKind::Distance || unit == UnitKind::Angle) ? toInternal(unit, m_units) : 1.0;
    if (segs.size() >= 2 && segs[segs.size() - 2].indexed() && segs[segs.size() - 2].last != segs[segs.size() - 2].first)
        return setAcrossMidRange(plug, target, segs.size() - 2, unit, factor);
    const int schemaWidth = spec ? componentCount(spec->type) : 0;
    const uint32_t valueLine = m_tok.line, valueColumn = m_tok.column;

    if (sizeHint >= 0 || keyable >= 0 || locked >= 0) {
        std::vector<PlugSegment> keySegs = segs;
        keySegs.back().first = keySegs.back().last = -1;
        AttrData& data = m_g.attrData(target.node, m_g.canonicalPath(target.node, keySegs));
        if (sizeHint >= 0) data.sizeHint = sizeHint;
        if (keyable >= 0) data.keyable = keyable == 1;
        if (locked >= 0) data.locked = locked == 1;
    }
    if (m_tok.kind == MaTokenKind::Semicolon && !hasType) return;  // flags only

    if (hasType && last.indexed() && !tupleWidth(type) && type != "string")
        m_ctx.elementTypes[{target.node, last.name}] = type;
    if (!hasType && m_tok.kind == MaTokenKind::Word &&
        detail::parseMaNumber(m_tok.text, unit, m_units).status == detail::MaNumberStatus::NotANumber) {
        // Typed values continued in a statement that omits -type: Maya splits long polyFaces runs
        // (`.fc[0:499]` -type "polyFaces" …, then `.fc[500:999]` f 4 …). The type is the schema's,
        // else the one an earlier element of the multi named.
        if (const char* t = spec ? dataTypeName(spec->type) : nullptr) {
            type = t;
            hasType = true;
        } else if (auto it = m_ctx.elementTypes.find(std::pair<NodeId, std::string>(target.node, last.name));
                   it != m_ctx.elementTypes.end()) {
            type = it->second;
            hasType = true;
        }
    }

    auto countMismatch = [&](size_t got, int64_t expected, const std::string& what) {
        fail(valueLine, valueColumn, "setAttr \"" + util::excerpt(plug.text) + "\": " + what + " needs " + std::to_string(expected) +
                                         " values, found " + std::to_string(got));
    };
    const int64_t elementCount = std::max<int64_t>(elements, 1);

    Value value;
    if (!hasType) {
        if (m_tok.kind == MaTokenKind::String) {
            std::string s = readStringValue("setAttr");
            if (!atCommandEnd()) failAt(m_tok, "setAttr: unexpected value " + describe(m_tok) + " after a string");
            value = StringValue{std::move(s)};
        } else {
            Numbers nums;
            const int64_t expected = schemaWidth > 0 ? elementCount * schemaWidth : 0;
            nums.values.reserve(plausibleCount(expected > 0 ? expected : elementCount));
            readNumbersUntilEnd(nums.values, unit, factor);
            const size_t got = nums.values.size();
            if (got == 0) countMismatch(got, std::max<int64_t>(expected, 1), "the attribute");
            if (expected > 0 && int64_t(got) != expected)
                countMismatch(got, expected,
                              elements > 0 ? "a range of " + std::to_string(elements) + " × " + std::to_string(schemaWidth)
                                           : "the attribute");
            if (elements > 0 && (got % size_t(elements) != 0))
                fail(valueLine, valueColumn, "setAttr \"" + util::excerpt(plug.text) + "\": " + std::to_string(got) +
                                                 " values do not divide into the range's " + std::to_string(elements) +
                                                 " elements");
            value = std::move(nums);
        }
    } else if (const int w = tupleWidth(type); w > 0) {
        Numbers nums;
        nums.kind = Numbers::Kind::Tuple;
        nums.tupleSize = w;
        nums.values.reserve(plausibleCount(elementCount * w));
        readNumbersUntilEnd(nums.values, unit, factor);
        if (int64_t(nums.values.size()) != elementCount * w) countMismatch(nums.values.size(), elementCount * w, type);
        value = std::move(nums);
    } else if (type == "matrix") {
        if (m_tok.kind == MaTokenKind::String) {
            value = readRawData(type);  // the "xform" form: a transformation's components
        } else {
            Numbers nums;
            nums.kind = Numbers::Kind::Matrix;
            nums.tupleSize = 16;
            readNumbersUntilEnd(nums.values, UnitKind::None, 1.0);
            if (int64_t(nums.values.size()) != elementCount * 16) countMismatch(nums.values.size(), elementCount * 16, type);
            value = std::move(nums);
        }
    } else if (type == "string") {
        std::vector<std::string> strings;
        while (!atCommandEnd()) strings.push_back(readStringValue("setAttr -type string"));
        if (int64_t(strings.size()) != elementCount) countMismatch(strings.size(), elementCount, "string");
        if (elements > 1) {
            // A range of strings: one element each.
            for (int64_t i = 0; i < elements; ++i) {
                std::vector<PlugSegment> one = segs;
                one.back().first = one.back().last = last.first + i;
                m_g.setValue(target.node, one, StringValue{std::move(strings[size_t(i)])});
            }
            return;
        }
        value = StringValue{std::move(strings.front())};
    } else if (type == "stringArray" || type == "componentList") {
        const int64_t n = readCount(("setAttr -type " + type + " count").c_str());
        std::vector<std::string> items;
        items.reserve(plausibleCount(n) / 2);
        while (!atCommandEnd()) items.push_back(readStringValue(("setAttr -type " + type).c_str()));
        if (int64_t(items.size()) != n) countMismatch(items.size(), n, type);
        if (type == "stringArray") value = StringArray{std::move(items)};
        else value = ComponentList{std::move(items)};
    } else if (type == "Int32Array" || type == "doubleArray" || type == "floatArray" || type == "pointArray" ||
               type == "vectorArray") {
        Numbers nums;
        int width = 1;
        nums.kind = Numbers::Kind::DoubleArray;
        if (type == "Int32Array") nums.kind = Numbers::Kind::Int32Array;
        if (type == "pointArray") nums.kind = Numbers::Kind::PointArray, width = 4;
        if (type == "vectorArray") nums.kind = Numbers::Kind::VectorArray, width = 3;
        nums.tupleSize = width;
        const int64_t n = readCount(("setAttr -type " + type + " count").c_str());
        nums.values.reserve(plausibleCount(n * width));
        readNumbersUntilEnd(nums.values, UnitKind::None, 1.0);
        if (int64_t(nums.values.size()) != n * width) countMismatch(nums.values.size(), n * width, type);
        if (type == "Int32Array")
            for (double v : nums.values)
                // Range first: converting an out-of-range double to int32_t is undefined.
                if (!(v >= INT32_MIN && v <= INT32_MAX) || v != std::trunc(v))
                    fail(valueLine, valueColumn, "setAttr -type Int32Array: value " + std::to_string(v) + " is not a 32-bit integer");
        value = std::move(nums);
    } else if (type == "polyFaces") {
        value = readPolyFaces(elements);
    } else if (type == "nurbsCurve") {
        value = readNurbsCurve();
    } else if (type == "nurbsSurface") {
        value = readNurbsSurface();
    } else if (isRawDataType(type) || m_ctx.knownDataTypes.count(type)) {
        value = readRawData(type);
    } else {
        // A data type pushpin does not model (subdivision-surface data, plug-in types…): its values
        // are skipped by their tokens, with one warning per type.
        if (m_ctx.skippedDataTypes.size() < kMaxSkipWarnings && m_ctx.skippedDataTypes.insert(type).second)
            warn(plug.line, plug.column, "setAttr: data type \"" + util::excerpt(type) +
                                             "\" is not modelled; its values are skipped (reported once per type)");
        while (!atCommandEnd()) rawNext(m_tok);
        return;
    }
    m_g.setValue(target.node, segs, std::move(value));
}

}  // namespace

// ------------------------------------------------------------------ entry points

namespace {

Graph readWith(MaLexer& lex, const std::string& name, const ReadOptions& options, uint64_t totalBytes) {
    Graph g;
    g.sourceFile = name;
    ReadContext ctx{g, options};
    std::filesystem::path dir = std::filesystem::path(name).parent_path();
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(name, ec);
    ctx.loading.push_back(ec ? std::filesystem::path(name) : canonical);
    Parser parser(ctx, lex, name, dir, std::string(), 0, totalBytes);
    parser.run();
    if (ctx.statementsSkipped > kMaxSkipWarnings)
        g.warn(Diagnostic{name, 0, 0, {},
                          std::to_string(ctx.statementsSkipped - kMaxSkipWarnings) +
                              " more statements failed and were skipped (not listed one by one)"});
    if (ctx.renamesUnreported > 0)
        g.warn(Diagnostic{name, 0, 0, {},
                          std::to_string(ctx.renamesUnreported) + " more nodes were renamed because their names were "
                                                                  "taken (not listed one by one)"});
    return g;
}

}  // namespace

Graph MaReader::readFile(const std::filesystem::path& path, const ReadOptions& options) {
    // An ifstream opens a directory on Linux and reads nothing from it, which would pass for an
    // empty scene.
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec) throw IoError(path, "cannot open", ec.value());
    if (status.type() == std::filesystem::file_type::directory) throw IoError(path, "is a directory, not a .ma file");
    if (status.type() != std::filesystem::file_type::regular)
        throw IoError(path, "is not a regular file (a device, socket or pipe), not a .ma file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path, "cannot open", errno);
    const uint64_t size = std::filesystem::file_size(path, ec);
    MaLexer lex(in);
    return readWith(lex, path.string(), options, ec ? 0 : size);
}

Graph MaReader::readString(std::string_view text, const std::string& name, const ReadOptions& options) {
    MaLexer lex(text);
    return readWith(lex, name, options, text.size());
}

Graph MaReader::readStream(std::istream& in, const std::string& name, const ReadOptions& options) {
    uint64_t size = 0;
    const auto pos = in.tellg();
    if (pos != std::streampos(-1) && in.seekg(0, std::ios::end)) {
        const auto end = in.tellg();
        if (end != std::streampos(-1) && end >= pos) size = uint64_t(end - pos);
        in.seekg(pos);
    }
    in.clear();
    MaLexer lex(in);
    return readWith(lex, name, options, size);
}

}  // namespace pushpin::scene
