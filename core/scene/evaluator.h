// core/scene/evaluator.h: evaluates a scene::Graph at one frame: attribute values through their
// incoming connections (animCurves, unitConversion, pass-through plugs), transform matrices with
// Maya's full transform stack, and DAG visibility.
// Thread safety: an Evaluator caches results and is not thread-safe; use one per thread.
// Bounded work: plugs are evaluated with an explicit stack, never by recursion, so a chain of a
// million connections costs a million steps and no call stack; each plug is computed once per
// frame. World matrices of nodes with a single DAG path are cached, so asking for every node of a
// deep chain costs one pass over it.
// Matrices follow Maya's row-vector convention internally but are returned as GLM column-major
// matrices for column vectors: p_world = worldFromObject * vec4(p_object, 1).
#pragma once

#include "core/scene/graph.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <deque>
#include <string>
#include <string_view>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace pushpin::scene {

class Evaluator {
public:
    // `frame` is in the scene's time unit (Graph::units.framesPerSecond), as animCurve keys are.
    Evaluator(const Graph& graph, double frame);

    const Graph& graph() const { return m_graph; }
    double frame() const { return m_frame; }

    // Numbers of `node.plugPath` at this frame. Follows an incoming connection on the plug (or, for a
    // numeric compound, on each child component): animCurve outputs are evaluated at the frame,
    // unitConversion multiplies its input by conversionFactor, `time1.outTime` gives the frame, and
    // any other source plug is evaluated in turn as a stored/default value (cycles are broken and
    // reported once). Without a connection: the stored value, else the schema default; the outputs
    // of animCurve, unitConversion and time nodes are computed when asked for directly.
    // animCurve keys keep the file's units in the Graph and are converted to internal units here.
    // Returns false when the plug has neither a value nor a default (or the path does not parse).
    bool numbers(NodeId node, std::string_view plugPath, std::vector<double>& out);
    double getDouble(NodeId node, std::string_view plugPath, double fallback = 0.0);
    bool getBool(NodeId node, std::string_view plugPath, bool fallback = false);
    int getInt(NodeId node, std::string_view plugPath, int fallback = 0);
    glm::dvec3 getDouble3(NodeId node, std::string_view plugPath, glm::dvec3 fallback = glm::dvec3(0.0));

    // Local matrix of a transform (or joint) node: parentFromLocal (core/scene/transform.h), times a
    // stored offsetParentMatrix. Identity for nodes that are not transforms (shapes). A joint's inverse
    // scale comes from its inverseScale plug when connected or set, else from its first parent joint.
    glm::dmat4 localMatrix(NodeId transform);
    // worldFromObject of the last node of a DAG path (as returned by Graph::dagPaths), honouring
    // inheritsTransform.
    glm::dmat4 worldMatrix(const std::vector<NodeId>& dagPath);
    // True when every node on the path is visible (visibility, lodVisibility, not an intermediate
    // object, not hidden by its drawing overrides: overrideEnabled + overrideVisibility, or a display
    // layer connected to drawOverride that is enabled and hidden). An empty path is not visible.
    bool visible(const std::vector<NodeId>& dagPath);
    // Why a DAG path is not drawn, naming the first node on it that hides it ("hidden by 'x'
    // (visibility, a drawing override or a display layer)"); empty when visible(dagPath).
    std::string hiddenReason(const std::vector<NodeId>& dagPath);

