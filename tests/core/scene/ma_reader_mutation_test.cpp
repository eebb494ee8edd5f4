// Deterministic mutation testing of the .ma reader: damaged versions of real scenes (or of built-in
// snippets when the corpus is absent) must either load or throw pushpin::Error — never crash, hang
// or throw anything else. The same seed gives the same mutants on every run.
#include "core/scene/ma_reader.h"

#include "tests/support/ma_corpus.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

namespace pushpin::scene {
namespace {

namespace fs = std::filesystem;

constexpr int kMutantsPerInput = 300;
constexpr uint32_t kSeed = 0x5eed1234;

const char* const kSnippets[] = {
    R"(//Maya ASCII 2018 scene
requires maya "2018";
requires -nodeType "aiOptions" "mtoa" "3.0";
currentUnit -l centimeter -a degree -t film;
fileInfo "application" "maya";
createNode transform -s -n "persp";
	setAttr ".t" -type "double3" 28 21 28 ;
	setAttr ".r" -type "double3" -27.9 45 0 ;
createNode camera -s -n "perspShape" -p "persp";
	setAttr -k off ".v" no;
	setAttr ".fl" 34.999999999999993;
createNode transform -n "pCube1";
createNode mesh -n "pCubeShape1" -p "pCube1";
	setAttr ".uvst[0].uvsn" -type "string" "map1";
	setAttr -s 14 ".uvst[0].uvsp[0:13]" -type "float2" 0.375 0 0.625 0 0.375 0.25
		 0.625 0.25 0.375 0.5 0.625 0.5 0.375 0.75 0.625 0.75 0.375 1 0.625 1
		 0.875 0 0.875 0.25 0.125 0 0.125 0.25;
	setAttr -s 8 ".vt[0:7]"  -0.5 -0.5 0.5 0.5 -0.5 0.5 -0.5 0.5 0.5 0.5 0.5 0.5
		 -0.5 0.5 -0.5 0.5 0.5 -0.5 -0.5 -0.5 -0.5 0.5 -0.5 -0.5;
	setAttr -s 12 ".ed[0:11]"  0 1 0 2 3 0 4 5 0 6 7 0 0 2 0 1 3 0
		 2 4 0 3 5 0 4 6 0 5 7 0 6 0 0 7 1 0;
	setAttr -s 6 -ch 24 ".fc[0:5]" -type "polyFaces"
		f 4 0 5 -2 -5      mu 0 4 0 1 3 2
		f 4 1 7 -3 -7      mu 0 4 2 3 5 4
		f 4 2 9 -4 -9      mu 0 4 4 5 7 6
		f 4 3 11 -1 -11    mu 0 4 6 7 9 8
		f 4 -12 -10 -8 -6  mu 0 4 1 10 11 3
		f 4 10 4 6 8       mu 0 4 12 0 2 13;
	setAttr ".cd" -type "dataPolyComponent" Index_Data Edge 0 ;
createNode transform -n "pCube2";
parent -s -nc -r -add "|pCube1|pCubeShape1" "pCube2";
createNode lambert -n "lambert2";
	setAttr ".c" -type "float3" 1 0 0 ;
createNode shadingEngine -n "lambert2SG";
	setAttr ".ihi" 0;
	setAttr ".ro" yes;
createNode script -n "sceneConfigurationScriptNode";
	setAttr ".b" -type "string" ("playbackOptions -min 1 -max 24 -ast 1 -aet 48 "
		+ "; // \"quoted\"\n");
	setAttr ".st" 6;
select -ne :time1;
	setAttr ".o" 1;
select -ne :defaultRenderGlobals;
	setAttr ".an" yes;
connectAttr "lambert2.oc" "lambert2SG.ss";
connectAttr "pCubeShape1.iog" "lambert2SG.dsm" -na;
relationship "link" ":lightLinker1" "lambert2SG.message" ":defaultLightSet.message";
// End of snippet.ma
)",
    R"(currentUnit -l m -a rad;
createNode nurbsSurface -n "s";
	setAttr ".cc" -type "nurbsSurface"
		3 3 0 2 no
		6 0 0 0 1 1 1
		7 -2 -1 0 1 2 3 4
		NOTRIM
		20
		0 0 0 0 0 1 0 0 2 0 0 3 0 0 4
		1 0 0 1 0 1 1 0 2 1 0 3 1 0 4
		2 0 0 2 0 1 2 0 2 2 0 3 2 0 4
		3 0 0 3 0 1 3 0 2 3 0 3 3 0 4;
createNode nurbsCurve -n "c";
	setAttr ".cc" -type "nurbsCurve" 3 2 0 no 3 7 0 0 0 1 2 2 2 5 0 0 0 1 1 0 2 0 0 3 1 0 4 0 0;
createNode transform -n "t";
	addAttr -ci true -sn "bl" -ln "blurLength" -min 0 -max 10 -at "double";
	addAttr -ci true -uac -sn "tint" -ln "tintColor" -at "float3" -nc 3;
	addAttr -ci true -sn "tintR" -ln "tintColorR" -at "float" -p "tintColor";
	addAttr -ci true -sn "tintG" -ln "tintColorG" -at "float" -p "tintColor";
	addAttr -ci true -sn "tintB" -ln "tintColorB" -at "float" -p "tintColor";
	setAttr ".bl" 3;
	setAttr ".tint" -type "float3" 1 0.5 0;
	setAttr ".sa" -type "stringArray" 2 "a" "b";
	setAttr ".ia" -type "Int32Array" 3 1 2 3;
	setAttr ".m" -type "matrix" 1 0 0 0 0 1 0 0 0 0 1 0 5m 0 0 1;
	setAttr ".aal" -type "attributeAlias" {"a","b"} ;
	setAttr ".cl" -type "componentList" 1 "f[0:5]";
lockNode -l 1;
)",
};

