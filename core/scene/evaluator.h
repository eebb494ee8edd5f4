// core/scene/evaluator.h: evaluates a scene::Graph at one frame: attribute values through their
// incoming connections (animCurves, unitConversion, pass-through plugs), transform matrices with
// Maya's full transform stack, and DAG visibility.
// Thread safety: an Evaluator caches results and is not thread-safe; use one per thread.
// Matrices follow Maya's row-vector convention internally but are returned as GLM column-major
// matrices for column vectors: p_world = worldFromObject * vec4(p_object, 1).
#pragma once

#include "core/scene/graph.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <string>
#include <string_view>
#include <unordered_map>
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
    // any other source plug is evaluated recursively as a stored/default value (cycles are broken and
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
    bool evaluatePlug(NodeId node, const std::string& canonicalPath, std::vector<double>& out);
    bool evaluateSource(const Plug& source, std::vector<double>& out);
    bool computeOutput(NodeId node, const std::string& canonicalPath, std::vector<double>& out);
    double evaluateAnimCurve(NodeId curve);
    glm::dmat4 localMatrixUnder(NodeId transform, NodeId dagParent);

    const Graph& m_graph;
    double m_frame;
    std::unordered_map<std::string, std::vector<double>> m_cache;  // "node#plug" → value at frame
    std::vector<std::string> m_evaluating;                          // cycle guard
    std::vector<Diagnostic> m_diagnostics;
};

}  // namespace pushpin::scene