    // Problems met while evaluating (connection cycles, each reported once), in the order found.
    const std::vector<Diagnostic>& diagnostics() const { return m_diagnostics; }

private:
    // A cached plug: being evaluated (on the stack; met again it is a cycle), without a value, or
    // with one (valueCount numbers at valueOffset in m_values). Plugs read straight from the Graph
    // (no connection, not a computed output) are not cached, so a deep DAG does not keep every
    // transform attribute it read.
    struct CacheEntry {
        enum class State : uint8_t { Evaluating, Missing, Ready };
        NodeId node = kNoNode;
        State state = State::Evaluating;
        uint32_t valueCount = 0;
        uint32_t nextOfNode = ~uint32_t(0);  // the node's entry cached before this one (or kNoEntry)
        size_t valueOffset = 0;
        std::string path;  // canonical
    };
    // A node's entries are found through a list from the node while it has at most this many,
    // then through the hash table.
    static constexpr uint8_t kListedEntriesPerNode = 8;
    bool hashedEntries(NodeId node) const { return m_entriesOfNode[node] > kListedEntriesPerNode; }
    // The attributes every transform's matrix and visibility read, by number: on a node nothing
    // drives, they are read through the schema's spec, found once per schema, instead of by name.
    enum class Channel : uint8_t {
        Translate, Rotate, Scale, Shear, RotateOrder, RotateAxis, RotatePivot, RotatePivotTranslate,
        ScalePivot, ScalePivotTranslate, InheritsTransform, Visibility, LodVisibility, IntermediateObject,
        Template, OverrideEnabled, OverrideVisibility, OverrideDisplayType, Count
    };
    static constexpr size_t kChannels = size_t(Channel::Count);
    static const std::array<std::string_view, kChannels> kChannelNames;
    using ChannelSpecs = std::array<const AttrSpec*, kChannels>;
    const ChannelSpecs& channelSpecs(const NodeSchema& schema);
    bool channel(NodeId node, Channel c, std::vector<double>& out);
    glm::dvec3 channel3(NodeId node, Channel c, glm::dvec3 fallback);
    bool channelBool(NodeId node, Channel c, bool fallback);
    int channelInt(NodeId node, Channel c, int fallback);

    static constexpr uint32_t kNoEntry = util::IndexTable::kNone;
    uint32_t findEntry(NodeId node, std::string_view path) const;  // kNoEntry if not cached
    uint32_t addEntry(NodeId node, std::string path);              // a new entry, Evaluating
    void readEntry(const CacheEntry& e, std::vector<double>& out) const;
    // Whether `node` computes outputs of its own (animCurve, unitConversion, time); per node, once.
    bool computesOutputs(NodeId node);
    bool holdsStoredValues(NodeId node);  // no connection in and no output of its own

    bool evaluatePlug(NodeId node, const std::string& canonicalPath, std::vector<double>& out);
    // The plugs whose values `node.path` is computed from: every plug computePlug may read (more
    // is harmless; they are evaluated first, each once).
    std::vector<Plug> dependencies(NodeId node, const std::string& path) const;
    bool needsCache(NodeId node, const std::string& path) const;
    bool isCachedOutput(NodeId node, std::string_view path) const;
    // The value of `node.path` from its dependencies' values, which are already evaluated.
    bool computePlug(NodeId node, const std::string& path, std::vector<double>& out);
    void reportCycle(NodeId node, const std::string& path);
    bool computeOutput(NodeId node, const std::string& canonicalPath, std::vector<double>& out);
    double evaluateAnimCurve(NodeId curve);
    glm::dmat4 localMatrixUnder(NodeId transform, NodeId dagParent);
    bool nodeVisible(NodeId node);
    bool nodeVisibleUncached(NodeId node);
    bool hasSinglePath(NodeId node);

    const Graph& m_graph;
    double m_frame;
    // Values at this frame: entries by (node, path) through a short list per node (an index table
    // for nodes with many), their numbers side by side in one array. A deque, so that a path being
    // computed stays put while entries are added.
    std::deque<CacheEntry> m_entries;
    std::vector<uint32_t> m_firstEntry;    // per node: its latest entry, kNoEntry if none
    // Per node: its entries, counted up to one past kListedEntriesPerNode, when they are all in
    // m_entryIndex.
    std::vector<uint8_t> m_entriesOfNode;
    util::IndexTable m_entryIndex;
    std::vector<double> m_values;
    std::vector<uint8_t> m_computesOutputs;            // per node: 0 unknown, 1 yes, 2 no
    std::unordered_set<std::string> m_reportedCycles;
    std::vector<uint8_t> m_nodeVisible;                 // per node: 0 unknown, 1 visible, 2 hidden
    std::vector<uint8_t> m_singlePath;                  // per node: 0 unknown, 1 one DAG path, 2 more
    std::unordered_map<NodeId, glm::dmat4> m_worldOfSinglePath;  // world matrix of single-path nodes
    std::vector<Diagnostic> m_diagnostics;
    // Where the get* and channel* reads receive numbers (numbers() never calls them
    // back, so one buffer serves them all without an allocation per read).
    std::vector<double> m_scratch;
    std::unordered_map<const NodeSchema*, ChannelSpecs> m_channelSpecs;
    const NodeSchema* m_lastChannelSchema = nullptr;  // the schema of the last channelSpecs() call
    const ChannelSpecs* m_lastChannelSpecs = nullptr;
};

}  // namespace pushpin::scene
