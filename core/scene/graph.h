// core/scene/graph.h: the dependency graph a .ma file describes: nodes with typed attributes
// (addressed by long or short name), multi attributes with sparse indices, connections in both
// directions, DAG parenting with instancing. Static data only; animation and construction history
// are evaluated on top of it (core/scene/evaluator.h).
// Thread safety: building is single-threaded; a finished Graph may be read from many threads.
// Memory: numeric arrays are stored once as doubles in chunks as the file wrote them
// (`.vt[0:165]` is one chunk), so a 1M-vertex mesh costs its numbers and little more.
#pragma once

#include "core/scene/detail/name_index.h"
#include "core/scene/schema.h"
#include "core/scene/units.h"
#include "core/scene/value.h"
#include "core/util/index_table.h"

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace pushpin::scene {

using NodeId = uint32_t;
constexpr NodeId kNoNode = ~NodeId(0);

// One segment of an attribute path: `og[3]`, `vt[0:7]`, `t`.
struct PlugSegment {
    std::string name;
    int64_t first = -1;  // -1: no index
    int64_t last = -1;   // == first for a single index; inclusive range end
    bool indexed() const { return first >= 0; }
};
// Parses the attribute part of a plug ("iog[0].og[3].gcl", ".vt[0:7]"; a leading '.' is allowed).
// Returns nullopt on a syntax error (unbalanced brackets, negative or reversed ranges, empty names).
std::optional<std::vector<PlugSegment>> parsePlugPath(std::string_view text);
std::string formatPlugPath(const std::vector<PlugSegment>& segments);
// Whether a plug path is one attribute name, without a '.' or an index ("translate"): the common
// case, which needs no parsing.
bool isPlainPlugName(std::string_view text);

// Sparse storage of one multi attribute: runs of consecutive elements, each run one Value as the
// file wrote it. A later write replaces the elements it covers.
class MultiStore {
public:
    struct Run {
        uint32_t count = 0;
        int width = 1;  // numbers per element for Numbers runs
        Value value;
    };
    // Stores `count` elements starting at `first`. For Numbers, width = values.size() / count.
    void assign(uint32_t first, uint32_t count, Value value);
    // The run holding element `index` and the element's position within it; nullptr if unset.
    const Run* find(uint32_t index, uint32_t* offsetInRun) const;
    // The numbers of element `index` (its run's width of them) into `out`; false when it is unset
    // or not numeric.
    bool numbers(uint32_t index, std::vector<double>& out) const;
    std::vector<uint32_t> indices() const;  // every set element index, ascending
    uint32_t endIndex() const;              // one past the highest set index (0 when empty)
    const std::map<uint32_t, Run>& runs() const { return m_runs; }
    bool empty() const { return m_runs.empty(); }

private:
    void erase(uint32_t first, uint32_t count);
    std::map<uint32_t, Run> m_runs;  // keyed by first element index
};

// What a node holds for one attribute path (without its final index).
struct AttrData {
    Value value;             // the plain value, when set without an index
    bool hasValue = false;
    MultiStore multi;        // elements, when set with an index or range
    int64_t sizeHint = -1;   // `setAttr -s N`
    bool locked = false;     // `-l on`
    bool keyable = false;    // `-k on`
};

// What links a node to others: DAG parents and children, addAttr'ed attributes and connections.
// Many nodes have none of these, so a Node holds them behind one pointer, allocated on first use.
struct NodeLinks {
    std::vector<NodeId> parents;       // DAG parents; more than one = instanced
    std::vector<NodeId> children;
    std::vector<AttrSpec> dynamicAttrs;  // from addAttr
    std::vector<size_t> inConnections;   // indices into Graph::connections()
    std::vector<size_t> outConnections;
};

// A node's attributes by canonical path (long names, indices kept). Many nodes set none, so the
// map is allocated on the first write and a node without attributes holds one pointer.
class AttrMap {
public:
    using Map = std::map<std::string, AttrData, std::less<>>;
    using const_iterator = Map::const_iterator;

    AttrMap() = default;
    AttrMap(AttrMap&&) noexcept = default;
    AttrMap& operator=(AttrMap&&) noexcept = default;
    AttrMap(const AttrMap& other) : m_map(other.m_map ? std::make_unique<Map>(*other.m_map) : nullptr) {}
    AttrMap& operator=(const AttrMap& other) {
        if (this != &other) *this = AttrMap(other);
        return *this;
    }

    bool empty() const { return !m_map || m_map->empty(); }
    size_t size() const { return m_map ? m_map->size() : 0; }
    const_iterator begin() const { return map().begin(); }
    const_iterator end() const { return map().end(); }
    const_iterator find(std::string_view key) const { return map().find(key); }
    const_iterator lower_bound(std::string_view key) const { return map().lower_bound(key); }
    AttrData& operator[](const std::string& key) {
        if (!m_map) m_map = std::make_unique<Map>();
        return (*m_map)[key];
    }

private:
    const Map& map() const;  // an empty map while none is allocated
    std::unique_ptr<Map> m_map;
};

struct Node {
    NodeId id = kNoNode;
    uint32_t line = 0;                 // source line of the createNode (0 for implicit defaults)
    // The Graph's name index: nodes of one name form a ring in creation order, from the first
    // created; prevSameName of that first node is the last.
    NodeId nextSameName = kNoNode;
    NodeId prevSameName = kNoNode;
    const NodeSchema* schema = nullptr;  // nullptr for types pushpin does not model
    std::string type;
    std::string name;                  // unique among non-DAG nodes; DAG siblings differ
    AttrMap attrs;
    bool underWorld = false;           // also (or only) a child of the world: a DAG path starts here
    bool shared = false;               // createNode -s
    bool locked = false;               // lockNode

    Node() = default;
    Node(Node&&) noexcept = default;
    Node& operator=(Node&&) noexcept = default;
    Node(const Node& other);
    Node& operator=(const Node& other);

    const std::vector<NodeId>& parents() const { return links().parents; }
    const std::vector<NodeId>& children() const { return links().children; }
    const std::vector<AttrSpec>& dynamicAttrs() const { return links().dynamicAttrs; }
    const std::vector<size_t>& inConnections() const { return links().inConnections; }
    const std::vector<size_t>& outConnections() const { return links().outConnections; }
    NodeLinks& mutableLinks();         // allocates the links on first use

    bool isDag() const;                // transform, shape, camera, light… (schema says so)

    // Attribute spec by long or short name, including addAttr'ed ones; nullptr if unknown.
    const AttrSpec* findAttr(std::string_view name) const;

private:
    const NodeLinks& links() const;
    std::unique_ptr<NodeLinks> m_links;
};

// The nodes of a Graph, in creation order, stored in fixed-size chunks: adding a node never moves
// the others (references to nodes stay valid) and a million-node file never copies its nodes to
// grow.
class NodeStore {
public:
    static constexpr size_t kChunkBits = 12;
    static constexpr size_t kChunkSize = size_t(1) << kChunkBits;

    size_t size() const { return m_size; }
    bool empty() const { return m_size == 0; }
    const Node& operator[](size_t i) const { return m_chunks[i >> kChunkBits][i & (kChunkSize - 1)]; }
    Node& operator[](size_t i) { return m_chunks[i >> kChunkBits][i & (kChunkSize - 1)]; }
    const Node& at(size_t i) const { return i < m_size ? (*this)[i] : outOfRange(i); }
    Node& at(size_t i) { return i < m_size ? (*this)[i] : const_cast<Node&>(outOfRange(i)); }
    Node& back() { return (*this)[m_size - 1]; }
    Node& push_back(Node&& node) {
        if (m_chunks.empty() || m_chunks.back().size() == kChunkSize) m_chunks.emplace_back().reserve(kChunkSize);
        ++m_size;
        return m_chunks.back().emplace_back(std::move(node));
    }

    template <class Store, class Value>
    class Iterator {
    public:
        Iterator(Store* store, size_t i) : m_store(store), m_i(i) {}
        Value& operator*() const { return (*m_store)[m_i]; }
        Value* operator->() const { return &(*m_store)[m_i]; }
        Iterator& operator++() {
            ++m_i;
            return *this;
        }
        bool operator==(const Iterator& o) const { return m_i == o.m_i; }

    private:
        Store* m_store;
        size_t m_i;
    };
    using const_iterator = Iterator<const NodeStore, const Node>;
    const_iterator begin() const { return {this, 0}; }
    const_iterator end() const { return {this, m_size}; }

private:
    [[noreturn]] static const Node& outOfRange(size_t i);
    std::vector<std::vector<Node>> m_chunks;  // each reserved to kChunkSize, so never reallocated
    size_t m_size = 0;
};

struct Plug {
    NodeId node = kNoNode;
    std::string path;  // canonical: long names where known, indices kept ("instObjGroups[0].objectGroups[1]")
    bool operator==(const Plug&) const = default;
};

struct Connection {
    Plug src;
    Plug dst;
    bool alive = true;  // false after disconnectAttr
};

struct Relationship {
    std::string type;             // "link", "shadowLink", …
    std::vector<Plug> plugs;      // as written: the linker node first, then the linked plugs
};

struct Diagnostic {
    std::string file;
    uint32_t line = 0;
    uint32_t column = 0;
    std::string node;
    std::string message;
};

// Bounds on DAG path enumeration, shared by the calls of one pass over the scene so that the
// pass as a whole stays bounded. The defaults allow far more instances than real scenes have
// (a million paths, 16M nodes of path in total, 64 MB of NodeIds).
struct DagPathBudget {
    static constexpr uint64_t kDefaultMaxPaths = uint64_t(1) << 20;
    static constexpr uint64_t kDefaultMaxPathNodes = uint64_t(1) << 24;
    uint64_t maxPaths = kDefaultMaxPaths;
    uint64_t maxPathNodes = kDefaultMaxPathNodes;  // sum of the lengths of the paths enumerated
    uint64_t paths = 0;                            // used so far
    uint64_t pathNodes = 0;
    bool exhausted = false;                        // a call stopped early
};
class Graph;
// The one warning for a pass whose budget ran out at `node`: names the node and the limits.
std::string dagPathBudgetMessage(const Graph& graph, NodeId node, const DagPathBudget& budget);

class Graph {
public:
    Graph();

    // ---- building (used by MaReader and tests)
    // Creates a node. `parent` may be kNoNode (world). Throws pushpin::Error if a DAG node with the same
    // name already exists under the same parent, or a non-DAG node with the same name exists.
    NodeId createNode(std::string_view type, std::string_view name, NodeId parent = kNoNode, uint32_t line = 0);
    // The node that makes createNode(type, name, parent) refuse the name, or nullptr if it is free.
    const Node* clashingNode(std::string_view type, std::string_view name, NodeId parent) const;
    // Adds `parent` as another DAG parent of `child` (instancing) or, with add == false, reparents.
    void setParent(NodeId child, NodeId parent, bool add);
    void rename(NodeId node, std::string_view newName);
    // Canonical form of an attribute path on `node`: names resolved to long names where the schema or
    // addAttr knows them, indices kept. Unknown names stay as written.
    std::string canonicalPath(NodeId node, const std::vector<PlugSegment>& segments) const;
    // Stores a value. `segments` is the parsed path; a final index/range writes multi elements
    // (`count` = last − first + 1). A component child of a numeric compound (translateX) writes
    // into its parent's value, filling the other components from defaults.
    void setValue(NodeId node, const std::vector<PlugSegment>& segments, Value value);
    AttrData& attrData(NodeId node, const std::string& canonicalKey);
    // Connects two plugs (canonical paths). With nextAvailable, the destination gets the next free
    // index appended (`connectAttr -na`). Returns the connection index.
    size_t connect(Plug src, Plug dst, bool nextAvailable = false);
    // Removes the connection src → dst if present; returns whether one was removed.
    bool disconnect(const Plug& src, const Plug& dst);
    void addRelationship(Relationship r) { m_relationships.push_back(std::move(r)); }
    void warn(Diagnostic d);  // kept in warnings(), never fatal
    void noteUnsupportedAttribute(const Node& node, std::string_view attrName);

    // ---- lookup
    size_t size() const { return m_nodes.size(); }
    const Node& node(NodeId id) const { return m_nodes[id]; }
    Node& node(NodeId id) { return m_nodes[id]; }
    const NodeStore& nodes() const { return m_nodes; }
    // Heap bytes of the stored attribute values: numeric arrays, strings, component lists, and
    // polyFaces, NURBS curve and surface payloads (each shared payload once). What a memory cap
    // charges for the loaded scene; the nodes' own records and names are not counted. Linear in
    // the values; thread-safe (reads only).
    uint64_t storedBytes() const;
    // Finds a node by name or DAG path: "pCube1", "|group1|pCube1", "group1|pCube1", ":lambert1",
    // "ns:name". An ambiguous short DAG name returns the first created. kNoNode if none.
    NodeId find(std::string_view nameOrPath) const;
    // The first created node named `name` (exactly) that has `parent` among its DAG parents.
    NodeId childNamed(NodeId parent, std::string_view name) const;
    std::vector<NodeId> nodesOfType(std::string_view type, bool derived = true) const;
    // Full DAG paths of every instance of a DAG node ("|pCube1|pCubeShape1", …), in a stable order:
    // the node's own world instance first, then its parents' paths in parent order. The work is
    // bounded by `budget` (a per-call default budget when nullptr): a diamond-shaped DAG has 2^depth
    // paths, so enumeration stops at the budget and sets budget->exhausted. Linear in the length of
    // the paths returned; never recursive, whatever the depth.
    std::vector<std::vector<NodeId>> dagPaths(NodeId node, DagPathBudget* budget = nullptr) const;
    // The first of dagPaths(node) alone, in time linear in its length.
    std::vector<NodeId> firstDagPath(NodeId node) const;
    std::string dagPathName(const std::vector<NodeId>& path) const;

    // ---- attribute values (static, as stored; no animation)
    const AttrData* findAttr(NodeId node, std::string_view canonicalKey) const;
    // Numbers of a plug path ("translate", "translateX", "vrts[5]", "colorEntryList[0].position"):
    // the stored value, else the schema default for the plug's components. False if neither exists.
    bool numbers(NodeId node, std::string_view plugPath, std::vector<double>& out) const;
    // The same for a whole attribute of the node given by its spec (one the node's schema or
    // addAttr holds, not a component such as translateX): no name to look up.
    bool numbers(NodeId node, const AttrSpec& spec, std::vector<double>& out) const;
    double getDouble(NodeId node, std::string_view plugPath, double fallback = 0.0) const;
    bool getBool(NodeId node, std::string_view plugPath, bool fallback = false) const;
    int getInt(NodeId node, std::string_view plugPath, int fallback = 0) const;
    std::string getString(NodeId node, std::string_view plugPath, std::string_view fallback = {}) const;
    // The stored Value of an exact plug path (no defaults); nullptr if unset.
    const Value* value(NodeId node, std::string_view plugPath) const;

    // ---- connections
    const std::vector<Connection>& connections() const { return m_connections; }
    // The source plug feeding `node.plugPath` exactly (canonical path), if any.
    std::optional<Plug> source(NodeId node, std::string_view plugPath) const;
    // The same for a path already in canonical form (long names), without parsing it; nullptr if
    // none. The pointer stays valid until the next connect.
    const Plug* sourceOfCanonical(NodeId node, std::string_view canonicalPath) const;
    // Every live connection into / out of a node.
    std::vector<const Connection*> inputs(NodeId node) const;
    std::vector<const Connection*> outputs(NodeId node) const;

    const std::vector<Relationship>& relationships() const { return m_relationships; }
    const std::vector<Diagnostic>& warnings() const { return m_warnings; }
    // type → node count for node types without a schema; "type.attr" → count for unknown attributes.
    const std::map<std::string, int>& unsupportedTypes() const { return m_unsupportedTypes; }
    const std::map<std::string, int>& unsupportedAttributes() const { return m_unsupportedAttrs; }

    // ---- file-level facts
    Units units;
    std::string sourceFile;
    std::vector<std::pair<std::string, std::string>> fileInfo;
    std::vector<std::string> requirements;  // `requires` lines: "maya 2018", "mtoa 1.0" …
    std::vector<std::string> references;  // referenced files that were loaded

private:
    Plug canonicalPlug(const Plug& p) const;
    NodeStore m_nodes;
    // Name → the first created node of that name (DAG nodes under different parents share names);
    // Node::nextSameName links the rest in creation order.
    detail::NameIndex m_byName;
    // (parent, name) → node, for the nodes whose name another node shares: every DAG node under
    // each of its parents, and under kNoNode the nodes at world level and every node outside the
    // DAG. Name clashes and child lookups then cost one probe, however many nodes share a name.
    util::IndexTable m_bySibling;
    NodeId firstNamed(std::string_view name) const;
    // `any`: firstNamed(name), which the caller has at hand.
    const Node* clashing(bool dag, std::string_view name, NodeId parent, NodeId any) const;
    // Adds node `id` under its name; `head`: firstNamed of that name before it joins.
    void indexName(NodeId id, NodeId head);
    void unindexName(NodeId id);
    bool atWorldKey(const Node& n) const;    // indexed under kNoNode in m_bySibling
    bool inSharedRing(const Node& n) const;  // another node has its name: it is in m_bySibling
    template <class Visit>
    void forEachSibling(NodeId parent, std::string_view name, Visit&& visit) const;
    void indexSiblings(NodeId id);
    void unindexSiblings(NodeId id);
    bool isAncestorOrSelf(NodeId ancestor, NodeId node) const;
    std::vector<Connection> m_connections;
    std::vector<Relationship> m_relationships;
    std::vector<Diagnostic> m_warnings;
    std::map<std::string, int> m_unsupportedTypes;
    std::map<std::string, int> m_unsupportedAttrs;
};

}  // namespace pushpin::scene
