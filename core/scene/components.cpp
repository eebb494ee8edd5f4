// core/scene/components.cpp: parsing of Maya component strings.
#include "core/scene/components.h"

#include <algorithm>
#include <cctype>

namespace pushpin::scene {

namespace {

constexpr int64_t kMaxIndex = (int64_t(1) << 31) - 1;

bool fail(std::string* error, std::string message) {
    if (error) *error = std::move(message);
    return false;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

bool parseIndex(std::string_view s, int64_t& out) {
    s = trim(s);
    if (s.empty() || s.size() > 10) return false;
    int64_t v = 0;
    for (char c : s) {
        if (c < '0' || c > '9') return false;
        v = v * 10 + (c - '0');
    }
    if (v > kMaxIndex) return false;
    out = v;
    return true;
}

bool parseRange(std::string_view s, IndexRange& out) {
    s = trim(s);
    if (s == "*") {
        out = {0, kAllIndices};
        return true;
    }
    const size_t colon = s.find(':');
    if (colon == std::string_view::npos) {
        int64_t v = 0;
        if (!parseIndex(s, v)) return false;
        out = {v, v};
        return true;
    }
    int64_t a = 0, b = 0;
    if (!parseIndex(s.substr(0, colon), a) || !parseIndex(s.substr(colon + 1), b) || a > b) return false;
    out = {a, b};
    return true;
}

ComponentKind kindOf(std::string_view name) {
    if (name == "f") return ComponentKind::Face;
    if (name == "vtx") return ComponentKind::Vertex;
    if (name == "e") return ComponentKind::Edge;
    if (name == "map") return ComponentKind::Uv;
    if (name == "vtxFace") return ComponentKind::VertexFace;
    return ComponentKind::Other;
}

}  // namespace

std::optional<ComponentRange> parseComponent(std::string_view textIn, std::string* error) {
    std::string_view text = trim(textIn);
    const std::string quoted = "'" + std::string(textIn.substr(0, 80)) + "'";
    // An object prefix ends at the last '.' before the first '['.
    const size_t bracket = text.find('[');
    if (bracket == std::string_view::npos) {
        fail(error, "component " + quoted + " has no index");
        return std::nullopt;
    }
    const size_t dot = text.substr(0, bracket).rfind('.');
    if (dot != std::string_view::npos) text.remove_prefix(dot + 1);
    ComponentRange out;
    const size_t open = text.find('[');
    out.name = std::string(text.substr(0, open));
    if (out.name.empty() ||
        !std::all_of(out.name.begin(), out.name.end(), [](char c) { return std::isalpha(static_cast<unsigned char>(c)); })) {
        fail(error, "component " + quoted + " has no valid name");
        return std::nullopt;
    }
    out.kind = kindOf(out.name);
    std::string_view rest = text.substr(open);
    int groups = 0;
    while (!rest.empty()) {
        if (rest.front() != '[') {
            fail(error, "component " + quoted + " has text after its indices");
            return std::nullopt;
        }
        const size_t close = rest.find(']');
        if (close == std::string_view::npos) {
            fail(error, "component " + quoted + " has an unclosed '['");
            return std::nullopt;
        }
        IndexRange r;
        if (!parseRange(rest.substr(1, close - 1), r)) {
            fail(error, "component " + quoted + " has a bad index range");
            return std::nullopt;
        }
        if (groups == 0) out.range = r;
        else if (groups == 1) out.second = r;
        else {
            fail(error, "component " + quoted + " has more than two indices");
            return std::nullopt;
        }
        ++groups;
        rest.remove_prefix(close + 1);
    }
    if (out.kind == ComponentKind::VertexFace && !out.second) {
        fail(error, "component " + quoted + " needs a vertex and a face index");
        return std::nullopt;
    }
    return out;
}

ParsedComponents parseComponents(const ComponentList& list) {
    ParsedComponents out;
    for (const std::string& item : list.items) {
        std::string error;
        if (std::optional<ComponentRange> r = parseComponent(item, &error)) out.ranges.push_back(std::move(*r));
        else out.errors.push_back(std::move(error));
    }
    return out;
}

std::vector<bool> componentMask(const std::vector<ComponentRange>& ranges, ComponentKind kind, size_t count,
                                std::string* error) {
    std::vector<bool> mask(count, false);
    std::string problems;
    for (const ComponentRange& r : ranges) {
        if (r.kind != kind) continue;
        const int64_t first = r.range.first;
        int64_t last = r.range.all() ? int64_t(count) - 1 : r.range.last;
        if (!r.range.all() && last >= int64_t(count)) {
            if (!problems.empty()) problems += "; ";
            problems += r.name + "[" + std::to_string(r.range.first) + ":" + std::to_string(r.range.last) +
                        "] reaches past the " + std::to_string(count) + " elements";
            last = int64_t(count) - 1;
        }
        for (int64_t i = first; i <= last; ++i) mask[size_t(i)] = true;
    }
    if (error) *error = std::move(problems);
    return mask;
}

std::vector<bool> faceMask(const ComponentList& list, size_t faceCount, std::string* error) {
    ParsedComponents parsed = parseComponents(list);
    std::vector<std::string> problems = std::move(parsed.errors);
    for (const ComponentRange& r : parsed.ranges)
        if (r.kind != ComponentKind::Face) problems.push_back("component " + r.name + "[…] is not a face");
    std::string clipError;
    std::vector<bool> mask = componentMask(parsed.ranges, ComponentKind::Face, faceCount, &clipError);
    if (!clipError.empty()) problems.push_back(std::move(clipError));
    if (error) {
        error->clear();
        for (const std::string& p : problems) {
            if (!error->empty()) *error += "; ";
            *error += p;
        }
    }
    return mask;
}

}  // namespace pushpin::scene
