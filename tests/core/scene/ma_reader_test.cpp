#include "core/scene/ma_reader.h"

#include "core/scene/detail/ma_lexer.h"
#include "core/scene/detail/ma_number.h"

#include "tests/support/ma_corpus.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <span>
#include <sstream>

namespace pushpin::scene {
namespace {

namespace fs = std::filesystem;

Graph read(std::string_view text) { return MaReader::readString(text, "test.ma"); }

NodeId findNode(const Graph& g, std::string_view name) {
    NodeId id = g.find(name);
    EXPECT_NE(id, kNoNode) << "no node " << name;
    return id;
}

// The stored Numbers of an exact plug; fails the test when absent.
const Numbers& numbersOf(const Graph& g, std::string_view node, std::string_view plug) {
    static const Numbers empty;
    NodeId id = findNode(g, node);
    if (id == kNoNode) return empty;
    const Value* v = g.value(id, plug);
    EXPECT_NE(v, nullptr) << node << "." << plug << " is not set";
    if (!v) return empty;
    const Numbers* n = std::get_if<Numbers>(v);
    EXPECT_NE(n, nullptr) << node << "." << plug << " does not hold numbers";
    return n ? *n : empty;
}

void expectValues(const Numbers& n, std::vector<double> expected, double tol = 1e-12) {
    ASSERT_EQ(n.values.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(n.values[i], expected[i], tol) << "value " << i;
}

// A temporary folder removed at the end of a test.
struct TempDir {
    fs::path path;
    TempDir() {
        std::random_device rd;
        path = fs::temp_directory_path() / ("pushpin_ma_reader_" + std::to_string(rd()) + std::to_string(rd()));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    fs::path write(const std::string& name, const std::string& text) const {
        fs::path p = path / name;
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
};

constexpr double kDeg = std::numbers::pi / 180.0;

// ------------------------------------------------------------------ header, units, fileInfo

TEST(MaReader, ReadsHeaderRequiresUnitsAndFileInfo) {
    Graph g = read(R"(//Maya ASCII 2018 scene
//Name: shot.ma
requires maya "2018";
requires -nodeType "aiOptions" -nodeType "aiAOVDriver" "mtoa" "3.0.1";
requires -nodeType "mayaUsdLayerManager" -dataType "pxrUsdStageData" "mayaUsdPlugin" "0.25.0";
currentUnit -l meter -a radian -t ntsc;
fileInfo "application" "maya";
fileInfo "osv" "Linux\n";
// End of shot.ma
)");
    ASSERT_EQ(g.requirements.size(), 3u);
    EXPECT_EQ(g.requirements[0], "maya 2018");
    EXPECT_EQ(g.requirements[1], "mtoa 3.0.1");
    EXPECT_EQ(g.requirements[2], "mayaUsdPlugin 0.25.0");
    EXPECT_DOUBLE_EQ(g.units.cmPerLinearUnit, 100.0);
    EXPECT_DOUBLE_EQ(g.units.radiansPerAngleUnit, 1.0);
    EXPECT_DOUBLE_EQ(g.units.framesPerSecond, 30.0);
    ASSERT_EQ(g.fileInfo.size(), 2u);
    EXPECT_EQ(g.fileInfo[1].first, "osv");
    EXPECT_EQ(g.fileInfo[1].second, "Linux\n");
    EXPECT_TRUE(g.warnings().empty());
}

TEST(MaReader, FileInfoAndRelationshipFlagsTakeTheirArguments) {
    Graph g = read(R"(fileInfo "application" "maya";
fileInfo "product" "Maya 2024";
fileInfo -rm "product";
fileInfo -q "osv" "Linux";
createNode shadingEngine -n "sg";
relationship -b "link" ":lightLinker1" "sg.message" ":defaultLightSet.message";
relationship "link" -zz 3 ":lightLinker1" "sg.message" ":defaultLightSet.message";
)");
    ASSERT_EQ(g.fileInfo.size(), 2u);
    EXPECT_EQ(g.fileInfo[0].first, "application");
    EXPECT_EQ(g.fileInfo[1].first, "osv");
    ASSERT_EQ(g.relationships().size(), 2u);
    for (const Relationship& r : g.relationships()) {
        EXPECT_EQ(r.type, "link");
        EXPECT_EQ(r.plugs.size(), 3u);
    }
    // The unknown -zz was skipped with its number, with one warning naming it.
    size_t unknown = 0;
    for (const Diagnostic& d : g.warnings()) unknown += d.message.find("-zz") != std::string::npos;
    EXPECT_EQ(unknown, 1u);
}

TEST(MaLexer, PlainNumberFastPathReadsWhatTheTokenPathReads) {
    const std::string text =
        "1 -2.5 +3 4cm 5e3 /*c*/ 6 // x\n 7. .8 -0 1e400 1e-400 nan abc 123456789012 -7;\n"
        "0.000125 99999.5 -3e-7 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30;";
    using detail::MaLexer;
    using detail::MaToken;
    using detail::MaTokenKind;
    // What each token means to a number list: a plain number's value, or the token itself.
    auto plain = [](const MaToken& t, double& v) {
        if (t.kind != MaTokenKind::Word || t.text.empty()) return false;
        const char c = t.text.front();
        if (!((c >= '0' && c <= '9') || c == '-' || c == '.')) return false;
        const detail::MaNumber n = detail::parseMaNumber(t.text, UnitKind::None, Units{});
        if (n.status != detail::MaNumberStatus::Ok || n.hasUnit) return false;
        v = n.value;
        return true;
    };
    auto describe = [&](MaLexer& lex, bool fast) {
        std::vector<std::string> out;
        for (;;) {
            double v = 0;
            if (fast && lex.nextPlainNumber(v)) {
                out.push_back("N" + std::to_string(v));
                continue;
            }
            MaToken t;
            lex.next(t);
            if (t.kind == MaTokenKind::End) break;
            // 1e-400 underflows to zero on the token path; the fast path leaves it to tokens.
            if (plain(t, v)) out.push_back("N" + std::to_string(v));
            else out.push_back(std::to_string(int(t.kind)) + ":" + t.text);
        }
        return out;
    };
    MaLexer whole{std::string_view(text)};
    const std::vector<std::string> expected = describe(whole, false);
    ASSERT_GT(expected.size(), 30u);
    {
        MaLexer lex{std::string_view(text)};
        EXPECT_EQ(describe(lex, true), expected);
    }
    for (size_t bufferBytes : {16, 17, 19, 23, 31, 64}) {
        std::istringstream in(text);
        MaLexer lex(in, bufferBytes);
        EXPECT_EQ(describe(lex, true), expected) << "buffer " << bufferBytes;
    }
}

TEST(MaReader, LongNumberListsKeepTheirValuesAndTheirErrorPlaces) {
    // 30,000 points, one chunk; then the same with a non-finite value on line 7001.
    std::string text = "createNode mesh -n \"m\";\n\tsetAttr -s 30000 \".vt[0:29999]\"";
    for (int i = 0; i < 30000; ++i) {
        if (i % 3 == 0) text += "\n\t\t";
        text += " " + std::to_string(i) + ".25 " + std::to_string(-i) + " 1e-3";
    }
    text += ";\n";
    Graph g = read(text);
    std::vector<double> p;
    ASSERT_TRUE(g.numbers(findNode(g, "m"), "vt[29999]", p));
    ASSERT_EQ(p.size(), 3u);
    // Mesh points are single precision, as Maya keeps them.
    EXPECT_EQ(p[0], 29999.25);
    EXPECT_EQ(p[1], -29999.0);
    EXPECT_EQ(p[2], double(1e-3f));
    const size_t at = text.find(" 21000.25 ");
    ASSERT_NE(at, std::string::npos);
    std::string bad = text;
    bad.replace(at + 1, 8, "inf");
    const size_t line = size_t(std::count(bad.begin(), bad.begin() + std::ptrdiff_t(at), '\n')) + 1;
    // The statement is skipped with one warning at the value's own line; nothing of it is kept.
    const Graph skipped = read(bad);
    bool found = false;
    for (const Diagnostic& d : skipped.warnings())
        if (d.line == line && d.message.find("not finite") != std::string::npos) found = true;
    EXPECT_TRUE(found);
    if (skipped.numbers(findNode(skipped, "m"), "vt[29999]", p)) {
        ASSERT_FALSE(p.empty());
        EXPECT_NE(p[0], 29999.25);
    }
}

TEST(MaReader, LongFlagFormsOfCurrentUnit) {
    Graph g = read("currentUnit -linear millimeter -angle degree -time pal;\n");
    EXPECT_DOUBLE_EQ(g.units.cmPerLinearUnit, 0.1);
    EXPECT_DOUBLE_EQ(g.units.radiansPerAngleUnit, kDeg);
    EXPECT_DOUBLE_EQ(g.units.framesPerSecond, 25.0);
}

TEST(MaReader, ConvertsUnitBearingAttributesToCentimetresAndRadians) {
    Graph g = read(R"(currentUnit -l m -a deg -t film;
createNode transform -n "a";
	setAttr ".t" -type "double3" 1 2 3 ;
	setAttr ".r" -type "double3" 90 0 -45 ;
	setAttr ".s" -type "double3" 2 2 2 ;
	setAttr ".tx" 5;
createNode camera -n "camShape" -p "a";
	setAttr ".ncp" 0.5;
	setAttr ".fl" 50;
)");
    expectValues(numbersOf(g, "a", "translate"), {500, 200, 300});
    expectValues(numbersOf(g, "a", "rotate"), {90 * kDeg, 0, -45 * kDeg});
    expectValues(numbersOf(g, "a", "scale"), {2, 2, 2});  // unitless
    NodeId cam = findNode(g, "camShape");
    EXPECT_DOUBLE_EQ(g.getDouble(cam, "nearClipPlane"), 50.0);
    EXPECT_DOUBLE_EQ(g.getDouble(cam, "focalLength"), 50.0);  // millimetres, not a distance attribute
    NodeId a = findNode(g, "a");
    std::vector<double> t;
    ASSERT_TRUE(g.numbers(a, "translate", t));
    EXPECT_DOUBLE_EQ(t[0], 500.0);  // translateX written later, in metres
}

TEST(MaReader, RadiansAndInchesInCurrentUnit) {
    Graph g = read(R"(currentUnit -l inch -a rad;
createNode transform -n "a";
	setAttr ".t" -type "double3" 1 0 0 ;
	setAttr ".r" -type "double3" 1.5 0 0 ;
)");
    expectValues(numbersOf(g, "a", "translate"), {2.54, 0, 0});
    expectValues(numbersOf(g, "a", "rotate"), {1.5, 0, 0});
}

TEST(MaReader, NumbersWithUnitSuffixes) {
    Graph g = read(R"(currentUnit -l m -a rad;
createNode transform -n "a";
	setAttr ".t" -type "double3" 5cm 4inch 1m ;
	setAttr ".r" -type "double3" 90deg 1 0 ;
)");
    // A suffix overrides the file's unit; plain numbers still follow currentUnit.
    expectValues(numbersOf(g, "a", "translate"), {5, 4 * 2.54, 100});
    expectValues(numbersOf(g, "a", "rotate"), {std::numbers::pi / 2, 1, 0});
}

// An unknown unit is a failed command: it is skipped with a warning and the file's units stay.
TEST(MaReader, UnknownUnitIsSkippedWithAWarning) {
    Graph g = read("currentUnit -l parsec;\ncurrentUnit -a radian;\n");
    ASSERT_EQ(g.warnings().size(), 1u);
    EXPECT_NE(g.warnings()[0].message.find("unknown linear unit 'parsec'"), std::string::npos);
    EXPECT_DOUBLE_EQ(g.units.cmPerLinearUnit, 1.0);
    EXPECT_DOUBLE_EQ(g.units.radiansPerAngleUnit, 1.0);
}

// ------------------------------------------------------------------ createNode

TEST(MaReader, CreateNodeShortAndLongFlags) {
    Graph g = read(R"(createNode transform -n "grp";
createNode transform -name "child" -parent "grp";
createNode mesh -n "childShape" -p "|grp|child";
createNode transform -shared -name "persp";
createNode lambert -ss -n "mat";
)");
    NodeId grp = findNode(g, "grp");
    NodeId child = findNode(g, "child");
    NodeId shape = findNode(g, "childShape");
    ASSERT_EQ(g.node(child).parents().size(), 1u);
    EXPECT_EQ(g.node(child).parents()[0], grp);
    ASSERT_EQ(g.node(shape).parents().size(), 1u);
    EXPECT_EQ(g.node(shape).parents()[0], child);
    EXPECT_EQ(g.node(shape).type, "mesh");
    EXPECT_EQ(g.node(shape).line, 3u);
    EXPECT_TRUE(g.node(findNode(g, "persp")).shared);
    EXPECT_EQ(g.node(findNode(g, "mat")).type, "lambert");
}

TEST(MaReader, SharedCreateNodeReusesTheExistingNode) {
    Graph g = read(R"(createNode transform -s -n "persp";
	setAttr ".tx" 1;
createNode transform -s -n "persp";
	setAttr ".ty" 2;
)");
    EXPECT_EQ(g.nodesOfType("transform", false).size(), 1u);
    expectValues(numbersOf(g, "persp", "translate"), {1, 2, 0});
}

TEST(MaReader, UnnamedNodesGetMayaStyleNames) {
    Graph g = read("createNode polyCube;\ncreateNode polyCube;\n");
    EXPECT_NE(g.find("polyCube1"), kNoNode);
    EXPECT_NE(g.find("polyCube2"), kNoNode);
}

TEST(MaReader, DuplicateNodeNameIsRenamedWithAWarning) {
    Graph g = read(R"(createNode lambert -n "mat1";
createNode lambert -n "mat1";
	setAttr ".dc" 0.25;
)");
    NodeId second = g.find("mat2");
    ASSERT_NE(second, kNoNode);
    EXPECT_DOUBLE_EQ(g.getDouble(second, "diffuse"), 0.25);
    ASSERT_EQ(g.warnings().size(), 1u);
    EXPECT_EQ(g.warnings()[0].line, 2u);
    EXPECT_NE(g.warnings()[0].message.find("renamed 'mat2'"), std::string::npos);
}

TEST(MaReader, DagSiblingsUnderDifferentParentsMayShareANames) {
    Graph g = read(R"(createNode transform -n "a";
createNode transform -n "b";
createNode mesh -n "shape" -p "a";
createNode mesh -n "shape" -p "b";
)");
    EXPECT_NE(g.find("|a|shape"), g.find("|b|shape"));
    EXPECT_TRUE(g.warnings().empty());
}

TEST(MaReader, PluginNodeTypesPassThroughAsUnsupported) {
    Graph g = read(R"(requires "mtoa" "1.0";
createNode aiStandardSurface -n "ai1";
	setAttr ".base" 0.8;
	setAttr ".specularColor" -type "float3" 1 0.5 0.25 ;
connectAttr "ai1.outColor" ":initialShadingGroup.ss";
)");
    NodeId ai = findNode(g, "ai1");
    EXPECT_EQ(g.node(ai).schema, nullptr);
    EXPECT_EQ(g.unsupportedTypes().at("aiStandardSurface"), 1);
    expectValues(numbersOf(g, "ai1", "specularColor"), {1, 0.5, 0.25});
    EXPECT_DOUBLE_EQ(g.getDouble(ai, "base"), 0.8);
}

TEST(MaReader, RenameIgnoresUidAndRenamesTheCurrentNode) {
    Graph g = read(R"(createNode transform -n "old";
	rename -uid "8F1AD47F-4B2E-4A3C-9D11-000000000001";
	rename "fresh";
	setAttr ".tx" 3;
)");
    EXPECT_EQ(g.find("old"), kNoNode);
    NodeId id = findNode(g, "fresh");
    EXPECT_DOUBLE_EQ(g.getDouble(id, "translateX"), 3.0);
}

// ------------------------------------------------------------------ setAttr forms

TEST(MaReader, SetAttrScalarsAndBooleans) {
    Graph g = read(R"(createNode polyCube -n "c";
	setAttr ".w" 2;
	setAttr ".h" 1.5e+00;
createNode transform -n "t";
	setAttr ".v" no;
	setAttr ".it" off;
createNode mesh -n "m" -p "t";
	setAttr ".vir" yes;
	setAttr ".vif" on;
	setAttr ".csh" false;
	setAttr ".rcsh" true;
)");
    NodeId c = findNode(g, "c");
    EXPECT_DOUBLE_EQ(g.getDouble(c, "width"), 2.0);
    EXPECT_DOUBLE_EQ(g.getDouble(c, "height"), 1.5);
    NodeId t = findNode(g, "t");
    EXPECT_FALSE(g.getBool(t, "visibility", true));
    EXPECT_FALSE(g.getBool(t, "inheritsTransform", true));
    NodeId m = findNode(g, "m");
    EXPECT_TRUE(g.getBool(m, "visibleInReflections"));
    EXPECT_TRUE(g.getBool(m, "visibleInRefractions"));
    EXPECT_FALSE(g.getBool(m, "castsShadows", true));
    EXPECT_TRUE(g.getBool(m, "receiveShadows"));
}

TEST(MaReader, SetAttrTupleTypes) {
    Graph g = read(R"(createNode unknownThing -n "u";
	setAttr ".a" -type "double2" 1 2 ;
	setAttr ".b" -type "double3" 1 2 3 ;
	setAttr ".c" -type "double4" 1 2 3 4 ;
	setAttr ".d" -type "float2" 0.5 0.25 ;
	setAttr ".e" -type "float3" 1 0 1 ;
	setAttr ".f" -type "long2" 7 8 ;
	setAttr ".g" -type "long3" 1 2 3 ;
	setAttr ".h" -type "short2" 193 128 ;
	setAttr ".i" -type "short3" -1 0 1 ;
)");
    struct Case { const char* plug; int width; std::vector<double> values; };
    const Case cases[] = {{"a", 2, {1, 2}},       {"b", 3, {1, 2, 3}},  {"c", 4, {1, 2, 3, 4}},
                          {"d", 2, {0.5, 0.25}},  {"e", 3, {1, 0, 1}},  {"f", 2, {7, 8}},
                          {"g", 3, {1, 2, 3}},    {"h", 2, {193, 128}}, {"i", 3, {-1, 0, 1}}};
    for (const Case& c : cases) {
        const Numbers& n = numbersOf(g, "u", c.plug);
        EXPECT_EQ(n.kind, Numbers::Kind::Tuple) << c.plug;
        EXPECT_EQ(n.tupleSize, c.width) << c.plug;
        expectValues(n, c.values);
    }
}

TEST(MaReader, SetAttrStringsWithEscapesAndConcatenation) {
    Graph g = read(R"(createNode file -n "file1";
	setAttr ".ftn" -type "string" "C:\\maps\\wood \"oak\".tif";
createNode script -n "sceneConfigurationScriptNode";
	setAttr ".b" -type "string" (
		"playbackOptions -min 1 -max 24;\n"
		+ "// a comment inside a string; with a semicolon\n"
		+ "print \"hi\";");
	setAttr ".st" 6;
createNode script -n "s2";
	setAttr ".a" -type "string" "one" + "two";
)");
    EXPECT_EQ(g.getString(findNode(g, "file1"), "fileTextureName"), "C:\\maps\\wood \"oak\".tif");
    NodeId s = findNode(g, "sceneConfigurationScriptNode");
    EXPECT_EQ(g.getString(s, "b"),
              "playbackOptions -min 1 -max 24;\n// a comment inside a string; with a semicolon\nprint \"hi\";");
    EXPECT_DOUBLE_EQ(g.getDouble(s, "st"), 6.0);
    EXPECT_EQ(g.getString(findNode(g, "s2"), "a"), "onetwo");
}

TEST(MaReader, ExpressionsAreKeptAsStrings) {
    Graph g = read(R"(createNode expression -n "expression1";
	setAttr -k on ".nds";
	setAttr ".ixp" -type "string" "pSphere1.translateY = sin(time);";
)");
    EXPECT_EQ(g.getString(findNode(g, "expression1"), "ixp"), "pSphere1.translateY = sin(time);");
}

TEST(MaReader, SetAttrArrayTypes) {
    Graph g = read(R"(createNode unknownThing -n "u";
	setAttr ".sa" -type "stringArray" 3 "a" "b c" "" ;
	setAttr ".ia" -type "Int32Array" 4 0 -1 2 3 ;
	setAttr ".da" -type "doubleArray" 2 0.5 1e-3 ;
	setAttr ".pa" -type "pointArray" 2 1 2 3 1 4 5 6 1 ;
	setAttr ".va" -type "vectorArray" 2 1 0 0 0 1 0 ;
	setAttr ".ea" -type "doubleArray" 0 ;
	setAttr ".cl" -type "componentList" 2 "f[0:5]" "vtx[3]";
)");
    NodeId u = findNode(g, "u");
    auto* sa = std::get_if<StringArray>(g.value(u, "sa"));
    ASSERT_NE(sa, nullptr);
    EXPECT_EQ(sa->items, (std::vector<std::string>{"a", "b c", ""}));
    const Numbers& ia = numbersOf(g, "u", "ia");
    EXPECT_EQ(ia.kind, Numbers::Kind::Int32Array);
    expectValues(ia, {0, -1, 2, 3});
    const Numbers& da = numbersOf(g, "u", "da");
    EXPECT_EQ(da.kind, Numbers::Kind::DoubleArray);
    expectValues(da, {0.5, 1e-3});
    const Numbers& pa = numbersOf(g, "u", "pa");
    EXPECT_EQ(pa.kind, Numbers::Kind::PointArray);
    EXPECT_EQ(pa.tupleSize, 4);
    expectValues(pa, {1, 2, 3, 1, 4, 5, 6, 1});
    const Numbers& va = numbersOf(g, "u", "va");
    EXPECT_EQ(va.kind, Numbers::Kind::VectorArray);
    expectValues(va, {1, 0, 0, 0, 1, 0});
    EXPECT_TRUE(numbersOf(g, "u", "ea").values.empty());
    auto* cl = std::get_if<ComponentList>(g.value(u, "cl"));
    ASSERT_NE(cl, nullptr);
    EXPECT_EQ(cl->items, (std::vector<std::string>{"f[0:5]", "vtx[3]"}));
}

TEST(MaReader, SetAttrMatrixAndXformMatrix) {
    Graph g = read(R"(createNode unknownThing -n "u";
	setAttr ".m" -type "matrix" 1 0 0 0 0 1 0 0
		 0 0 1 0 10 20 30 1;
	setAttr ".x" -type "matrix" "xform" 1 1 1 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0
		 0 0 0 1 0 0 0 1 1 1 0 yes;
)");
    const Numbers& m = numbersOf(g, "u", "m");
    EXPECT_EQ(m.kind, Numbers::Kind::Matrix);
    ASSERT_EQ(m.values.size(), 16u);
    EXPECT_EQ(m.values[12], 10);
    EXPECT_EQ(m.values[14], 30);
    auto* raw = std::get_if<RawData>(g.value(findNode(g, "u"), "x"));
    ASSERT_NE(raw, nullptr);
    EXPECT_EQ(raw->type, "matrix");
    ASSERT_FALSE(raw->tokens.empty());
    EXPECT_EQ(raw->tokens.front(), "xform");
    EXPECT_EQ(raw->tokens.back(), "yes");
}

TEST(MaReader, SetAttrRawDataTypes) {
    Graph g = read(R"(requires -dataType "pxrUsdStageData" "mayaUsdPlugin" "1";
createNode mesh -n "m";
	setAttr ".cd" -type "dataPolyComponent" Index_Data Edge 0 ;
createNode aiOptions -n "o";
	setAttr ".aal" -type "attributeAlias" {"exposure","aiExposure","normalize"
		,"aiNormalize"} ;
	setAttr ".stage" -type "pxrUsdStageData" ;
)");
    auto* cd = std::get_if<RawData>(g.value(findNode(g, "m"), "cd"));
    ASSERT_NE(cd, nullptr);
    EXPECT_EQ(cd->type, "dataPolyComponent");
    EXPECT_EQ(cd->tokens, (std::vector<std::string>{"Index_Data", "Edge", "0"}));
    auto* aal = std::get_if<RawData>(g.value(findNode(g, "o"), "aal"));
    ASSERT_NE(aal, nullptr);
    EXPECT_EQ(aal->tokens, (std::vector<std::string>{"exposure", "aiExposure", "normalize", "aiNormalize"}));
    auto* stage = std::get_if<RawData>(g.value(findNode(g, "o"), "stage"));
    ASSERT_NE(stage, nullptr);
    EXPECT_TRUE(stage->tokens.empty());
}

TEST(MaReader, SetAttrFlagsSizeKeyableLockAndIgnoredOnes) {
    Graph g = read(R"(createNode transform -n "t";
	setAttr -k off ".v";
	setAttr -l on ".tx";
	setAttr -keyable on -lock off ".ty" 4;
	setAttr -av -k on ".tz" 2;
	setAttr -cb on ".ro" 3;
	setAttr -ca on -c ".sx" 2;
createNode mesh -n "m" -p "t";
	setAttr -s 4 ".pt";
	setAttr -size 2 -ch 8 ".vt[0:1]" 1 2 3 4 5 6;
)");
    NodeId t = findNode(g, "t");
    const AttrData* v = g.findAttr(t, "visibility");
    ASSERT_NE(v, nullptr);
    EXPECT_FALSE(v->keyable);
    EXPECT_FALSE(v->hasValue);
    ASSERT_NE(g.findAttr(t, "translateX"), nullptr);
    EXPECT_TRUE(g.findAttr(t, "translateX")->locked);
    ASSERT_NE(g.findAttr(t, "translateY"), nullptr);
    EXPECT_TRUE(g.findAttr(t, "translateY")->keyable);
    EXPECT_FALSE(g.findAttr(t, "translateY")->locked);
    expectValues(numbersOf(g, "t", "translate"), {0, 4, 2});
    EXPECT_EQ(g.getInt(t, "rotateOrder"), 3);
    EXPECT_DOUBLE_EQ(g.getDouble(t, "scaleX"), 2.0);
    NodeId m = findNode(g, "m");
    ASSERT_NE(g.findAttr(m, "pnts"), nullptr);
    EXPECT_EQ(g.findAttr(m, "pnts")->sizeHint, 4);
    ASSERT_NE(g.findAttr(m, "vrts"), nullptr);
    EXPECT_EQ(g.findAttr(m, "vrts")->sizeHint, 2);
}

TEST(MaReader, IndexRangeIsOneChunkAcrossLines) {
    Graph g = read(R"(currentUnit -l m;
createNode mesh -n "m";
	setAttr -s 8 ".vt[0:7]"  -0.5 -0.5 0.5 0.5 -0.5 0.5 -0.5 0.5 0.5 0.5 0.5 0.5
		 -0.5 0.5 -0.5 0.5 0.5 -0.5 -0.5 -0.5 -0.5 0.5 -0.5 -0.5;
	setAttr ".vt[8]" -type "float3" 1 2 3;
	setAttr ".pt[2]" -type "float3" 0 0.25 0 ;
)");
    NodeId m = findNode(g, "m");
    const AttrData* vt = g.findAttr(m, "vrts");
    ASSERT_NE(vt, nullptr);
    ASSERT_EQ(vt->multi.runs().size(), 2u);
    const MultiStore::Run& run = vt->multi.runs().begin()->second;
    EXPECT_EQ(run.count, 8u);
    EXPECT_EQ(run.width, 3);
    std::vector<double> p;
    ASSERT_TRUE(g.numbers(m, "vrts[5]", p));
    // Point arrays are float3 data in centimetres whatever the file's unit: kept as written.
    expectValues(Numbers{Numbers::Kind::Plain, 1, p}, {0.5, 0.5, -0.5});
    ASSERT_TRUE(g.numbers(m, "vt[8]", p));
    expectValues(Numbers{Numbers::Kind::Plain, 1, p}, {1, 2, 3});
    ASSERT_TRUE(g.numbers(m, "pnts[2]", p));
    expectValues(Numbers{Numbers::Kind::Plain, 1, p}, {0, 0.25, 0});
}

TEST(MaReader, TupleRangesAndEdges) {
    Graph g = read(R"(createNode mesh -n "m";
	setAttr ".uvst[0].uvsn" -type "string" "map1";
	setAttr -s 3 ".uvst[0].uvsp[0:2]" -type "float2" 0 0 1 0
		 1 1;
	setAttr -s 2 ".ed[0:1]" 0 1 0 1 2 1;
)");
    NodeId m = findNode(g, "m");
    EXPECT_EQ(g.getString(m, "uvSet[0].uvSetName"), "map1");
    std::vector<double> uv;
    ASSERT_TRUE(g.numbers(m, "uvst[0].uvsp[2]", uv));
    EXPECT_EQ(uv, (std::vector<double>{1, 1}));
    std::vector<double> e;
    ASSERT_TRUE(g.numbers(m, "edge[1]", e));
    EXPECT_EQ(e, (std::vector<double>{1, 2, 1}));
}

TEST(MaReader, SetAttrRangeOfStrings) {
    Graph g = read(R"(createNode unknownThing -n "u";
	setAttr -s 2 ".names[3:4]" -type "string" "a" "b";
)");
    NodeId u = findNode(g, "u");
    EXPECT_EQ(g.getString(u, "names[3]"), "a");
    EXPECT_EQ(g.getString(u, "names[4]"), "b");
}

TEST(MaReader, SetAttrAddressingAnotherNode) {
    Graph g = read(R"(createNode transform -n "a";
createNode transform -n "b";
setAttr "a.tx" 7;
setAttr "|a.translateY" 8;
	setAttr ".tz" 9;
)");
    expectValues(numbersOf(g, "a", "translate"), {7, 8, 0});
    expectValues(numbersOf(g, "b", "translate"), {0, 0, 9});  // '.' is still the current node
}

TEST(MaReader, LongAttributeNamesAreCanonical) {
    Graph g = read(R"(createNode transform -n "a";
	setAttr ".translate" -type "double3" 1 2 3;
	setAttr ".rotateX" 90;
createNode transform -n "b";
connectAttr "a.translate" "b.t";
)");
    NodeId a = findNode(g, "a");
    NodeId b = findNode(g, "b");
    expectValues(numbersOf(g, "a", "t"), {1, 2, 3});
    EXPECT_NEAR(g.getDouble(a, "rx"), std::numbers::pi / 2, 1e-12);
    auto src = g.source(b, "translate");
    ASSERT_TRUE(src.has_value());
    EXPECT_EQ(src->node, a);
    EXPECT_EQ(src->path, "translate");
}

std::vector<int32_t> ids(std::span<const int32_t> s) { return {s.begin(), s.end()}; }

TEST(MaReader, PolyFacesWithHolesUvsAndColours) {
    Graph g = read(R"(createNode mesh -n "m";
	setAttr -s 2 -ch 11 ".fc[0:1]" -type "polyFaces"
		f 4 0 5 -2 -5
		mu 0 4 0 1 3 2
		mu 1 4 4 5 7 6
		fc 4 0 1 2 3
		h 3 8 9 10
		mu 0 3 10 11 12
		f 4 1 7 -3 -7
		mf 4 2 3 5 4 ;
)");
    auto* pf = std::get_if<std::shared_ptr<const PolyFaces>>(g.value(findNode(g, "m"), "face[0]"));
    ASSERT_NE(pf, nullptr);
    const PolyFaces& faces = **pf;
    ASSERT_EQ(faces.faceCount(), 2u);
    ASSERT_EQ(faces.loopCount(), 3u);
    ASSERT_EQ(faces.loops(0).size(), 2u);
    const size_t outer = faces.loops(0)[0], hole = faces.loops(0)[1];
    EXPECT_EQ(ids(faces.edges(outer)), (std::vector<int32_t>{0, 5, -2, -5}));
    ASSERT_EQ(faces.uvCount(outer), 2u);
    EXPECT_EQ(faces.uv(outer, 0).set, 0);
    EXPECT_EQ(ids(faces.uv(outer, 0).ids), (std::vector<int32_t>{0, 1, 3, 2}));
    EXPECT_EQ(faces.uv(outer, 1).set, 1);
    EXPECT_EQ(ids(faces.uv(outer, 1).ids), (std::vector<int32_t>{4, 5, 7, 6}));
    EXPECT_EQ(ids(faces.colors(outer)), (std::vector<int32_t>{0, 1, 2, 3}));
    EXPECT_EQ(ids(faces.edges(hole)), (std::vector<int32_t>{8, 9, 10}));
    ASSERT_EQ(faces.uvCount(hole), 1u);
    EXPECT_EQ(ids(faces.uv(hole, 0).ids), (std::vector<int32_t>{10, 11, 12}));
    EXPECT_TRUE(faces.colors(hole).empty());
    ASSERT_EQ(faces.loops(1).size(), 1u);
    const size_t second = faces.loops(1)[0];
    EXPECT_EQ(ids(faces.edges(second)), (std::vector<int32_t>{1, 7, -3, -7}));
    ASSERT_EQ(faces.uvCount(second), 1u);
    EXPECT_EQ(faces.uv(second, 0).set, 0);
    EXPECT_EQ(ids(faces.uv(second, 0).ids), (std::vector<int32_t>{2, 3, 5, 4}));
    EXPECT_TRUE(faces.colors(second).empty());
}

// The records of a face may come in any order: `mf` after `h` names the outer loop again, `mh`
// the last hole. Each loop keeps its own records in file order.
TEST(MaReader, PolyFacesRecordsOfAFaceInAnyOrder) {
    Graph g = read(R"(createNode mesh -n "m";
	setAttr ".fc[0:2]" -type "polyFaces"
		f 3 0 1 2
		h 3 3 4 5
		h 4 6 7 8 9
		mf 3 20 21 22
		mu 1 4 30 31 32 33
		mh 4 40 41 42 43
		fc 4 9 9 9 9
		mf 3 23 24 25
		f 3 10 11 12
		mu 0 3 50 51 52
		f 3 13 14 15 ;
)");
    auto* pf = std::get_if<std::shared_ptr<const PolyFaces>>(g.value(findNode(g, "m"), "face[0]"));
    ASSERT_NE(pf, nullptr);
    const PolyFaces& faces = **pf;
    ASSERT_EQ(faces.faceCount(), 3u);
    ASSERT_EQ(faces.loops(0).size(), 3u);
    const size_t outer = faces.loops(0)[0], hole1 = faces.loops(0)[1], hole2 = faces.loops(0)[2];
    EXPECT_EQ(ids(faces.edges(outer)), (std::vector<int32_t>{0, 1, 2}));
    ASSERT_EQ(faces.uvCount(outer), 2u);
    EXPECT_EQ(ids(faces.uv(outer, 0).ids), (std::vector<int32_t>{20, 21, 22}));
    EXPECT_EQ(ids(faces.uv(outer, 1).ids), (std::vector<int32_t>{23, 24, 25}));
    EXPECT_TRUE(faces.colors(outer).empty());
    EXPECT_EQ(ids(faces.edges(hole1)), (std::vector<int32_t>{3, 4, 5}));
    EXPECT_EQ(faces.uvCount(hole1), 0u);
    EXPECT_EQ(ids(faces.edges(hole2)), (std::vector<int32_t>{6, 7, 8, 9}));
    ASSERT_EQ(faces.uvCount(hole2), 2u);
    EXPECT_EQ(faces.uv(hole2, 0).set, 1);
    EXPECT_EQ(ids(faces.uv(hole2, 0).ids), (std::vector<int32_t>{30, 31, 32, 33}));
    EXPECT_EQ(faces.uv(hole2, 1).set, 0);
    EXPECT_EQ(ids(faces.uv(hole2, 1).ids), (std::vector<int32_t>{40, 41, 42, 43}));
    EXPECT_EQ(ids(faces.colors(hole2)), (std::vector<int32_t>{9, 9, 9, 9}));
    ASSERT_EQ(faces.loops(1).size(), 1u);
    const size_t second = faces.loops(1)[0];
    EXPECT_EQ(ids(faces.edges(second)), (std::vector<int32_t>{10, 11, 12}));
    ASSERT_EQ(faces.uvCount(second), 1u);
    EXPECT_EQ(faces.uv(second, 0).set, 0);
    EXPECT_EQ(ids(faces.uv(second, 0).ids), (std::vector<int32_t>{50, 51, 52}));
    const size_t third = faces.loops(2)[0];
    EXPECT_EQ(ids(faces.edges(third)), (std::vector<int32_t>{13, 14, 15}));
    EXPECT_EQ(faces.uvCount(third), 0u);
    EXPECT_TRUE(faces.colors(third).empty());
}

// Faces that all name the same uv sets, faces whose sets differ from those before them, holes and
// colours that first appear late in a run: every face reads back as written.
TEST(MaReader, PolyFacesReadBackWhateverTheirMix) {
    std::mt19937 rng(7);
    struct Loop {
        std::vector<int32_t> edges;
        std::vector<std::pair<int32_t, std::vector<int32_t>>> uvs;
        std::vector<int32_t> colors;
    };
    std::vector<std::vector<Loop>> written;
    std::string text = "createNode mesh -n \"m\";\n\tsetAttr \".fc[0:299]\" -type \"polyFaces\"\n";
    int32_t next = 0;
    for (int f = 0; f < 300; ++f) {
        // The first 100 faces are quads with uv set 0 only; then anything goes.
        const bool plain = f < 100;
        const int loops = plain ? 1 : 1 + int(rng() % 3 == 0) * int(1 + rng() % 2);
        std::vector<Loop> face;
        for (int l = 0; l < loops; ++l) {
            Loop loop;
            const int n = plain ? 4 : 3 + int(rng() % 4);
            for (int i = 0; i < n; ++i) loop.edges.push_back(rng() % 2 ? next++ : -next++);
            text += std::string(l == 0 ? "\t\tf " : "\t\th ") + std::to_string(n);
            for (int32_t e : loop.edges) text += " " + std::to_string(e);
            const int uvs = plain ? 1 : int(rng() % 3);
            for (int u = 0; u < uvs; ++u) {
                const int32_t set = plain ? 0 : int32_t(rng() % 3);
                std::vector<int32_t> uvIds;
                for (int i = 0; i < n; ++i) uvIds.push_back(next++);
                text += " mu " + std::to_string(set) + " " + std::to_string(n);
                for (int32_t id : uvIds) text += " " + std::to_string(id);
                loop.uvs.emplace_back(set, std::move(uvIds));
            }
            if (!plain && rng() % 4 == 0) {
                for (int i = 0; i < n; ++i) loop.colors.push_back(next++);
                text += " fc " + std::to_string(n);
                for (int32_t id : loop.colors) text += " " + std::to_string(id);
            }
            text += "\n";
            face.push_back(std::move(loop));
        }
        written.push_back(std::move(face));
    }
    text += ";\n";
    Graph g = read(text);
    ASSERT_TRUE(g.warnings().empty()) << g.warnings()[0].message;
    auto* pf = std::get_if<std::shared_ptr<const PolyFaces>>(g.value(findNode(g, "m"), "face[0]"));
    ASSERT_NE(pf, nullptr);
    const PolyFaces& faces = **pf;
    ASSERT_EQ(faces.faceCount(), written.size());
    size_t loopsSeen = 0;
    for (size_t f = 0; f < written.size(); ++f) {
        SCOPED_TRACE("face " + std::to_string(f));
        const auto loops = faces.loops(f);
        ASSERT_EQ(loops.size(), written[f].size());
        for (size_t l = 0; l < loops.size(); ++l) {
            const Loop& want = written[f][l];
            const size_t loop = loops[l];
            EXPECT_EQ(loop, loopsSeen++);
            EXPECT_EQ(ids(faces.edges(loop)), want.edges);
            ASSERT_EQ(faces.uvCount(loop), want.uvs.size());
            for (size_t u = 0; u < want.uvs.size(); ++u) {
                EXPECT_EQ(faces.uv(loop, u).set, want.uvs[u].first);
                EXPECT_EQ(ids(faces.uv(loop, u).ids), want.uvs[u].second);
            }
            EXPECT_EQ(ids(faces.colors(loop)), want.colors);
        }
    }
    EXPECT_EQ(faces.loopCount(), loopsSeen);
}

// A run of quads with one uv set each, as Maya writes most meshes, keeps 36 bytes per face: four
// edge ids, four uv ids and where the face's edges begin.
TEST(MaReader, PolyFacesOfQuadsWithOneUvSetTakeFewBytes) {
    std::string text = "createNode mesh -n \"m\";\n\tsetAttr \".fc[0:999]\" -type \"polyFaces\"\n";
    for (int f = 0; f < 1000; ++f) {
        const std::string a = std::to_string(4 * f), b = std::to_string(4 * f + 1), c = std::to_string(4 * f + 2),
                          d = std::to_string(4 * f + 3);
        text += "\t\tf 4 " + a + " " + b + " -" + c + " -" + d + "\n\t\tmu 0 4 " + a + " " + b + " " + c + " " + d + "\n";
    }
    text += ";\n";
    Graph g = read(text);
    auto* pf = std::get_if<std::shared_ptr<const PolyFaces>>(g.value(findNode(g, "m"), "face[0]"));
    ASSERT_NE(pf, nullptr);
    ASSERT_EQ((*pf)->faceCount(), 1000u);
    EXPECT_LE((*pf)->heapBytes(), 36u * 1000 + 64);
    EXPECT_EQ(ids((*pf)->uv(999, 0).ids), (std::vector<int32_t>{3996, 3997, 3998, 3999}));
    EXPECT_EQ(ids((*pf)->edges(999)), (std::vector<int32_t>{3996, 3997, -3998, -3999}));
}

TEST(MaReader, NurbsCurve) {
    Graph g = read(R"(createNode nurbsCurve -n "c";
	setAttr ".cc" -type "nurbsCurve"
		3 2 0 no 3
		7 0 0 0 1 2 2 2
		5
		0 0 0
		1 1 0
		2 0 0
		3 1 0
		4 0 0
		;
)");
    auto* c = std::get_if<std::shared_ptr<const NurbsCurveData>>(g.value(findNode(g, "c"), "cc"));
    ASSERT_NE(c, nullptr);
    EXPECT_EQ((*c)->degree, 3);
    EXPECT_EQ((*c)->spans, 2);
    EXPECT_EQ((*c)->form, 0);
    EXPECT_FALSE((*c)->rational);
    EXPECT_EQ((*c)->dimension, 3);
    EXPECT_EQ((*c)->knots, (std::vector<double>{0, 0, 0, 1, 2, 2, 2}));
    ASSERT_EQ((*c)->cvs.size(), 15u);
    EXPECT_EQ((*c)->cvs[9], 3);
}

TEST(MaReader, NurbsSurfaceWithAndWithoutTrimToken) {
    const char* body = R"(
		3 3 0 2 yes
		6 0 0 0 1 1 1
		%KNOTSV%
		%TRIM%
		%COUNT%
)";
    auto make = [&](const std::string& trim) {
        std::string text = std::string("createNode nurbsSurface -n \"s\";\n\tsetAttr \".cc\" -type \"nurbsSurface\"") + body;
        auto rep = [&](const std::string& key, const std::string& v) { text.replace(text.find(key), key.size(), v); };
        // Periodic V, degree 3: 7 knots → 5 CVs in V; open U: 6 knots → 4 CVs. Rational: 4 numbers each.
        rep("%KNOTSV%", "7 -2 -1 0 1 2 3 4");
        rep("%TRIM%", trim);
        std::string cvs = "20\n";
        for (int i = 0; i < 20; ++i) cvs += std::to_string(i) + " 0 " + std::to_string(-i) + " 1\n";
        rep("%COUNT%", cvs);
        return text + ";\n";
    };
    for (const std::string trim : {"", "NOTRIM", "TRIM"}) {
        Graph g = read(make(trim));
        auto* s = std::get_if<std::shared_ptr<const NurbsSurfaceData>>(g.value(findNode(g, "s"), "cc"));
        ASSERT_NE(s, nullptr) << trim;
        EXPECT_EQ((*s)->degreeU, 3);
        EXPECT_EQ((*s)->formV, 2);
        EXPECT_TRUE((*s)->rational);
        EXPECT_EQ((*s)->trimmed, trim == "TRIM");
        EXPECT_EQ((*s)->cvCountU, 4);
        EXPECT_EQ((*s)->cvCountV, 5);
        ASSERT_EQ((*s)->cvs.size(), 80u);
        EXPECT_EQ((*s)->cvs[4 * 7], 7);
        EXPECT_EQ((*s)->cvs[4 * 7 + 2], -7);
        EXPECT_EQ((*s)->knotsV.front(), -2);
    }
}

// ------------------------------------------------------------------ addAttr

TEST(MaReader, AddAttrThenSetAttrByShortAndLongName) {
    Graph g = read(R"(currentUnit -l m;
createNode transform -n "t";
	addAttr -ci true -sn "bl" -ln "blurLength" -min 0 -max 10 -at "double";
	addAttr -ci true -k true -sn "off" -ln "offsetDistance" -dv 2 -at "doubleLinear";
	addAttr -ci true -uac -sn "tint" -ln "tintColor" -at "float3" -nc 3;
	addAttr -ci true -sn "tintR" -ln "tintColorR" -dv 1 -at "float" -p "tintColor";
	addAttr -ci true -sn "tintG" -ln "tintColorG" -dv 0.5 -at "float" -p "tint";
	addAttr -ci true -sn "tintB" -ln "tintColorB" -at "float" -p "tintColor";
	addAttr -ci true -m -sn "lst" -ln "labels" -dt "string";
	addAttr -ci true -longName "notes" -shortName "nts" -dataType "string";
	setAttr ".bl" 3;
	setAttr ".offsetDistance" 1.5;
	setAttr ".tintG" 0.25;
	setAttr ".labels[2]" -type "string" "two";
	setAttr ".nts" -type "string" "hello";
createNode transform -n "u";
connectAttr "t.blurLength" "u.tx";
)");
    NodeId t = findNode(g, "t");
    const Node& n = g.node(t);
    ASSERT_EQ(n.dynamicAttrs().size(), 8u);
    const AttrSpec* bl = n.findAttr("bl");
    ASSERT_NE(bl, nullptr);
    EXPECT_EQ(bl->longName, "blurLength");
    EXPECT_EQ(bl->type, AttrType::Double);
    const AttrSpec* off = n.findAttr("offsetDistance");
    ASSERT_NE(off, nullptr);
    EXPECT_EQ(off->unit, UnitKind::Distance);
    EXPECT_EQ(off->defaults[0], 2);
    const AttrSpec* tintG = n.findAttr("tintColorG");
    ASSERT_NE(tintG, nullptr);
    EXPECT_EQ(tintG->parent, "tintColor");
    EXPECT_EQ(tintG->component, 1);
    const AttrSpec* labels = n.findAttr("lst");
    ASSERT_NE(labels, nullptr);
    EXPECT_TRUE(labels->multi);
    EXPECT_EQ(labels->type, AttrType::String);
    EXPECT_DOUBLE_EQ(g.getDouble(t, "blurLength"), 3.0);
    EXPECT_DOUBLE_EQ(g.getDouble(t, "off"), 150.0);  // doubleLinear follows currentUnit
    std::vector<double> tint;
    ASSERT_TRUE(g.numbers(t, "tintColor", tint));
    EXPECT_EQ(tint, (std::vector<double>{1, 0.25, 0}));
    EXPECT_EQ(g.getString(t, "lst[2]"), "two");
    EXPECT_EQ(g.getString(t, "notes"), "hello");
    auto src = g.source(findNode(g, "u"), "translateX");
    ASSERT_TRUE(src.has_value());
    EXPECT_EQ(src->path, "blurLength");
}

TEST(MaReader, AddAttrOnANamedNode) {
    Graph g = read(R"(createNode transform -n "t";
createNode transform -n "u";
addAttr -ln "extra" -at long "t";
setAttr "t.extra" 4;
)");
    EXPECT_NE(g.node(findNode(g, "t")).findAttr("extra"), nullptr);
    EXPECT_EQ(g.node(findNode(g, "u")).findAttr("extra"), nullptr);
    EXPECT_EQ(g.getInt(findNode(g, "t"), "extra"), 4);
}

// ------------------------------------------------------------------ connections

TEST(MaReader, ConnectAttrFlagsAndDisconnect) {
    Graph g = read(R"(createNode lambert -n "m";
createNode shadingEngine -n "sg";
createNode transform -n "t";
createNode mesh -n "s" -p "t";
createNode place2dTexture -n "p";
createNode file -n "f";
connectAttr "m.oc" "sg.ss";
connectAttr "s.iog" "sg.dsm" -na;
connectAttr -nextAvailable "t.iog" "sg.dsm";
connectAttr -f "p.o" "f.uv";
connectAttr "p.ofs" "f.fs" -l on;
disconnectAttr "p.ofs" "f.fs";
connectAttr "sg.msg" ":defaultLightSet.dsm" -na;
)");
    NodeId sg = findNode(g, "sg");
    auto ss = g.source(sg, "surfaceShader");
    ASSERT_TRUE(ss.has_value());
    EXPECT_EQ(ss->node, findNode(g, "m"));
    EXPECT_EQ(ss->path, "outColor");
    auto d0 = g.source(sg, "dagSetMembers[0]");
    auto d1 = g.source(sg, "dagSetMembers[1]");
    ASSERT_TRUE(d0.has_value());
    ASSERT_TRUE(d1.has_value());
    EXPECT_EQ(d0->node, findNode(g, "s"));
    EXPECT_EQ(d1->node, findNode(g, "t"));
    NodeId f = findNode(g, "f");
    EXPECT_TRUE(g.source(f, "uvCoord").has_value());
    EXPECT_FALSE(g.source(f, "fs").has_value());
    EXPECT_EQ(g.inputs(g.find(":defaultLightSet")).size(), 1u);
}

TEST(MaReader, RelationshipsAreKept) {
    Graph g = read(R"(createNode lightLinker -s -n "lightLinker1";
createNode shadingEngine -n "sg";
relationship "link" ":lightLinker1" "sg.message" ":defaultLightSet.message";
relationship "shadowLink" ":lightLinker1" ":initialShadingGroup.message" ":defaultLightSet.message";
relationship "ignore" ":lightLinker1" "sg.msg";
)");
    ASSERT_EQ(g.relationships().size(), 3u);
    const Relationship& r = g.relationships()[0];
    EXPECT_EQ(r.type, "link");
    ASSERT_EQ(r.plugs.size(), 3u);
    EXPECT_EQ(r.plugs[0].node, g.find("lightLinker1"));
    EXPECT_EQ(r.plugs[0].path, "");
    EXPECT_EQ(r.plugs[1].node, g.find("sg"));
    EXPECT_EQ(r.plugs[1].path, "message");
    EXPECT_EQ(r.plugs[2].node, g.find("defaultLightSet"));
    EXPECT_EQ(g.relationships()[1].type, "shadowLink");
    EXPECT_EQ(g.relationships()[2].type, "ignore");
    EXPECT_EQ(g.relationships()[2].plugs[1].path, "message");
}

// ------------------------------------------------------------------ DAG, selection, locking

TEST(MaReader, ParentAddCreatesAnInstance) {
    Graph g = read(R"(createNode transform -n "pCube1";
createNode mesh -n "pCubeShape1" -p "pCube1";
createNode transform -n "pCube2";
parent -s -nc -r -add "|pCube1|pCubeShape1" "pCube2";
)");
    NodeId shape = findNode(g, "pCubeShape1");
    auto paths = g.dagPaths(shape);
    ASSERT_EQ(paths.size(), 2u);
    EXPECT_EQ(g.dagPathName(paths[0]), "|pCube1|pCubeShape1");
    EXPECT_EQ(g.dagPathName(paths[1]), "|pCube2|pCubeShape1");
}

// A per-instance attribute named through one instance's path, without an index, is that
// instance's element: each instance keeps its own shading group.
TEST(MaReader, InstancePathsSelectTheirOwnInstObjGroupsElement) {
    Graph g = read(R"(createNode transform -n "grp";
createNode transform -n "a" -p "grp";
createNode mesh -n "shape" -p "a";
createNode transform -n "b" -p "grp";
createNode transform -n "c" -p "grp";
parent -s -nc -r -add "|grp|a|shape" "b";
parent -s -nc -r -add "|grp|a|shape" "c";
createNode shadingEngine -n "sgA";
createNode shadingEngine -n "sgC";
connectAttr "|grp|a|shape.iog" "sgA.dsm" -na;
connectAttr "c|shape.iog" "sgC.dsm" -na;
connectAttr "|grp|b|shape.iog.og[0]" "sgC.dsm" -na;
connectAttr "|grp|c|shape.wm" "sgA.msg";
connectAttr "shape.iog[1]" "sgA.dsm" -na;
)");
    const NodeId shape = findNode(g, "shape");
    ASSERT_EQ(g.dagPaths(shape).size(), 3u);
    std::vector<std::string> sources;
    for (const std::string sg : {"sgA", "sgC"})
        for (const Connection* c : g.inputs(findNode(g, sg)))
            if (c->src.node == shape) sources.push_back(sg + "<-" + c->src.path);
    EXPECT_EQ(sources, (std::vector<std::string>{"sgA<-instObjGroups[0]", "sgA<-worldMatrix[2]", "sgA<-instObjGroups[1]",
                                                 "sgC<-instObjGroups[2]", "sgC<-instObjGroups[1].objectGroups[0]"}));
}

TEST(MaReader, ParentReparentsAndWorld) {
    Graph g = read(R"(createNode transform -n "a";
createNode transform -n "b";
createNode transform -n "c" -p "a";
parent "c" "b";
createNode transform -n "d" -p "a";
parent -w "d";
)");
    NodeId c = findNode(g, "c");
    ASSERT_EQ(g.node(c).parents().size(), 1u);
    EXPECT_EQ(g.node(c).parents()[0], findNode(g, "b"));
    EXPECT_TRUE(g.node(findNode(g, "d")).parents().empty());
    EXPECT_TRUE(g.node(findNode(g, "a")).children().empty());
}

TEST(MaReader, SelectNoExpandEditsDefaultNodes) {
    Graph g = read(R"(createNode transform -n "t";
select -ne :defaultRenderGlobals;
	setAttr ".an" yes;
	setAttr ".outf" 7;
select -noExpand :time1;
	setAttr ".o" 12;
select -ne :defaultColorMgtGlobals;
	setAttr ".cme" no;
select -ne t;
	setAttr ".tx" 1;
)");
    NodeId rg = findNode(g, "defaultRenderGlobals");
    EXPECT_TRUE(g.getBool(rg, "animation"));
    EXPECT_EQ(g.getInt(rg, "imageFormat", -1), 7);
    EXPECT_DOUBLE_EQ(g.getDouble(findNode(g, "time1"), "o"), 12.0);
    NodeId cm = findNode(g, "defaultColorMgtGlobals");
    EXPECT_EQ(g.node(cm).line, 0u);  // created implicitly
    EXPECT_FALSE(g.getBool(cm, "cme", true));
    EXPECT_DOUBLE_EQ(g.getDouble(findNode(g, "t"), "translateX"), 1.0);
}

TEST(MaReader, LockNode) {
    Graph g = read(R"(createNode transform -n "a";
	lockNode -l 1 ;
createNode transform -n "b";
lockNode -l 1 -lu 1 "b";
createNode transform -n "c";
	lockNode -l 0;
createNode transform -n "d";
lockNode -l 1 -bogus 3 "d";
)");
    EXPECT_TRUE(g.node(findNode(g, "a")).locked);
    EXPECT_TRUE(g.node(findNode(g, "b")).locked);
    EXPECT_FALSE(g.node(findNode(g, "c")).locked);
    // A flag lockNode does not know is reported and skipped with its number; the node still locks.
    EXPECT_TRUE(g.node(findNode(g, "d")).locked);
    ASSERT_EQ(g.warnings().size(), 1u);
    EXPECT_NE(g.warnings()[0].message.find("lockNode: unknown flag -bogus"), std::string::npos) << g.warnings()[0].message;
}

// ------------------------------------------------------------------ warnings

TEST(MaReader, UnknownCommandsAreSkippedWithOneWarningEach) {
    Graph g = read(R"(createNode transform -n "a";
dataStructure -fmt "raw" -as "name=x:string=node";
applyMetadata -fmt "raw" -v "channel\nname x\n";
applyMetadata -fmt "raw" -v "again";
workspace -fr "images" "images";
	setAttr ".tx" 2;
)");
    ASSERT_EQ(g.warnings().size(), 3u);
    EXPECT_NE(g.warnings()[0].message.find("'dataStructure'"), std::string::npos);
    EXPECT_EQ(g.warnings()[0].line, 2u);
    EXPECT_EQ(g.warnings()[0].column, 1u);
    EXPECT_NE(g.warnings()[1].message.find("'applyMetadata'"), std::string::npos);
    EXPECT_NE(g.warnings()[2].message.find("'workspace'"), std::string::npos);
    EXPECT_DOUBLE_EQ(g.getDouble(findNode(g, "a"), "tx"), 2.0);
}

TEST(MaReader, CommentsAndBlankCommands) {
    Graph g = read("// header\n/* block\n comment */ createNode transform -n \"a\"; ;; // trailing\n"
                   "\tsetAttr \".tx\" 1; // end\n");
    EXPECT_DOUBLE_EQ(g.getDouble(findNode(g, "a"), "tx"), 1.0);
}

// ------------------------------------------------------------------ references

TEST(MaReader, ReferencesAreMergedUnderTheirNamespace) {
    TempDir dir;
    dir.write("assets/cube.ma", R"(//Maya ASCII 2018 scene
currentUnit -l m -a deg -t film;
createNode transform -n "pCube1";
	setAttr ".t" -type "double3" 1 0 0 ;
createNode mesh -n "pCubeShape1" -p "pCube1";
createNode lambert -n "mat";
connectAttr "mat.msg" ":defaultShaderList1.s" -na;
)");
    const fs::path scene = dir.write("shot.ma", R"(//Maya ASCII 2018 scene
file -rdi 1 -ns "hero" -rfn "heroRN" "assets/cube.ma";
file -r -ns "hero" -dr 1 -rfn "heroRN" -typ "mayaAscii" "assets/cube.ma";
file -r -ns "prop" -rfn "propRN" "/nowhere/that/exists/cube.ma";
requires maya "2018";
currentUnit -l centimeter -a degree -t film;
createNode reference -n "heroRN";
	setAttr ".ed" -type "dataReferenceEdits"
		"heroRN"
		"heroRN" 0;
createNode transform -n "grp";
parent -s -add "hero:pCubeShape1" "grp";
	setAttr "hero:pCube1.ty" 2;
	setAttr "prop:thing.tx" 3;
connectAttr "prop:thing.msg" "grp.msg";
)");
    Graph g = MaReader::readFile(scene);
    NodeId cube = findNode(g, "hero:pCube1");
    expectValues(numbersOf(g, "hero:pCube1", "translate"), {100, 2, 0});  // the reference is in metres
    NodeId shape = findNode(g, "hero:pCubeShape1");
    ASSERT_EQ(g.node(shape).parents().size(), 2u);
    EXPECT_EQ(g.node(shape).parents()[0], cube);
    EXPECT_EQ(g.node(shape).parents()[1], findNode(g, "grp"));
    EXPECT_NE(g.find("hero:mat"), kNoNode);
    EXPECT_EQ(g.find("mat"), kNoNode);
    ASSERT_EQ(g.references.size(), 1u);
    EXPECT_NE(g.references[0].find("cube.ma"), std::string::npos);
    EXPECT_DOUBLE_EQ(g.units.cmPerLinearUnit, 1.0);
    // The missing reference: one warning naming it, and edits to its nodes are skipped.
    int refWarnings = 0;
    for (const Diagnostic& d : g.warnings())
        if (d.message.find("/nowhere/that/exists/cube.ma") != std::string::npos) ++refWarnings;
    EXPECT_EQ(refWarnings, 1);
}

TEST(MaReader, ReferencesHonourReadOptions) {
    TempDir dir;
    dir.write("a.ma", "createNode transform -n \"x\";\nfile -r -ns \"b\" \"b.ma\";\n");
    dir.write("b.ma", "createNode transform -n \"y\";\nfile -r -ns \"c\" \"c.ma\";\n");
    dir.write("c.ma", "createNode transform -n \"z\";\nfile -r -ns \"d\" \"d.ma\";\n");
    dir.write("d.ma", "createNode transform -n \"w\";\n");
    const fs::path scene = dir.write("s.ma", "file -r -ns \"a\" \"a.ma\";\n");
    ReadOptions off;
    off.loadReferences = false;
    Graph none = MaReader::readFile(scene, off);
    EXPECT_EQ(none.find("a:x"), kNoNode);
    EXPECT_TRUE(none.references.empty());
    ASSERT_EQ(none.warnings().size(), 1u);

    ReadOptions shallow;
    shallow.maxReferenceDepth = 3;
    Graph g = MaReader::readFile(scene, shallow);
    EXPECT_NE(g.find("a:x"), kNoNode);
    EXPECT_NE(g.find("a:b:y"), kNoNode);
    EXPECT_NE(g.find("a:b:c:z"), kNoNode);
    EXPECT_EQ(g.find("a:b:c:d:w"), kNoNode);  // stopped by the depth limit
    EXPECT_EQ(g.references.size(), 3u);
}

TEST(MaReader, RecursiveReferenceIsRefusedNamingTheChain) {
    TempDir dir;
    dir.write("a.ma", "createNode transform -n \"x\";\nfile -r -ns \"b\" \"b.ma\";\n");
    dir.write("b.ma", "createNode transform -n \"y\";\nfile -r -ns \"a\" \"./a.ma\";\n");  // a cycle
    const fs::path scene = dir.write("s.ma", "file -r -ns \"a\" \"a.ma\";\n");
    Graph g = MaReader::readFile(scene);
    EXPECT_NE(g.find("a:x"), kNoNode);
    EXPECT_NE(g.find("a:b:y"), kNoNode);
    EXPECT_EQ(g.find("a:b:a:x"), kNoNode);  // Maya refuses the recursive reference too
    EXPECT_EQ(g.references.size(), 2u);
    ASSERT_EQ(g.warnings().size(), 1u);
    const Diagnostic& d = g.warnings()[0];
    EXPECT_NE(d.file.find("b.ma"), std::string::npos) << d.file;
    EXPECT_EQ(d.line, 2u);
    EXPECT_NE(d.message.find("already being loaded (a.ma -> b.ma -> a.ma)"), std::string::npos) << d.message;
}

// ------------------------------------------------------------------ streaming

TEST(MaReader, StreamsThroughBufferBoundaries) {
    // Long lines, strings and number lists straddle the 1 MiB buffer many times.
    std::string text = "createNode mesh -n \"m\";\n\tsetAttr -s 200000 \".vt[0:199999]\"";
    for (int i = 0; i < 200000; ++i) text += (i % 7 == 0 ? "\n\t\t" : " ") + std::to_string(i) + " 0.5 -1e-3";
    text += ";\ncreateNode script -n \"s\";\n\tsetAttr \".b\" -type \"string\" \"";
    for (int i = 0; i < 300000; ++i) text += i % 1000 == 0 ? "\\n" : "abc";
    text += "\";\n//comment at end";
    std::istringstream in(text);
    Graph g = MaReader::readStream(in, "big.ma");
    Graph h = MaReader::readString(text, "big.ma");
    for (const Graph* gr : {&g, &h}) {
        NodeId m = gr->find("m");
        ASSERT_NE(m, kNoNode);
        std::vector<double> p;
        ASSERT_TRUE(gr->numbers(m, "vrts[199999]", p));
        EXPECT_EQ(p, (std::vector<double>{199999, 0.5, double(-1e-3f)}));  // single precision, as in Maya
        EXPECT_EQ(gr->getString(gr->find("s"), "b").size(), 300u + 299700u * 3);
    }
}

TEST(MaLexer, TinyBufferGivesTheSameTokensAsInMemoryText) {
    // Every token boundary, escape, comment opener and line break lands on a buffer edge somewhere.
    const std::string text =
        "//Maya ASCII\n/* c */ createNode transform -n \"a\";\r\n\tsetAttr \".t\" -type \"double3\" 1 -2.5e+01 3;\n"
        "setAttr \".s\" -type \"string\" (\"x\\\"y\\\\z\\n\" + \"w\");\n/a/b //tail\n{\"p\",\"q\"} / ;";
    using detail::MaLexer;
    using detail::MaToken;
    using detail::MaTokenKind;
    std::vector<MaToken> expected;
    {
        MaLexer lex{std::string_view(text)};
        MaToken t;
        do {
            lex.next(t);
            expected.push_back(t);
        } while (t.kind != MaTokenKind::End);
    }
    ASSERT_GT(expected.size(), 30u);
    EXPECT_EQ(expected[2].text, "-n");
    EXPECT_EQ(expected[3].kind, MaTokenKind::String);
    EXPECT_EQ(expected[3].line, 2u);
    EXPECT_EQ(expected[3].column, 33u);
    for (size_t bufferBytes : {16, 17, 19, 23, 31, 64}) {
        std::istringstream in(text);
        MaLexer lex(in, bufferBytes);
        MaToken t;
        for (size_t i = 0; i < expected.size(); ++i) {
            lex.next(t);
            EXPECT_EQ(int(t.kind), int(expected[i].kind)) << "buffer " << bufferBytes << " token " << i;
            EXPECT_EQ(t.text, expected[i].text) << "buffer " << bufferBytes << " token " << i;
            EXPECT_EQ(t.line, expected[i].line) << "buffer " << bufferBytes << " token " << i;
            EXPECT_EQ(t.column, expected[i].column) << "buffer " << bufferBytes << " token " << i;
        }
    }
    // Shift the text by one byte at a time so that every character sits on a 16-byte boundary once.
    for (size_t shift = 1; shift < 16; ++shift) {
        const std::string padded = std::string(shift, ' ') + text;
        std::istringstream in(padded);
        MaLexer lex(in, 16);
        MaToken t;
        for (size_t i = 0; i < expected.size(); ++i) {
            lex.next(t);
            EXPECT_EQ(t.text, expected[i].text) << "shift " << shift << " token " << i;
        }
    }
}

TEST(MaReader, ReadFileMissingIsAnIoError) {
    EXPECT_THROW(MaReader::readFile("/nonexistent/dir/scene.ma"), IoError);
}

// ------------------------------------------------------------------ corpus

TEST(MaReader, ReadsEveryCorpusFile) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    int files = 0;
    for (const fs::path& path : test::maCorpusFiles()) {
        ++files;
        SCOPED_TRACE(path.string());
        Graph g;
        ASSERT_NO_THROW(g = MaReader::readFile(path));
        EXPECT_GT(g.size(), 23u);  // more than the implicit default nodes
        EXPECT_FALSE(g.requirements.empty());
        // Every mesh with explicit polyFaces has as many faces stored as its ranges say.
        for (NodeId id : g.nodesOfType("mesh", false)) {
            const AttrData* fc = g.findAttr(id, "face");
            if (!fc) continue;
            for (const auto& [first, run] : fc->multi.runs()) {
                auto* pf = std::get_if<std::shared_ptr<const PolyFaces>>(&run.value);
                ASSERT_NE(pf, nullptr);
                EXPECT_EQ((*pf)->faceCount(), run.count);
            }
        }
    }
    EXPECT_GT(files, 0);
}

TEST(MaReader, CorpusLongFlagFileAndNurbs) {
    const fs::path corpus = PUSHPIN_MA_CORPUS;
    const fs::path longFlags = corpus / "sebastienblor__arnold-usd__test_0001_test.ma";
    const fs::path nurbs = corpus / "tws0002__pop2-project__CarrotTop.ma";
    if (!fs::exists(longFlags) || !fs::exists(nurbs)) GTEST_SKIP() << "corpus files are absent";
    Graph g = MaReader::readFile(longFlags);
    EXPECT_FALSE(g.nodesOfType("mesh", false).empty());
    Graph n = MaReader::readFile(nurbs);
    int surfaces = 0;
    for (NodeId id : n.nodesOfType("nurbsSurface", false))
        if (auto* v = n.value(id, "cc"); v && std::holds_alternative<std::shared_ptr<const NurbsSurfaceData>>(*v)) {
            const auto& s = *std::get<std::shared_ptr<const NurbsSurfaceData>>(*v);
            EXPECT_EQ(size_t(s.cvCountU * s.cvCountV * (s.rational ? 4 : 3)), s.cvs.size());
            ++surfaces;
        }
    EXPECT_GT(surfaces, 0);
}

// ------------------------------------------------------------------ what Maya writes and pushpin tolerates

const PolyFaces* polyFacesAt(const Graph& g, std::string_view node, std::string_view plug) {
    const Value* v = g.value(findNode(g, node), plug);
    auto* pf = v ? std::get_if<std::shared_ptr<const PolyFaces>>(v) : nullptr;
    return pf && *pf ? pf->get() : nullptr;
}

// Maya splits a long polyFaces run over several statements and names the type only in the first;
// the type of the rest comes from the schema (a mesh's .fc) or from the earlier element.
TEST(MaReaderTolerance, TypedValuesContinuedWithoutTheirType) {
    Graph g = read(R"(createNode mesh -n "m";
	setAttr -s 3 ".fc[0:1]" -type "polyFaces"
		f 3 0 1 2
		f 3 2 3 4;
	setAttr ".fc[2]"
		f 3 4 5 6
		mu 0 3 0 1 2;
createNode unknownThing -n "u";
	setAttr ".zz[0]" -type "polyFaces" f 3 0 1 2;
	setAttr ".zz[1]" f 4 0 1 2 3;
)");
    EXPECT_TRUE(g.warnings().empty()) << g.warnings()[0].message;
    const PolyFaces* first = polyFacesAt(g, "m", "face[0]");
    const PolyFaces* later = polyFacesAt(g, "m", "face[2]");
    ASSERT_NE(first, nullptr);
    ASSERT_NE(later, nullptr);
    EXPECT_EQ(first->faceCount(), 2u);
    ASSERT_EQ(later->faceCount(), 1u);
    EXPECT_EQ(ids(later->edges(later->loops(0)[0])), (std::vector<int32_t>{4, 5, 6}));
    const PolyFaces* unknown = polyFacesAt(g, "u", "zz[1]");
    ASSERT_NE(unknown, nullptr);
    EXPECT_EQ(unknown->edges(unknown->loops(0)[0]).size(), 4u);
}

// Data types pushpin does not model are skipped by their tokens, one warning per type.
TEST(MaReaderTolerance, UnmodelledDataTypesAreSkippedOncePerType) {
    Graph g = read(R"(createNode subdiv -n "s";
	setAttr ".ecr" -type "subdivEdgeCrease" 0 0;
	setAttr ".vcr" -type "subdivEdgeCrease" 2 0 1 "x" { 1, 2 };
	setAttr ".tx" 4;
)");
    ASSERT_EQ(g.warnings().size(), 1u);
    const Diagnostic& w = g.warnings()[0];
    EXPECT_EQ(w.line, 2u);
    EXPECT_EQ(w.node, "s");
    EXPECT_NE(w.message.find("\"subdivEdgeCrease\" is not modelled"), std::string::npos) << w.message;
    EXPECT_EQ(g.value(findNode(g, "s"), "ecr"), nullptr);
}

// A flag the command table does not know is skipped with the arguments its tokens look like, and
// never takes the node, the type or a plug.
TEST(MaReaderTolerance, UnknownFlagsNeverTakeTheNodeOrPlug) {
    Graph g = read(R"(createNode transform -zz 3 -n "a";
createNode -yy "big" transform -n "b";
	addAttr -ci true -qq "mtoa" -sn "ex" -ln "extra" -at "double";
	setAttr -ww 5 ".tx" 2;
connectAttr -vv "a.tx" "b.ty";
connectAttr "a.ty" "b.tz" -uu "x";
select -pp "a";
	setAttr ".sx" 3;
)");
    const NodeId a = findNode(g, "a"), b = findNode(g, "b");
    ASSERT_NE(a, kNoNode);
    ASSERT_NE(b, kNoNode);
    EXPECT_EQ(g.node(b).type, "transform");
    EXPECT_NE(g.node(b).findAttr("extra"), nullptr);
    EXPECT_DOUBLE_EQ(g.getDouble(b, "translateX"), 2.0);
    EXPECT_DOUBLE_EQ(g.getDouble(a, "scaleX"), 3.0);
    EXPECT_TRUE(g.source(b, "translateY").has_value());
    EXPECT_TRUE(g.source(b, "translateZ").has_value());
    // One warning per unknown flag, each at the flag.
    std::vector<std::string> flags;
    for (const Diagnostic& d : g.warnings()) flags.push_back(d.message.substr(0, d.message.find(" is skipped")));
    EXPECT_EQ(flags, (std::vector<std::string>{"createNode: unknown flag -zz", "createNode: unknown flag -yy",
                                               "addAttr: unknown flag -qq", "setAttr: unknown flag -ww",
                                               "connectAttr: unknown flag -vv", "connectAttr: unknown flag -uu",
                                               "select: unknown flag -pp"}));
    EXPECT_EQ(g.warnings()[0].line, 1u);
    EXPECT_EQ(g.warnings()[0].column, 22u);
}

// Files from Maya 2013 and earlier carry names in the system's 8-bit encoding: kept byte for byte.
TEST(MaReaderTolerance, Latin1NamesAreKeptByteForByte) {
    Graph g = read("createNode transform -n \"St\xfctzen\";\ncreateNode mesh -n \"St\xfctzenShape\" -p \"St\xfctzen\";\n"
                   "createNode transform -n \"Gr\xc3\xb6\xc3\x9f" "e\";\n");
    EXPECT_TRUE(g.warnings().empty());
    const NodeId t = findNode(g, "St\xfctzen");
    ASSERT_NE(t, kNoNode);
    EXPECT_EQ(g.node(t).name, "St\xfctzen");
    EXPECT_NE(g.find("|St\xfctzen|St\xfctzenShape"), kNoNode);
    EXPECT_NE(g.find("Gr\xc3\xb6\xc3\x9f" "e"), kNoNode);
}

// Underworld paths name nodes below a shape's own DAG: `shape->|child`.
TEST(MaReaderTolerance, UnderworldPathsResolve) {
    Graph g = read(R"(createNode transform -n "curve1";
createNode nurbsCurve -n "curveShape1" -p "curve1";
createNode transform -n "projectionCurve18" -p "|curve1|curveShape1->";
createNode nurbsCurve -n "projectionCurveShape18" -p "|curve1|curveShape1->|projectionCurve18";
select -ne "|curve1|curveShape1->|projectionCurve18";
	setAttr ".tx" 3;
connectAttr "curveShape1.ws" "|curve1|curveShape1->|projectionCurve18|projectionCurveShape18.cr";
)");
    EXPECT_TRUE(g.warnings().empty()) << g.warnings()[0].message;
    const NodeId shape = findNode(g, "curveShape1"), projection = findNode(g, "projectionCurve18");
    ASSERT_EQ(g.node(projection).parents().size(), 1u);
    EXPECT_EQ(g.node(projection).parents()[0], shape);
    EXPECT_DOUBLE_EQ(g.getDouble(projection, "translateX"), 3.0);
    EXPECT_TRUE(g.source(findNode(g, "projectionCurveShape18"), "create").has_value());
}

// A range before the last attribute: skin weights as counted (index, value) pairs per element, or
// an even share of the values for each element.
TEST(MaReaderTolerance, RangesInTheMiddleOfAPlug) {
    Graph g = read(R"(createNode skinCluster -n "skin1";
	setAttr -s 3 ".wl";
	setAttr ".wl[0:2].w"
		2 0 0.25 3 0.75
		1 1 1
		0;
createNode unknownThing -n "u";
	setAttr ".e[4:5].v" 1 2 3 4;
)");
    EXPECT_TRUE(g.warnings().empty()) << g.warnings()[0].message;
    const NodeId skin = findNode(g, "skin1");
    EXPECT_DOUBLE_EQ(g.getDouble(skin, "wl[0].w[0]"), 0.25);
    EXPECT_DOUBLE_EQ(g.getDouble(skin, "wl[0].w[3]"), 0.75);
    EXPECT_DOUBLE_EQ(g.getDouble(skin, "wl[1].w[1]"), 1.0);
    EXPECT_EQ(g.value(skin, "wl[0].w[1]"), nullptr);
    expectValues(numbersOf(g, "u", "e[4].v"), {1, 2});
    expectValues(numbersOf(g, "u", "e[5].v"), {3, 4});
    // Values that fit neither reading: the statement is skipped with a warning.
    Graph bad = read("createNode unknownThing -n \"u\";\n\tsetAttr \".e[0:1].v\" 1 2 3;\n");
    ASSERT_EQ(bad.warnings().size(), 1u);
    EXPECT_NE(bad.warnings()[0].message.find("fit neither"), std::string::npos) << bad.warnings()[0].message;
}

}  // namespace
}  // namespace pushpin::scene
