#include "core/scene/graph.h"

#include "cache/error.h"
#include "core/util/format.h"

#include <algorithm>
#include <charconv>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <type_traits>
#include <unordered_set>

namespace pushpin::scene {

// ------------------------------------------------------------------ plug paths

namespace {

bool isNameStart(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool isNameChar(char c) { return isNameStart(c) || (c >= '0' && c <= '9'); }

bool parseIndex(std::string_view s, int64_t& out) {
    if (s.empty()) return false;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && ptr == s.data() + s.size() && out >= 0;
}

bool isNumericCompound(AttrType t) {
    switch (t) {
        case AttrType::Double2: case AttrType::Double3: case AttrType::Double4:
        case AttrType::Float2: case AttrType::Float3: case AttrType::Long2: case AttrType::Long3:
        case AttrType::Short2: case AttrType::Short3: return true;
        default: return false;
    }
}

// The schema default of `spec` into `out`, reusing its storage.
void assignDefaults(const AttrSpec& spec, std::vector<double>& out) {
    const int n = componentCount(spec.type);
    out.assign(spec.defaults.begin(), spec.defaults.begin() + std::clamp(n, 0, 4));
}

// The plain value stored in `a`, else the schema default of `spec`; false when there is neither.
bool storedOrDefault(const AttrData* a, const AttrSpec* spec, std::vector<double>& out) {
    if (a && a->hasValue)
        if (auto* nums = std::get_if<Numbers>(&a->value)) {
            out = nums->values;
            return true;
        }
    if (spec && componentCount(spec->type) > 0) {
        assignDefaults(*spec, out);
        return true;
    }
    return false;
}

// The canonical key of a plain attribute name: its long name where the node knows it.
std::string_view plainKey(const AttrSpec* spec, std::string_view name) {
    return spec ? std::string_view(spec->longName) : name;
}

std::vector<double> defaultNumbers(const AttrSpec& spec) {
    std::vector<double> out;
    assignDefaults(spec, out);
    return out;
}

}  // namespace

std::optional<std::vector<PlugSegment>> parsePlugPath(std::string_view text) {
    std::vector<PlugSegment> out;
    size_t i = 0;
    if (i < text.size() && text[i] == '.') ++i;
    if (i >= text.size()) return std::nullopt;
    while (i < text.size()) {
        PlugSegment seg;
        size_t start = i;
        if (!isNameStart(text[i])) return std::nullopt;
        while (i < text.size() && isNameChar(text[i])) ++i;
        seg.name.assign(text.substr(start, i - start));
        if (i < text.size() && text[i] == '[') {
            size_t close = text.find(']', i);
            if (close == std::string_view::npos) return std::nullopt;
            std::string_view inside = text.substr(i + 1, close - i - 1);
            size_t colon = inside.find(':');
            if (colon == std::string_view::npos) {
                if (!parseIndex(inside, seg.first)) return std::nullopt;
                seg.last = seg.first;
            } else {
                if (!parseIndex(inside.substr(0, colon), seg.first) ||
                    !parseIndex(inside.substr(colon + 1), seg.last) || seg.last < seg.first)
                    return std::nullopt;
            }
            if (seg.first > 0xFFFFFFF0LL || seg.last > 0xFFFFFFF0LL) return std::nullopt;
            i = close + 1;
        }
        out.push_back(std::move(seg));
        if (i == text.size()) break;
        if (text[i] != '.') return std::nullopt;
        ++i;
        if (i == text.size()) return std::nullopt;
    }
    return out;
}

bool isPlainPlugName(std::string_view s) {
    if (s.empty() || !isNameStart(s.front())) return false;
    for (char c : s)
        if (!isNameChar(c)) return false;
    return true;
}

std::string formatPlugPath(const std::vector<PlugSegment>& segments) {
    std::string s;
    for (size_t k = 0; k < segments.size(); ++k) {
        if (k) s += '.';
        s += segments[k].name;
        if (segments[k].indexed()) {
            s += '[' + std::to_string(segments[k].first);
            if (segments[k].last != segments[k].first) s += ':' + std::to_string(segments[k].last);
            s += ']';
        }
    }
    return s;
}

// ------------------------------------------------------------------ MultiStore

void MultiStore::erase(uint32_t first, uint32_t count) {
    uint64_t end = uint64_t(first) + count;
    auto it = m_runs.upper_bound(first);
    if (it != m_runs.begin()) --it;
    while (it != m_runs.end() && it->first < end) {
        uint64_t runFirst = it->first, runEnd = runFirst + it->second.count;
        if (runEnd <= first) {
            ++it;
            continue;
        }
        Run run = std::move(it->second);
        it = m_runs.erase(it);
        auto* nums = std::get_if<Numbers>(&run.value);
        // Keep the parts of the old run outside [first, end). Only numeric runs can be split;
        // other kinds (polyFaces, strings) are replaced whole.
        if (nums) {
            size_t w = size_t(run.width);
            if (runFirst < first) {
                Run head{uint32_t(first - runFirst), run.width, nums->slice(0, (first - runFirst) * w)};
                m_runs.emplace(uint32_t(runFirst), std::move(head));
            }
            if (runEnd > end) {
                const size_t from = (end - runFirst) * w;
                Run tail{uint32_t(runEnd - end), run.width, nums->slice(from, nums->size() - std::min(from, nums->size()))};
                it = m_runs.emplace(uint32_t(end), std::move(tail)).first;
                ++it;
            }
        }
    }
}

void MultiStore::assign(uint32_t first, uint32_t count, Value value) {
    constexpr uint32_t kMergedChunk = 16;
    if (count == 0) return;
    erase(first, count);
    int width = 1;
    if (auto* nums = std::get_if<Numbers>(&value)) width = std::max<int>(1, int(nums->size() / count));
    // Appending single elements one after another (`.pt[5]`, `.pt[6]` …) grows the previous run
    // instead of creating one map entry per element. Long chunks (`.vt[0:499]`) keep runs of their
    // own: growing one run by them would copy everything before at each growth.
    if (auto* nums = std::get_if<Numbers>(&value); nums && first > 0 && count <= kMergedChunk) {
        auto prev = m_runs.lower_bound(first);
        if (prev != m_runs.begin()) {
            --prev;
            auto* pn = std::get_if<Numbers>(&prev->second.value);
            if (pn && prev->first + prev->second.count == first && prev->second.width == width &&
                pn->kind == nums->kind && pn->append(*nums)) {
                prev->second.count += count;
                return;
            }
        }
    }
    m_runs.emplace(first, Run{count, width, std::move(value)});
}

const MultiStore::Run* MultiStore::find(uint32_t index, uint32_t* offsetInRun) const {
    auto it = m_runs.upper_bound(index);
    if (it == m_runs.begin()) return nullptr;
    --it;
    if (index >= uint64_t(it->first) + it->second.count) return nullptr;
    if (offsetInRun) *offsetInRun = index - it->first;
    return &it->second;
}

bool MultiStore::numbers(uint32_t index, std::vector<double>& out) const {
    uint32_t off = 0;
    const Run* run = find(index, &off);
    if (!run) return false;
    auto* nums = std::get_if<Numbers>(&run->value);
    const size_t width = size_t(run->width);
    if (!nums || size_t(off + 1) * width > nums->size()) return false;
    out.resize(width);
    nums->copyTo(size_t(off) * width, width, out.data());
    return true;
}

std::vector<uint32_t> MultiStore::indices() const {
    std::vector<uint32_t> out;
    for (auto& [first, run] : m_runs)
        for (uint32_t k = 0; k < run.count; ++k) out.push_back(first + k);
    return out;
}

uint32_t MultiStore::endIndex() const {
    if (m_runs.empty()) return 0;
    auto it = std::prev(m_runs.end());
    return it->first + it->second.count;
}

// ------------------------------------------------------------------ Node

namespace {
const NodeLinks kNoLinks;
}  // namespace

const AttrMap::Map& AttrMap::map() const {
    static const Map kEmpty;
    return m_map ? *m_map : kEmpty;
}

Node::Node(const Node& other)
    : id(other.id), line(other.line), nextSameName(other.nextSameName), prevSameName(other.prevSameName),
      schema(other.schema), type(other.type), name(other.name), attrs(other.attrs), underWorld(other.underWorld),
      shared(other.shared), locked(other.locked),
      m_links(other.m_links ? std::make_unique<NodeLinks>(*other.m_links) : nullptr) {}

Node& Node::operator=(const Node& other) {
    if (this != &other) *this = Node(other);
    return *this;
}

const NodeLinks& Node::links() const { return m_links ? *m_links : kNoLinks; }

NodeLinks& Node::mutableLinks() {
    if (!m_links) m_links = std::make_unique<NodeLinks>();
    return *m_links;
}

bool Node::isDag() const {
    if (schema) return schema->isDag();
    return !parents().empty() || !children().empty();
}

const AttrSpec* Node::findAttr(std::string_view attrName) const {
    if (schema)
        if (const AttrSpec* s = schema->find(attrName)) return s;
    if (!m_links) return nullptr;
    for (const AttrSpec& s : m_links->dynamicAttrs)
        if (s.longName == attrName || s.shortName == attrName) return &s;
    return nullptr;
}

// ------------------------------------------------------------------ NodeStore

const Node& NodeStore::outOfRange(size_t i) {
    throw std::out_of_range("node id " + std::to_string(i) + " out of range");
}

// ------------------------------------------------------------------ Graph

Graph::Graph() {
    // Nodes every Maya scene has without creating them; files only `select -ne` them.
    static const std::pair<const char*, const char*> defaults[] = {
        {"time", "time1"},
        {"partition", "renderPartition"},
        {"renderGlobalsList", "renderGlobalsList1"},
        {"defaultShaderList", "defaultShaderList1"},
        {"postProcessList", "postProcessList1"},
        {"defaultRenderUtilityList", "defaultRenderUtilityList1"},
        {"defaultTextureList", "defaultTextureList1"},
        {"lightList", "lightList1"},
        {"shadingEngine", "initialShadingGroup"},
        {"shadingEngine", "initialParticleSE"},
        {"lambert", "lambert1"},
        {"particleCloud", "particleCloud1"},
        {"renderGlobals", "defaultRenderGlobals"},
        {"renderQuality", "defaultRenderQuality"},
        {"resolution", "defaultResolution"},
        {"objectSet", "defaultLightSet"},
        {"objectSet", "defaultObjectSet"},
        {"hardwareRenderGlobals", "hardwareRenderGlobals"},
        {"hardwareRenderingGlobals", "hardwareRenderingGlobals"},
        {"lightLinker", "lightLinker1"},
        {"strokeGlobals", "strokeGlobals"},
        {"defaultHardwareRenderGlobals", "defaultHardwareRenderGlobals"},
        {"ikSystem", "ikSystem"},
    };
    for (auto& [type, name] : defaults) {
        NodeId id = createNode(type, name);
        m_nodes[id].shared = true;
    }
    // The unknown-type counter should only reflect what files contain.
    m_unsupportedTypes.clear();
    connect({find("lambert1"), "outColor"}, {find("initialShadingGroup"), "surfaceShader"});
    connect({find("initialShadingGroup"), "partition"}, {find("renderPartition"), "sets"}, true);
    connect({find("initialParticleSE"), "partition"}, {find("renderPartition"), "sets"}, true);
}

const Node* Graph::clashingNode(std::string_view type, std::string_view name, NodeId parent) const {
    const NodeSchema* schema = findSchema(type);
    return clashing(schema ? schema->isDag() : parent != kNoNode, name, parent, firstNamed(name));
}

NodeId Graph::childNamed(NodeId parent, std::string_view name) const {
    NodeId best = kNoNode;
    forEachSibling(parent, name, [&](uint32_t e) { best = std::min(best, NodeId(e)); });
    return best;
}

// A node outside the DAG clashes with any node of its name; a DAG node with a node outside the
// DAG, and with a DAG node at the same place: at world level, or under the same parent.
const Node* Graph::clashing(bool dag, std::string_view name, NodeId parent, NodeId any) const {
    if (any == kNoNode) return nullptr;
    if (!dag) return &m_nodes[any];
    NodeId best = kNoNode;
    forEachSibling(kNoNode, name, [&](uint32_t e) {
        const Node& o = m_nodes[e];
        if (!o.isDag() || (parent == kNoNode && o.parents().empty())) best = std::min(best, NodeId(e));
    });
    if (best == kNoNode && parent != kNoNode) best = childNamed(parent, name);
    return best == kNoNode ? nullptr : &m_nodes[best];
}

NodeId Graph::createNode(std::string_view type, std::string_view name, NodeId parent, uint32_t line) {
    const NodeSchema* schema = findSchema(type);
    const bool dag = schema ? schema->isDag() : parent != kNoNode;
    const NodeId head = firstNamed(name);
    if (const Node* other = clashing(dag, name, parent, head))
        throw Error("a node named '" + util::excerpt(name) + "' already exists (" + other->type + ")");
    if (parent != kNoNode && parent >= m_nodes.size()) throw Error("createNode: invalid parent id");
    Node n;
    n.id = NodeId(m_nodes.size());
    n.type = std::string(type);
    n.name = std::string(name);
    n.schema = schema;
    n.line = line;
    if (!schema) ++m_unsupportedTypes[n.type];
    n.underWorld = parent == kNoNode && dag;
    const NodeId id = n.id;
    m_nodes.push_back(std::move(n));
    indexName(id, head);
    if (parent != kNoNode) setParent(id, parent, true);
    return id;
}

void Graph::setParent(NodeId child, NodeId parent, bool add) {
    Node& c = m_nodes.at(child);
    // Refuse cycles: the new parent must not be the child or one of its descendants. (Clearing the
    // child's own parents first would not change that.)
    if (parent != kNoNode && isAncestorOrSelf(child, NodeId(m_nodes.at(parent).id)))
        throw Error("parenting '" + util::excerpt(c.name) + "' under '" + util::excerpt(m_nodes[parent].name) +
                    "' would make a cycle");
    if (add && parent != kNoNode && std::find(c.parents().begin(), c.parents().end(), parent) != c.parents().end())
        return;
    const bool shared = inSharedRing(c);
    if (shared) unindexSiblings(child);
    if (!add) {
        for (NodeId p : c.parents()) {
            auto& kids = m_nodes[p].mutableLinks().children;
            kids.erase(std::remove(kids.begin(), kids.end(), child), kids.end());
        }
        if (!c.parents().empty()) c.mutableLinks().parents.clear();
        c.underWorld = false;
    }
    if (parent == kNoNode) {
        c.underWorld = true;  // parent -w: a child of the world
    } else {
        c.mutableLinks().parents.push_back(parent);
        m_nodes[parent].mutableLinks().children.push_back(child);
    }
    if (shared) indexSiblings(child);
}

// Whether `ancestor` is `node` or above it in the DAG. Searches up from `node` and down from
// `ancestor` in turn, one node each, and stops when either search runs out: the cost is twice the
// smaller of the two regions, so building a deep chain (whose new nodes have no children yet)
// stays linear. Iterative, whatever the depth.
bool Graph::isAncestorOrSelf(NodeId ancestor, NodeId node) const {
    if (ancestor == node) return true;
    if (m_nodes[ancestor].children().empty() || m_nodes[node].parents().empty()) return false;
    std::vector<NodeId> up{node}, down{ancestor};
    std::unordered_set<NodeId> seenUp{node}, seenDown{ancestor};
    size_t upNext = 0, downNext = 0;
    while (upNext < up.size() && downNext < down.size()) {
        for (NodeId p : m_nodes[up[upNext++]].parents()) {
            if (p == ancestor) return true;
            if (seenUp.insert(p).second) up.push_back(p);
        }
        for (NodeId c : m_nodes[down[downNext++]].children()) {
            if (c == node) return true;
            if (seenDown.insert(c).second) down.push_back(c);
        }
    }
    return false;
}

NodeId Graph::firstNamed(std::string_view name) const {
    const uint32_t head = m_byName.find(name, [&](uint32_t id) -> std::string_view { return m_nodes[id].name; });
    return head == detail::NameIndex::kNone ? kNoNode : NodeId(head);
}

// A node joins the end of its name's ring, which keeps the ring in creation order as long as
// nodes come in by createNode; a node renamed into a name goes to its place by id, searched from
// the end (renames of recent nodes are the common case). Nodes whose name is shared also go into
// the sibling index; a name held by one node needs none.
void Graph::indexName(NodeId id, NodeId head) {
    Node& n = m_nodes[id];
    if (head == kNoNode) {
        n.nextSameName = kNoNode;
        n.prevSameName = id;
        m_byName.insert(n.name, id);
        return;
    }
    if (m_nodes[head].nextSameName == kNoNode) indexSiblings(head);  // the name becomes shared
    if (id < head) {  // the new first of the name
        n.nextSameName = head;
        n.prevSameName = m_nodes[head].prevSameName;
        m_nodes[head].prevSameName = id;
        m_byName.replace(n.name, head, id);
    } else {
        NodeId after = m_nodes[head].prevSameName;  // the last
        while (after > id) after = m_nodes[after].prevSameName;
        n.prevSameName = after;
        n.nextSameName = m_nodes[after].nextSameName;
        m_nodes[after].nextSameName = id;
        if (n.nextSameName != kNoNode) m_nodes[n.nextSameName].prevSameName = id;
        else m_nodes[head].prevSameName = id;
    }
    indexSiblings(id);
}

void Graph::unindexName(NodeId id) {
    Node& n = m_nodes[id];
    const NodeId head = firstNamed(n.name);
    if (head == kNoNode) return;
    if (!inSharedRing(n)) {
        m_byName.erase(n.name, id);
        n.nextSameName = n.prevSameName = kNoNode;
        return;
    }
    unindexSiblings(id);
    NodeId newHead = head;
    if (head == id) {
        newHead = n.nextSameName;
        m_byName.replace(n.name, id, newHead);
        m_nodes[newHead].prevSameName = n.prevSameName;  // the last
    } else {
        m_nodes[n.prevSameName].nextSameName = n.nextSameName;
        if (n.nextSameName != kNoNode) m_nodes[n.nextSameName].prevSameName = n.prevSameName;
        else m_nodes[head].prevSameName = n.prevSameName;
    }
    n.nextSameName = n.prevSameName = kNoNode;
    if (m_nodes[newHead].nextSameName == kNoNode) unindexSiblings(newHead);  // no longer shared
}

bool Graph::inSharedRing(const Node& n) const { return n.nextSameName != kNoNode || n.prevSameName != n.id; }

// ---- siblings by name

bool Graph::atWorldKey(const Node& n) const {
    return n.parents().empty() || n.underWorld || (n.schema && !n.schema->isDag());
}

template <class Visit>
void Graph::forEachSibling(NodeId parent, std::string_view name, Visit&& visit) const {
    const NodeId head = firstNamed(name);
    if (head == kNoNode) return;
    auto matches = [&](uint32_t e) {
        const Node& o = m_nodes[e];
        if (o.name != name) return false;
        if (parent == kNoNode) return atWorldKey(o);
        const auto& ps = o.parents();
        return std::find(ps.begin(), ps.end(), parent) != ps.end();
    };
    if (m_nodes[head].nextSameName == kNoNode) {  // the name's only node, not in the sibling index
        if (matches(head)) visit(head);
        return;
    }
    m_bySibling.forEach(util::hashIdAndBytes(parent, name), matches, visit);
}

// Under a 32-bit hash collision between two keys of one node, erasing by entry could take the
// other key's slot; lookups check every match against the node itself, so that costs at most a
// missed clash, once in four billion.
void Graph::indexSiblings(NodeId id) {
    const Node& n = m_nodes[id];
    if (atWorldKey(n)) m_bySibling.insert(util::hashIdAndBytes(kNoNode, n.name), id);
    for (NodeId p : n.parents()) m_bySibling.insert(util::hashIdAndBytes(p, n.name), id);
}

void Graph::unindexSiblings(NodeId id) {
    const Node& n = m_nodes[id];
    auto isId = [&](uint32_t e) { return e == id; };
    if (atWorldKey(n)) m_bySibling.erase(util::hashIdAndBytes(kNoNode, n.name), isId);
    for (NodeId p : n.parents()) m_bySibling.erase(util::hashIdAndBytes(p, n.name), isId);
}

void Graph::rename(NodeId id, std::string_view newName) {
    m_nodes.at(id);
    unindexName(id);
    m_nodes[id].name = std::string(newName);
    indexName(id, firstNamed(newName));
}

std::string Graph::canonicalPath(NodeId nodeId, const std::vector<PlugSegment>& segments) const {
    const Node& n = m_nodes.at(nodeId);
    if (segments.size() == 1 && !segments[0].indexed()) {
        const AttrSpec* spec = n.findAttr(segments[0].name);
        return std::string(plainKey(spec, segments[0].name));
    }
    std::vector<PlugSegment> out = segments;
    for (PlugSegment& s : out)
        if (const AttrSpec* spec = n.findAttr(s.name)) s.name = spec->longName;
    return formatPlugPath(out);
}

AttrData& Graph::attrData(NodeId node, const std::string& key) { return m_nodes.at(node).attrs[key]; }

void Graph::noteUnsupportedAttribute(const Node& n, std::string_view attrName) {
    ++m_unsupportedAttrs[n.type + "." + std::string(attrName)];
}

void Graph::setValue(NodeId nodeId, const std::vector<PlugSegment>& segs, Value value) {
    if (segs.empty()) throw Error("setValue: empty attribute path");
    Node& n = m_nodes.at(nodeId);
    if (n.schema && !n.findAttr(segs.front().name)) noteUnsupportedAttribute(n, segs.front().name);
    const PlugSegment& last = segs.back();
    const AttrSpec* spec = n.findAttr(last.name);

    if (last.indexed()) {
        std::vector<PlugSegment> keySegs = segs;
        keySegs.back().first = keySegs.back().last = -1;
        AttrData& a = n.attrs[canonicalPath(nodeId, keySegs)];
        const uint32_t count = uint32_t(last.last - last.first + 1);
        if (auto* nums = std::get_if<Numbers>(&value); nums && spec) {
            const AttrType t = spec->type;
            compactNumbers(*nums, count, t == AttrType::Float || t == AttrType::Float2 || t == AttrType::Float3,
                           t == AttrType::Int || t == AttrType::Enum || t == AttrType::Bool || t == AttrType::Long2 ||
                               t == AttrType::Long3 || t == AttrType::Short2 || t == AttrType::Short3);
        }
        a.multi.assign(uint32_t(last.first), count, std::move(value));
        return;
    }

    // A component of a numeric compound (translateX, colorR, pnts[3].pntx) updates its parent's value.
    const AttrSpec* parentSpec = spec && spec->component >= 0 ? n.findAttr(spec->parent) : nullptr;
    auto* nums = std::get_if<Numbers>(&value);
    if (parentSpec && isNumericCompound(parentSpec->type) && nums && nums->values.size() == 1) {
        double v = nums->values[0];
        int width = componentCount(parentSpec->type);
        if (segs.size() >= 2 && segs[segs.size() - 2].indexed() &&
            n.findAttr(segs[segs.size() - 2].name) == parentSpec) {
            std::vector<PlugSegment> keySegs(segs.begin(), segs.end() - 1);
            uint32_t index = uint32_t(keySegs.back().first);
            keySegs.back().first = keySegs.back().last = -1;
            AttrData& a = n.attrs[canonicalPath(nodeId, keySegs)];
            std::vector<double> el;
            if (!a.multi.numbers(index, el) || el.size() != size_t(width)) el = defaultNumbers(*parentSpec);
            el.resize(size_t(width), 0.0);
            el[size_t(spec->component)] = v;
            a.multi.assign(index, 1, Numbers{Numbers::Kind::Tuple, width, std::move(el)});
            return;
        }
        std::vector<PlugSegment> keySegs(segs.begin(), segs.end() - 1);
        keySegs.push_back(PlugSegment{parentSpec->longName});
        AttrData& a = n.attrs[canonicalPath(nodeId, keySegs)];
        std::vector<double> el;
        if (auto* curNums = a.hasValue ? std::get_if<Numbers>(&a.value) : nullptr) el = curNums->values;
        if (el.size() != size_t(width)) el = defaultNumbers(*parentSpec);
        el.resize(size_t(width), 0.0);
        el[size_t(spec->component)] = v;
        a.value = Numbers{Numbers::Kind::Tuple, width, std::move(el)};
        a.hasValue = true;
        return;
    }
    AttrData& a = n.attrs[canonicalPath(nodeId, segs)];
    a.value = std::move(value);
    a.hasValue = true;
}

Plug Graph::canonicalPlug(const Plug& p) const {
    if (isPlainPlugName(p.path)) {
        const AttrSpec* spec = m_nodes.at(p.node).findAttr(p.path);
        return Plug{p.node, std::string(plainKey(spec, p.path))};
    }
    auto segs = parsePlugPath(p.path);
    if (!segs) throw Error("malformed plug '" + util::excerpt(p.path) + "'");
    return Plug{p.node, canonicalPath(p.node, *segs)};
}

size_t Graph::connect(Plug src, Plug dst, bool nextAvailable) {
    if (src.node >= m_nodes.size() || dst.node >= m_nodes.size()) throw Error("connect: invalid node id");
    src = canonicalPlug(src);
    dst = canonicalPlug(dst);
    if (nextAvailable && dst.path.back() != ']') {  // a canonical path ends in ']' when it is indexed
        // Next free logical index of the destination multi: after every connected or set element.
        const std::string prefix = dst.path + "[";
        int64_t next = 0;
        for (size_t ci : m_nodes[dst.node].inConnections()) {
            const Connection& c = m_connections[ci];
            if (!c.alive || c.dst.path.compare(0, prefix.size(), prefix) != 0) continue;
            int64_t idx = 0;
            std::string_view rest(c.dst.path);
            rest.remove_prefix(prefix.size());
            size_t close = rest.find(']');
            if (close != std::string_view::npos && parseIndex(rest.substr(0, close), idx)) next = std::max(next, idx + 1);
        }
        if (const AttrData* a = findAttr(dst.node, dst.path)) next = std::max<int64_t>(next, a->multi.endIndex());
        dst.path += "[" + std::to_string(next) + "]";
    }
    // A destination plug has one source: a new connection replaces the old one (connectAttr -f).
    for (size_t ci : m_nodes[dst.node].inConnections()) {
        Connection& c = m_connections[ci];
        if (c.alive && c.dst.path == dst.path) c.alive = false;
    }
    size_t index = m_connections.size();
    m_connections.push_back(Connection{src, dst, true});
    m_nodes[src.node].mutableLinks().outConnections.push_back(index);
    m_nodes[dst.node].mutableLinks().inConnections.push_back(index);
    return index;
}

bool Graph::disconnect(const Plug& srcIn, const Plug& dstIn) {
    Plug src = canonicalPlug(srcIn), dst = canonicalPlug(dstIn);
    for (size_t ci : m_nodes.at(dst.node).inConnections()) {
        Connection& c = m_connections[ci];
        if (c.alive && c.dst == dst && c.src == src) {
            c.alive = false;
            return true;
        }
    }
    return false;
}

void Graph::warn(Diagnostic d) { m_warnings.push_back(std::move(d)); }

NodeId Graph::find(std::string_view text) const {
    if (!text.empty() && text.front() == ':') text.remove_prefix(1);
    if (text.empty()) return kNoNode;
    // A plain name, the common case: the first created node of that name, which heads its ring.
    if (text.find('|') == std::string_view::npos) return firstNamed(text);
    bool absolute = text.front() == '|';
    std::vector<std::string_view> parts;
    size_t start = absolute ? 1 : 0;
    while (start <= text.size()) {
        size_t bar = text.find('|', start);
        if (bar == std::string_view::npos) bar = text.size();
        std::string_view part = text.substr(start, bar - start);
        if (!part.empty() && part.front() == ':') part.remove_prefix(1);
        if (part.empty()) return kNoNode;
        parts.push_back(part);
        start = bar + 1;
    }
    const NodeId named = firstNamed(parts.back());
    auto rootOk = [&](NodeId id) { return !absolute || m_nodes[id].underWorld || m_nodes[id].parents().empty(); };
    NodeId best = kNoNode;
    if (parts.size() == 1) {  // "|name": the first of the name at world level
        forEachSibling(kNoNode, parts[0], [&](uint32_t e) {
            if (rootOk(NodeId(e))) best = std::min(best, NodeId(e));
        });
        return best;
    }
    // A path "a|b|c" is resolved from whichever end has fewer nodes of its name: an absolute path
    // from the world, whose names are nearly unique; a relative one from the shorter of the rings
    // of `a` and `c` (walked side by side, so measuring costs twice the shorter).
    bool fromTop = absolute;
    if (!fromTop) {
        NodeId top = firstNamed(parts.front()), bottom = named;
        while (top != kNoNode && bottom != kNoNode) {
            top = m_nodes[top].nextSameName;
            bottom = m_nodes[bottom].nextSameName;
        }
        fromTop = top == kNoNode;
    }
    if (fromTop) {
        // Top down: the nodes matching the path so far, one level at a time, each level a set.
        std::vector<NodeId> level, next;
        if (absolute) {
            forEachSibling(kNoNode, parts[0], [&](uint32_t e) {
                if (rootOk(NodeId(e))) level.push_back(NodeId(e));
            });
        } else {
            for (NodeId at = firstNamed(parts[0]); at != kNoNode; at = m_nodes[at].nextSameName) level.push_back(at);
        }
        for (size_t k = 1; k < parts.size() && !level.empty(); ++k) {
            next.clear();
            for (NodeId p : level) forEachSibling(p, parts[k], [&](uint32_t e) { next.push_back(NodeId(e)); });
            std::sort(next.begin(), next.end());
            next.erase(std::unique(next.begin(), next.end()), next.end());
            level.swap(next);
        }
        return level.empty() ? kNoNode : level.front();
    }
    // Bottom up, from a path "a|b|c": first the nodes named b that are parents of a candidate c, then the nodes named
    // a above those (reach[k] holds the level-k nodes), then down again keeping the nodes with a
    // matching parent on the level above. Each level is a set, so the cost is linear in the nodes
    // the path can touch, not in the number of ways to walk it (a diamond-shaped DAG has 2^depth).
    std::vector<std::vector<NodeId>> reach(parts.size());
    for (NodeId at = named; at != kNoNode; at = m_nodes[at].nextSameName) reach.back().push_back(at);
    for (size_t k = parts.size() - 1; k-- > 0;) {
        for (NodeId id : reach[k + 1])
            for (NodeId p : m_nodes[id].parents())
                if (m_nodes[p].name == parts[k]) reach[k].push_back(p);
        std::sort(reach[k].begin(), reach[k].end());
        reach[k].erase(std::unique(reach[k].begin(), reach[k].end()), reach[k].end());
        if (reach[k].empty()) return kNoNode;
    }
    std::unordered_set<NodeId> above;
    for (NodeId id : reach[0])
        if (rootOk(id)) above.insert(id);
    for (size_t k = 1; k < parts.size() && !above.empty(); ++k) {
        std::unordered_set<NodeId> level;
        for (NodeId id : reach[k])
            for (NodeId p : m_nodes[id].parents())
                if (above.count(p)) {
                    level.insert(id);
                    break;
                }
        above.swap(level);
    }
    for (NodeId id : above) best = std::min(best, id);
    return best;
}

std::vector<NodeId> Graph::nodesOfType(std::string_view type, bool derived) const {
    std::vector<NodeId> out;
    // A modelled type is matched by schema pointer, without comparing each node's type name.
    if (const NodeSchema* schema = findSchema(type)) {
        for (const Node& n : m_nodes)
            if (n.schema == schema || (derived && n.schema && n.schema->isA(schema))) out.push_back(n.id);
        return out;
    }
    for (const Node& n : m_nodes)
        if (n.type == type) out.push_back(n.id);
    return out;
}

std::vector<std::vector<NodeId>> Graph::dagPaths(NodeId id, DagPathBudget* budget) const {
    DagPathBudget local;
    DagPathBudget& b = budget ? *budget : local;
    std::vector<std::vector<NodeId>> out;
    if (m_nodes.at(id).parents().empty()) {
        // The common case, a node at world level: one path of one node.
        if (b.paths + 1 > b.maxPaths || b.pathNodes + 1 > b.maxPathNodes) {
            b.exhausted = true;
            return out;
        }
        ++b.paths;
        ++b.pathNodes;
        out.push_back({id});
        return out;
    }
    // Depth-first walk up the parents with an explicit stack. At a node the choices, in order, are:
    // stop here (at world level: always for a root, first for an instance also under the world),
    // then each parent. The stack read top to bottom is the path, root first.
    struct Step {
        NodeId node;
        uint32_t next;
    };
    std::vector<Step> stack{{id, 0}};
    while (!stack.empty()) {
        Step& s = stack.back();
        const Node& n = m_nodes[s.node];
        const size_t stopChoices = n.parents().empty() || n.underWorld ? 1 : 0;
        if (s.next >= stopChoices + n.parents().size()) {
            stack.pop_back();
            continue;
        }
        const uint32_t choice = s.next++;
        if (choice < stopChoices) {
            if (b.paths + 1 > b.maxPaths || b.pathNodes + stack.size() > b.maxPathNodes) {
                b.exhausted = true;
                return out;
            }
            ++b.paths;
            b.pathNodes += stack.size();
            std::vector<NodeId>& path = out.emplace_back();
            path.reserve(stack.size());
            for (size_t k = stack.size(); k-- > 0;) path.push_back(stack[k].node);
            continue;
        }
        // setParent refuses cycles, so the stack never exceeds the node count; the check keeps a
        // corrupted graph from looping forever.
        if (stack.size() > m_nodes.size()) throw Error("DAG cycle through '" + util::excerpt(n.name) + "'");
        stack.push_back({n.parents()[choice - stopChoices], 0});
    }
    return out;
}

std::string dagPathBudgetMessage(const Graph& graph, NodeId node, const DagPathBudget& budget) {
    return "'" + util::excerpt(graph.node(node).name) + "': DAG instance paths not all listed: more than " +
           std::to_string(budget.maxPaths) + " paths or " + std::to_string(budget.maxPathNodes) +
           " path nodes in all (a deeply instanced DAG); the remaining instances are skipped";
}

std::vector<NodeId> Graph::firstDagPath(NodeId id) const {
    std::vector<NodeId> path{id};
    for (NodeId at = id; !m_nodes.at(at).parents().empty() && !m_nodes[at].underWorld;) {
        at = m_nodes[at].parents().front();
        path.push_back(at);
        if (path.size() > m_nodes.size()) throw Error("DAG cycle through '" + util::excerpt(m_nodes[id].name) + "'");
    }
    std::reverse(path.begin(), path.end());
    return path;
}

std::string Graph::dagPathName(const std::vector<NodeId>& path) const {
    std::string s;
    for (NodeId id : path) s += "|" + m_nodes.at(id).name;
    return s;
}

// ------------------------------------------------------------------ values

const AttrData* Graph::findAttr(NodeId node, std::string_view key) const {
    const auto& attrs = m_nodes.at(node).attrs;
    auto it = attrs.find(key);
    return it == attrs.end() ? nullptr : &it->second;
}

const Value* Graph::value(NodeId node, std::string_view plugPath) const {
    if (isPlainPlugName(plugPath)) {
        const AttrSpec* spec = m_nodes.at(node).findAttr(plugPath);
        const AttrData* a = findAttr(node, plainKey(spec, plugPath));
        return a && a->hasValue ? &a->value : nullptr;
    }
    auto segs = parsePlugPath(plugPath);
    if (!segs) return nullptr;
    const PlugSegment last = segs->back();
    if (last.indexed()) {
        segs->back().first = segs->back().last = -1;
        const AttrData* a = findAttr(node, canonicalPath(node, *segs));
        if (!a) return nullptr;
        const MultiStore::Run* run = a->multi.find(uint32_t(last.first), nullptr);
        return run ? &run->value : nullptr;
    }
    const AttrData* a = findAttr(node, canonicalPath(node, *segs));
    return a && a->hasValue ? &a->value : nullptr;
}

bool Graph::numbers(NodeId nodeId, std::string_view plugPath, std::vector<double>& out) const {
    out.clear();
    if (isPlainPlugName(plugPath)) {
        // One attribute name, the usual question ("translate", "visibility"): no path to parse.
        // Components of numeric compounds (translateX) take the general way below.
        const Node& n = m_nodes.at(nodeId);
        const AttrSpec* spec = n.findAttr(plugPath);
        if (!spec || spec->component < 0) return storedOrDefault(findAttr(nodeId, plainKey(spec, plugPath)), spec, out);
    }
    auto segs = parsePlugPath(plugPath);
    if (!segs) return false;
    const Node& n = m_nodes.at(nodeId);
    const PlugSegment last = segs->back();
    const AttrSpec* spec = n.findAttr(last.name);

    if (last.indexed()) {
        std::vector<PlugSegment> keySegs = *segs;
        keySegs.back().first = keySegs.back().last = -1;
        if (const AttrData* a = findAttr(nodeId, canonicalPath(nodeId, keySegs))) {
            if (a->multi.numbers(uint32_t(last.first), out)) return true;
        }
        return storedOrDefault(nullptr, spec, out);  // the element's default
    }

    const AttrSpec* parentSpec = spec && spec->component >= 0 ? n.findAttr(spec->parent) : nullptr;
    if (parentSpec && isNumericCompound(parentSpec->type)) {
        std::vector<PlugSegment> parentSegs(segs->begin(), segs->end() - 1);
        if (!(parentSegs.size() && parentSegs.back().indexed() && n.findAttr(parentSegs.back().name) == parentSpec))
            parentSegs.push_back(PlugSegment{parentSpec->longName});
        std::vector<double> whole;
        // An explicitly stored child value wins (unknown layouts, addAttr children).
        if (const AttrData* a = findAttr(nodeId, canonicalPath(nodeId, *segs)); a && a->hasValue)
            if (auto* nums = std::get_if<Numbers>(&a->value); nums && !nums->values.empty()) {
                out.push_back(nums->values[0]);
                return true;
            }
        if (numbers(nodeId, formatPlugPath(parentSegs), whole) && size_t(spec->component) < whole.size()) {
            out.push_back(whole[size_t(spec->component)]);
            return true;
        }
    }
    return storedOrDefault(findAttr(nodeId, canonicalPath(nodeId, *segs)), spec, out);
}

bool Graph::numbers(NodeId node, const AttrSpec& spec, std::vector<double>& out) const {
    out.clear();
    return storedOrDefault(findAttr(node, spec.longName), &spec, out);
}

double Graph::getDouble(NodeId node, std::string_view plugPath, double fallback) const {
    std::vector<double> v;
    return numbers(node, plugPath, v) && !v.empty() ? v[0] : fallback;
}

bool Graph::getBool(NodeId node, std::string_view plugPath, bool fallback) const {
    std::vector<double> v;
    return numbers(node, plugPath, v) && !v.empty() ? v[0] != 0.0 : fallback;
}

int Graph::getInt(NodeId node, std::string_view plugPath, int fallback) const {
    std::vector<double> v;
    return numbers(node, plugPath, v) && !v.empty() ? int(v[0]) : fallback;
}

std::string Graph::getString(NodeId node, std::string_view plugPath, std::string_view fallback) const {
    if (const Value* v = value(node, plugPath))
        if (auto* s = std::get_if<StringValue>(v)) return s->text;
    return std::string(fallback);
}

std::optional<Plug> Graph::source(NodeId node, std::string_view plugPath) const {
    if (m_nodes.at(node).inConnections().empty()) return std::nullopt;
    auto segs = parsePlugPath(plugPath);
    if (!segs) return std::nullopt;
    std::string path = canonicalPath(node, *segs);
    for (size_t ci : m_nodes.at(node).inConnections()) {
        const Connection& c = m_connections[ci];
        if (c.alive && c.dst.path == path) return c.src;
    }
    return std::nullopt;
}

const Plug* Graph::sourceOfCanonical(NodeId node, std::string_view path) const {
    for (size_t ci : m_nodes.at(node).inConnections()) {
        const Connection& c = m_connections[ci];
        if (c.alive && c.dst.path == path) return &c.src;
    }
    return nullptr;
}

std::vector<const Connection*> Graph::inputs(NodeId node) const {
    std::vector<const Connection*> out;
    for (size_t ci : m_nodes.at(node).inConnections())
        if (m_connections[ci].alive) out.push_back(&m_connections[ci]);
    return out;
}

std::vector<const Connection*> Graph::outputs(NodeId node) const {
    std::vector<const Connection*> out;
    for (size_t ci : m_nodes.at(node).outConnections())
        if (m_connections[ci].alive) out.push_back(&m_connections[ci]);
    return out;
}

namespace {

uint64_t stringsBytes(const std::vector<std::string>& items) {
    uint64_t bytes = uint64_t(items.capacity()) * sizeof(std::string);
    for (const std::string& t : items) bytes += t.capacity() > 15 ? t.capacity() + 1 : 0;
    return bytes;
}

}  // namespace

uint64_t Graph::storedBytes() const {
    std::unordered_set<const void*> shared;
    auto valueBytes = [&](const Value& v) -> uint64_t {
        return std::visit(
            [&](const auto& x) -> uint64_t {
                using T = std::decay_t<decltype(x)>;
                if constexpr (std::is_same_v<T, Numbers>) {
                    return uint64_t(x.heapBytes());
                } else if constexpr (std::is_same_v<T, StringValue>) {
                    return x.text.capacity() > 15 ? x.text.capacity() + 1 : 0;
                } else if constexpr (std::is_same_v<T, StringArray> || std::is_same_v<T, ComponentList>) {
                    return stringsBytes(x.items);
                } else if constexpr (std::is_same_v<T, RawData>) {
                    return stringsBytes(x.tokens);
                } else if constexpr (std::is_same_v<T, std::shared_ptr<const PolyFaces>>) {
                    return x && shared.insert(x.get()).second ? x->heapBytes() : 0;
                } else if constexpr (std::is_same_v<T, std::shared_ptr<const NurbsCurveData>>) {
                    return x && shared.insert(x.get()).second
                               ? uint64_t(x->knots.capacity() + x->cvs.capacity()) * sizeof(double)
                               : 0;
                } else if constexpr (std::is_same_v<T, std::shared_ptr<const NurbsSurfaceData>>) {
                    return x && shared.insert(x.get()).second
                               ? uint64_t(x->knotsU.capacity() + x->knotsV.capacity() + x->cvs.capacity()) * sizeof(double)
                               : 0;
                } else {
                    return 0;
                }
            },
            v);
    };
    uint64_t bytes = 0;
    for (const Node& node : m_nodes) {
        for (const auto& [path, data] : node.attrs) {
            if (data.hasValue) bytes += valueBytes(data.value);
            for (const auto& [first, run] : data.multi.runs()) bytes += valueBytes(run.value);
        }
    }
    return bytes;
}

}  // namespace pushpin::scene
