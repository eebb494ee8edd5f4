// core/scene/render_setup.h: what a render needs to know from a Graph before any geometry is
// built: cameras, lights, shading groups with their members (whole objects and face components),
// light links, and the render globals in effect (Maya's defaults where the file is silent).
// Pure reads of a finished Graph; thread-safe for concurrent calls.
#pragma once

#include "core/scene/graph.h"

#include <string>
#include <vector>

namespace pushpin::scene {

struct CameraInfo {
    NodeId shape = kNoNode;
    std::vector<NodeId> path;  // DAG path of this instance
    std::string name;          // the shape's name
    std::string transformName; // the parent transform's name ("persp" for "perspShape")
    bool renderable = true;
    bool orthographic = false;
};

struct LightInfo {
    NodeId shape = kNoNode;
    std::vector<NodeId> path;
    std::string name;
    std::string type;
    bool supported = true;  // false for plug-in light types pushpin does not model (aiSkyDomeLight …)
};

// One member of a shading group: a shape instance, whole or a subset of its components.
struct SetMember {
    NodeId shape = kNoNode;
    int instance = 0;            // instObjGroups index
    int objectGroup = -1;        // objectGroups index, -1 = the whole object
    std::vector<std::string> components;  // "f[0:3]" … from objectGrpCompList (empty = whole object)
};

struct ShadingGroupInfo {
    NodeId node = kNoNode;
    std::string name;
    NodeId surfaceShader = kNoNode;  // node wired to surfaceShader (ss)
    NodeId volumeShader = kNoNode;
    NodeId displacementShader = kNoNode;
    std::vector<SetMember> members;
    // Wired into renderPartition.sets (partition → sets): only such groups render, as in Maya.
    bool inRenderPartition = false;
};

// A light linked to (or, for shadowLink, casting shadows onto) an object, a set or a shading group.
struct LightLink {
    std::string kind;        // "link", "shadowLink", "ignore", "shadowIgnore"
    NodeId light = kNoNode;  // a light shape/transform or a set of lights (defaultLightSet)
    NodeId object = kNoNode; // a shape/transform, a set or a shading group
};

struct RenderSetup {
    std::vector<CameraInfo> cameras;
    std::vector<LightInfo> lights;
    std::vector<ShadingGroupInfo> shadingGroups;
    std::vector<LightLink> lightLinks;
    NodeId renderGlobals = kNoNode;   // :defaultRenderGlobals
    NodeId renderQuality = kNoNode;   // :defaultRenderQuality
    NodeId resolution = kNoNode;      // :defaultResolution
    std::vector<std::string> notes;   // problems met while extracting (instance paths cut short)
};

RenderSetup extractRenderSetup(const Graph& graph);

// The shading groups a shape instance belongs to (whole-object or component membership), in the
// order the sets appear in the scene.
std::vector<const ShadingGroupInfo*> shadingGroupsOf(const RenderSetup& setup, NodeId shape, int instance);

}  // namespace pushpin::scene
