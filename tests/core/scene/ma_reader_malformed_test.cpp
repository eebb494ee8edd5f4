// Malformed .ma input. Text that is not Maya ASCII throws scene::ParseError naming the file, line,
// column and node, with a message that says what is wrong; a statement that fails is skipped with
// a warning that says the same, and the load goes on.
#include "core/scene/ma_reader.h"

#include <gtest/gtest.h>

#include <optional>
#include <sstream>
#include <string>

namespace pushpin::scene {
namespace {

struct BadInput {
    const char* name;
    std::string text;
    uint32_t line;
    uint32_t column;
    const char* message;  // substring of the error message
    const char* node;     // expected ParseError::node()
};

std::ostream& operator<<(std::ostream& os, const BadInput& b) { return os << b.name; }

std::optional<ParseError> parseError(const std::string& text) {
    try {
        MaReader::readString(text, "bad.ma");
    } catch (const ParseError& e) {
        return e;
    }
    return std::nullopt;
}

const std::string kTransform = "createNode transform -n \"a\";\n";
const std::string kMesh = "createNode mesh -n \"m\";\n";

class MaReaderMalformed : public testing::TestWithParam<BadInput> {};

TEST_P(MaReaderMalformed, ThrowsParseErrorWithPosition) {
    const BadInput& bad = GetParam();
    std::optional<ParseError> e = parseError(bad.text);
    ASSERT_TRUE(e.has_value()) << "no ParseError for " << bad.name;
    EXPECT_EQ(e->file(), "bad.ma");
    EXPECT_EQ(e->line(), bad.line) << e->what();
    EXPECT_EQ(e->column(), bad.column) << e->what();
    EXPECT_NE(std::string(e->what()).find(bad.message), std::string::npos) << e->what();
    EXPECT_EQ(e->node(), bad.node) << e->what();
    const std::string prefix = "bad.ma:" + std::to_string(bad.line) + ":" + std::to_string(bad.column) + ": ";
    EXPECT_EQ(std::string(e->what()).rfind(prefix, 0), 0u) << e->what();
}

// Columns count bytes from 1; a tab is one column.
// Text that is not Maya ASCII: the load stops with an error at the place.
const BadInput kBadInputs[] = {
    {"TruncatedInsideString", kTransform + "\tsetAttr \".t\" -type \"string\" \"abc", 2, 30,
     "unterminated string (end of file", "a"},
    {"StringBrokenByNewline", kTransform + "\tsetAttr \".n\" -type \"string\" \"abc\n\tdef\";\n", 2, 30,
     "unterminated string (end of line", "a"},
    {"NulBytes", kTransform + std::string("\0\0junk", 6), 2, 1, "invalid character 0x00", "a"},
    {"ControlCharacterInString", kTransform + "\tsetAttr \".n\" -type \"string\" \"a\x01z\";\n", 2, 32,
     "invalid character 0x01", "a"},
    {"MissingSemicolonAtEnd", kTransform + "\tsetAttr \".tx\" 1", 2, 17, "has no ';'", "a"},
    {"NumberWhereCommandExpected", kTransform + "0.5 0.5 0.5;\n", 2, 1, "expected a command, found '0.5'", "a"},
    {"UnclosedParenthesis", kTransform + "\tsetAttr \".n\" -type \"string\" (\"a\" + \"b\";\n", 2, 40, "expected ')'",
     "a"},
    {"PlusWithoutString", kTransform + "\tsetAttr \".n\" -type \"string\" \"a\" + 5;\n", 2, 36,
     "expected a string after '+'", "a"},
};

INSTANTIATE_TEST_SUITE_P(Inputs, MaReaderMalformed, testing::ValuesIn(kBadInputs),
                         [](const testing::TestParamInfo<BadInput>& p) { return std::string(p.param.name); });

// Statements Maya would refuse one by one while it goes on loading: each is skipped with a
// warning at its place naming the node, and the statements after it still load.
class MaReaderTolerated : public testing::TestWithParam<BadInput> {};

TEST_P(MaReaderTolerated, SkipsTheStatementWithAWarningAndGoesOn) {
    const BadInput& bad = GetParam();
    Graph g;
    ASSERT_NO_THROW(g = MaReader::readString(bad.text + "createNode transform -n \"after\";\n", "bad.ma")) << bad.name;
    EXPECT_NE(g.find("after"), kNoNode);
    const Diagnostic* found = nullptr;
    for (const Diagnostic& d : g.warnings())
        if (d.message.find(bad.message) != std::string::npos) found = &d;
    ASSERT_NE(found, nullptr) << "no warning with \"" << bad.message << "\"; first: "
                              << (g.warnings().empty() ? std::string("none") : g.warnings()[0].message);
    EXPECT_EQ(found->file, "bad.ma");
    EXPECT_EQ(found->line, bad.line) << found->message;
    EXPECT_EQ(found->column, bad.column) << found->message;
    EXPECT_EQ(found->node, bad.node) << found->message;
}

const BadInput kToleratedInputs[] = {
    {"UnknownDataType", kTransform + "\tsetAttr \".x\" -type \"bogus\" 1;\n", 2, 10, "data type \"bogus\" is not modelled", "a"},
    {"TupleTooShort", kTransform + "\tsetAttr \".t\" -type \"double3\" 1 2;\n", 2, 31, "double3 needs 3 values, found 2",
     "a"},
    {"RangeTooFewNumbers", kMesh + "\tsetAttr -s 8 \".vt[0:7]\" 0 0 0 1 1 1;\n", 2, 26,
     "range of 8 × 3 needs 24 values, found 6", "m"},
    {"RangeNotDivisible", "createNode unknownThing -n \"u\";\n\tsetAttr \".q[0:3]\" 1 2 3 4 5;\n", 2, 20,
     "5 values do not divide into the range's 4 elements", "u"},
    {"NonNumericValue", kTransform + "\tsetAttr \".tx\" abc;\n", 2, 16, "expected a number, found 'abc'", "a"},
    {"NaNValue", kTransform + "\tsetAttr \".tx\" nan;\n", 2, 16, "'nan' is not finite", "a"},
    {"InfValue", kTransform + "\tsetAttr \".t\" -type \"double3\" 0 -inf 0;\n", 2, 33, "'-inf' is not finite", "a"},
    {"HugeValue", kTransform + "\tsetAttr \".tx\" 1e999;\n", 2, 16, "'1e999' is out of range", "a"},
    {"MissingParent", "createNode mesh -n \"s\" -p \"ghost\";\n", 1, 27, "no node named 'ghost'", "ghost"},
    {"ConnectMissingNode", kTransform + "connectAttr \"a.t\" \"ghost.t\";\n", 2, 19, "no node named 'ghost'", "ghost"},
    {"SetAttrMissingNode", kTransform + "setAttr \"ghost.tx\" 1;\n", 2, 9, "no node named 'ghost'", "ghost"},
    {"CreateNodeWithoutType", "createNode -n \"a\";\n", 1, 18, "no node type given", ""},
    {"ReversedRange", kMesh + "\tsetAttr \".vt[3:1]\" 0 0 0;\n", 2, 10, "malformed plug \".vt[3:1]\"", "m"},
    {"UnclosedBracket", kTransform + "\tsetAttr \".a[\" 1;\n", 2, 10, "malformed plug \".a[\"", "a"},
    {"IndexBeyondRange", kMesh + "\tsetAttr \".vt[0:3000000000]\" 0 0 0;\n", 2, 10, "index out of range", "m"},
    {"PolyFacesUnknownKeyword", kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\"\n\t\tf 3 0 1 2\n\t\tzz 3 0 1 2;\n", 4,
     3, "unknown keyword 'zz'", "m"},
    {"PolyFacesFaceCount", kMesh + "\tsetAttr \".fc[0:1]\" -type \"polyFaces\" f 3 0 1 2 ;\n", 2, 49,
     "the range holds 2 faces but 1 are given", "m"},
    {"PolyFacesUvCount", kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" f 3 0 1 2 mu 0 4 0 1 2 3;\n", 2, 47,
     "'mu' has 4 values for a loop of 3 edges", "m"},
    {"PolyFacesHoleFirst", kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" h 3 0 1 2;\n", 2, 37,
     "hole 'h' before any face", "m"},
    {"PolyFacesTruncatedFace", kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" f 4 0 1;\n", 2, 44,
     "expected 4 values, found 2", "m"},
    {"PolyFacesUvBeforeFace", kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" mu 0 3 0 1 2 f 3 0 1 2;\n", 2, 37,
     "'mu' before the loop it belongs to", "m"},
    {"PolyFacesOuterUvBeforeFace", kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" mf 3 0 1 2;\n", 2, 37,
     "'mf' before the loop it belongs to", "m"},
    {"PolyFacesHoleUvWithoutHole", kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" f 3 0 1 2 mh 3 0 1 2;\n", 2, 47,
     "'mh' before the loop it belongs to", "m"},
    {"PolyFacesOuterUvCount",
     kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" f 3 0 1 2 h 4 3 4 5 6 mf 4 0 1 2 3;\n", 2, 59,
     "'mf' has 4 values for a loop of 3 edges", "m"},
    {"PolyFacesHoleUvCount",
     kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" f 3 0 1 2 h 4 3 4 5 6 mf 3 0 1 2 mh 3 0 1 2;\n", 2, 70,
     "'mh' has 3 values for a loop of 4 edges", "m"},
    {"PolyFacesSecondColours",
     kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" f 3 0 1 2 fc 3 0 1 2 mu 0 3 1 2 3 fc 3 2 2 2;\n", 2, 71,
     "second 'fc' for the same loop", "m"},
    {"PolyFacesSecondHoleColours",
     kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" f 3 0 1 2 fc 3 0 1 2 h 3 3 4 5 mf 3 0 1 2 fc 3 1 1 1 fc 3 2 2 2;\n",
     2, 90, "second 'fc' for the same loop", "m"},
    {"PolyFacesTruncatedUvs", kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" f 3 0 1 2 mu 0 3 0 1;\n", 2, 57,
     "uv ids: expected 3 values, found 2", "m"},
    {"PolyFacesStringRecord", kMesh + "\tsetAttr \".fc[0]\" -type \"polyFaces\" f 3 0 1 2 \"x\";\n", 2, 47,
     "expected f, h, mu, mf, mh or fc, found string \"x\"", "m"},
    {"NurbsSurfaceKnotsVersusCvs",
     "createNode nurbsSurface -n \"s\";\n\tsetAttr \".cc\" -type \"nurbsSurface\"\n\t\t3 3 0 0 no\n\t\t6 0 0 0 1 1 1\n"
     "\t\t6 0 0 0 1 1 1\n\n\t\t15\n\t\t0 0 0;\n",
     3, 3, "need 4 × 4 CVs, the data has 15", "s"},
    {"NurbsCurveKnotsVersusCvs",
     "createNode nurbsCurve -n \"c\";\n\tsetAttr \".cc\" -type \"nurbsCurve\" 3 1 0 no 3 6 0 0 0 1 1 1 5 0 0 0;\n", 2, 35,
     "6 knots do not fit 5 CVs of degree 3", "c"},
    {"HugeArrayCount", "createNode unknownThing -n \"u\";\n\tsetAttr \".ia\" -type \"Int32Array\" 999999999999 1 2;\n",
     2, 35, "999999999999 is outside [0, 2147483647]", "u"},
    {"ArrayCountBeyondData", "createNode unknownThing -n \"u\";\n\tsetAttr \".ia\" -type \"Int32Array\" 100000 1 2;\n",
     2, 35, "Int32Array needs 100000 values, found 2", "u"},
    {"HugeSizeHint", kMesh + "\tsetAttr -s 999999999999 \".vt\";\n", 2, 13, "999999999999 is outside", "m"},
    {"SetAttrWithoutNode", "setAttr \".tx\" 1;\n", 1, 9, "no node is selected", ""},
    {"ParentCycle", kTransform + "createNode transform -n \"b\" -p \"a\";\nparent \"a\" \"b\";\n", 3, 8,
     "would make a cycle", "a"},
    {"UnknownAttributeType", kTransform + "\taddAttr -ln \"x\" -at \"quaternion\";\n", 2, 22,
     "unknown attribute type", "a"},
    {"StringWhereNumberExpected", kTransform + "\tsetAttr \".t\" -type \"double3\" 1 \"2\" 3;\n", 2, 33,
     "expected a number, found string \"2\"", "a"},
    {"UnknownLinearUnit", "currentUnit -l furlong;\n", 1, 16, "unknown linear unit 'furlong'", ""},
    {"UnitSuffixNotAUnit", kTransform + "\tsetAttr \".tx\" 5parsec;\n", 2, 16, "expected a number, found '5parsec'", "a"},
};

INSTANTIATE_TEST_SUITE_P(Inputs, MaReaderTolerated, testing::ValuesIn(kToleratedInputs),
                         [](const testing::TestParamInfo<BadInput>& p) { return std::string(p.param.name); });

TEST(MaReaderMalformedStream, ErrorsCarryTheFileNameOfAFile) {
    std::istringstream in("createNode transform -n \"a\";\n\tsetAttr \".n\" -type \"string\" \"oops\n");
    try {
        MaReader::readStream(in, "/scenes/shot.ma");
        FAIL() << "no error";
    } catch (const ParseError& e) {
        EXPECT_EQ(e.file(), "/scenes/shot.ma");
        EXPECT_EQ(e.line(), 2u);
        EXPECT_EQ(e.column(), 30u);
        EXPECT_EQ(e.node(), "a");
        EXPECT_EQ(std::string(e.what()).rfind("/scenes/shot.ma:2:30: unterminated string", 0), 0u) << e.what();
    }
}

TEST(MaReaderMalformedStream, WarningsCarryTheFileNameOfAFile) {
    std::istringstream in("createNode transform -n \"a\";\n\tsetAttr \".tx\" oops;\n");
    const Graph g = MaReader::readStream(in, "/scenes/shot.ma");
    ASSERT_EQ(g.warnings().size(), 1u);
    const Diagnostic& d = g.warnings()[0];
    EXPECT_EQ(d.file, "/scenes/shot.ma");
    EXPECT_EQ(d.line, 2u);
    EXPECT_EQ(d.column, 16u);
    EXPECT_EQ(d.node, "a");
    EXPECT_EQ(d.message, "setAttr: expected a number, found 'oops'; the statement is skipped");
}

TEST(MaReaderMalformedStream, ParseErrorIsAPushpinError) {
    EXPECT_THROW(MaReader::readString("createNode transform"), Error);
}

// Statements that fail are reported one by one up to a bound, then counted: a file of a million
// bad lines loads with a bounded list of warnings.
TEST(MaReaderMalformedStream, FailedStatementsAreCountedPastTheirBound) {
    std::string text = "createNode transform -n \"a\";\n";
    for (int i = 0; i < 5000; ++i) text += "\tsetAttr \".tx\" oops;\n";
    text += "\tsetAttr \".ty\" 2;\n";
    const Graph g = MaReader::readString(text, "many.ma");
    ASSERT_LE(g.warnings().size(), 201u);
    EXPECT_NE(g.warnings().back().message.find("4800 more statements failed"), std::string::npos)
        << g.warnings().back().message;
    EXPECT_DOUBLE_EQ(g.getDouble(g.find("a"), "translateY"), 2.0);
}

// A createNode that fails takes the statements that edit its node with it, without a warning each.
TEST(MaReaderMalformedStream, StatementsOfANodeThatWasNotMadeGoWithIt) {
    const Graph g = MaReader::readString(
        "createNode mesh -n \"s\" -p \"ghost\";\n\tsetAttr \".v\" no;\n\tsetAttr \".tx\" 1;\n"
        "createNode transform -n \"b\";\n\tsetAttr \".tx\" 3;\n",
        "ghost.ma");
    ASSERT_EQ(g.warnings().size(), 1u);
    EXPECT_NE(g.warnings()[0].message.find("no node named 'ghost'"), std::string::npos);
    EXPECT_EQ(g.find("s"), kNoNode);
    ASSERT_NE(g.find("b"), kNoNode);
    EXPECT_DOUBLE_EQ(g.getDouble(g.find("b"), "translateX"), 3.0);
}

}  // namespace
}  // namespace pushpin::scene