enum class Mutation { Truncate, FlipBytes, DeleteLine, DuplicateLine, SwapTokens, InsertJunk, HugeNumber, Count };

struct Mutator {
    explicit Mutator(const std::string& text) : original(text) {
        lines.push_back(0);
        for (size_t i = 0; i < text.size(); ++i)
            if (text[i] == '\n') lines.push_back(i + 1);
        size_t i = 0;
        while (i < text.size()) {
            while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
            size_t start = i;
            while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
            if (i > start) tokens.emplace_back(start, i - start);
        }
    }

    std::string mutate(std::mt19937& rng, Mutation kind) const {
        std::string t = original;
        auto pick = [&](size_t n) { return n == 0 ? size_t(0) : size_t(rng() % n); };
        switch (kind) {
            case Mutation::Truncate: t.resize(pick(t.size() + 1)); break;
            case Mutation::FlipBytes: {
                const size_t n = 1 + pick(8);
                for (size_t k = 0; k < n && !t.empty(); ++k) t[pick(t.size())] = char(rng() & 0xff);
                break;
            }
            case Mutation::DeleteLine:
            case Mutation::DuplicateLine: {
                const size_t l = pick(lines.size());
                const size_t begin = lines[l];
                const size_t end = l + 1 < lines.size() ? lines[l + 1] : t.size();
                if (kind == Mutation::DeleteLine) t.erase(begin, end - begin);
                else t.insert(begin, t.substr(begin, end - begin));
                break;
            }
            case Mutation::SwapTokens: {
                if (tokens.size() < 2) break;
                auto a = tokens[pick(tokens.size())], b = tokens[pick(tokens.size())];
                if (a.first > b.first) std::swap(a, b);
                if (a.first + a.second > b.first) break;
                const std::string ta = t.substr(a.first, a.second), tb = t.substr(b.first, b.second);
                t.replace(b.first, b.second, ta);
                t.replace(a.first, a.second, tb);
                break;
            }
            case Mutation::InsertJunk: {
                static const char* const junk[] = {";", "\"", "(", ")", "{", "}", "[", "]", ":", ".", "+", "-type",
                                                   "\"polyFaces\"", "f", "mu", "h", "-s", "-p", "\\", "/*", "//",
                                                   "\"nurbsSurface\"", "TRIM", "yes", "createNode", "setAttr",
                                                   "\".vt[0:7]\"", "\x01", "\x7f"};
                std::string piece;
                if (rng() % 4 == 0) {
                    for (size_t k = 0, n = 1 + pick(16); k < n; ++k) piece.push_back(char(rng() & 0xff));
                } else {
                    piece = std::string(" ") + junk[pick(std::size(junk))] + " ";
                }
                t.insert(pick(t.size() + 1), piece);
                break;
            }
            case Mutation::HugeNumber: {
                static const char* const huge[] = {"999999999999", "1e999", "-1e999", "2147483648", "-2147483649",
                                                   "4294967295", "nan", "inf", "1e-999", "0x7fffffff",
                                                   "18446744073709551616", "-0"};
                if (tokens.empty()) break;
                // Prefer a numeric token so that counts and indices get replaced.
                for (int attempt = 0; attempt < 16; ++attempt) {
                    const auto tok = tokens[pick(tokens.size())];
                    const char c = t[tok.first];
                    if ((c >= '0' && c <= '9') || c == '-' || attempt == 15) {
                        t.replace(tok.first, tok.second, huge[pick(std::size(huge))]);
                        break;
                    }
                }
                break;
            }
            case Mutation::Count: break;
        }
        return t;
    }

    const std::string& original;
    std::vector<size_t> lines;                      // offsets of line starts
    std::vector<std::pair<size_t, size_t>> tokens;  // (offset, length) of whitespace-separated tokens
};

struct Outcome {
    int loaded = 0;
    int rejected = 0;
};

// Reads every mutant of `text`; any exception other than pushpin::Error fails the test.
Outcome mutateAndRead(const std::string& text, const std::string& name, uint32_t seed) {
    Mutator mutator(text);
    std::mt19937 rng(seed);
    Outcome outcome;
    for (int i = 0; i < kMutantsPerInput; ++i) {
        const auto kind = Mutation(rng() % uint32_t(Mutation::Count));
        const std::string mutant = mutator.mutate(rng, kind);
        try {
            ReadOptions options;
            options.loadReferences = false;  // mutants never touch the file system
            MaReader::readString(mutant, name, options);
            ++outcome.loaded;
        } catch (const Error&) {
            ++outcome.rejected;
        } catch (const std::exception& e) {
            ADD_FAILURE() << name << " mutant " << i << " (kind " << int(kind) << "): unexpected " << typeid(e).name()
                          << ": " << e.what();
        } catch (...) {
            ADD_FAILURE() << name << " mutant " << i << " (kind " << int(kind) << "): unexpected non-std exception";
        }
    }
    return outcome;
}

std::vector<std::pair<std::string, std::string>> inputs() {
    std::vector<std::pair<std::string, std::string>> out;
    for (const fs::path& p : test::maCorpusFiles()) {  // sorted: seeds per file stay stable
        std::ifstream in(p, std::ios::binary);
        std::ostringstream ss;
        ss << in.rdbuf();
        out.emplace_back(p.filename().string(), ss.str());
    }
    if (out.empty()) {
        int k = 0;
        for (const char* s : kSnippets) out.emplace_back("snippet" + std::to_string(k++) + ".ma", s);
    }
    return out;
}

TEST(MaReaderMutation, MutantsLoadOrThrowPushpinError) {
    const auto all = inputs();
    if (!fs::is_directory(PUSHPIN_MA_CORPUS))
        std::cout << "corpus " << PUSHPIN_MA_CORPUS << " is absent; mutating built-in snippets\n";
    Outcome total;
    uint32_t seed = kSeed;
    for (const auto& [name, text] : all) {
        // The unmutated input must load, so that mutants test damage rather than a broken original.
        ASSERT_NO_THROW(MaReader::readString(text, name)) << name;
        const Outcome o = mutateAndRead(text, name, seed++);
        total.loaded += o.loaded;
        total.rejected += o.rejected;
    }
    // Both outcomes must occur: mutations that the reader tolerates (e.g. a duplicated setAttr)
    // and ones it rejects (truncation mid-string).
    EXPECT_GT(total.loaded, 0);
    EXPECT_GT(total.rejected, 0);
    std::cout << all.size() << " inputs, " << total.loaded << " mutants loaded, " << total.rejected << " rejected\n";
}

TEST(MaReaderMutation, SnippetsSurviveMutationToo) {
    Outcome total;
    uint32_t seed = kSeed ^ 0x9e3779b9u;
    int k = 0;
    for (const char* s : kSnippets) {
        const std::string name = "snippet" + std::to_string(k++) + ".ma";
        ASSERT_NO_THROW(MaReader::readString(s, name)) << name;
        const Outcome o = mutateAndRead(s, name, seed++);
        total.loaded += o.loaded;
        total.rejected += o.rejected;
    }
    EXPECT_GT(total.loaded, 0);
    EXPECT_GT(total.rejected, 0);
}

}  // namespace
}  // namespace pushpin::scene
