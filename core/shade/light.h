// core/shade/light.h: Maya's lights as the renderer sees them at one frame (reference/nodes.md §3):
// ambientLight (ambientShade), directionalLight, pointLight and spotLight (coneAngle, penumbraAngle,
// dropoff), with colour, intensity, decayRate, emitDiffuse/emitSpecular, and Maya's default light.
// illuminate() computes, for every sample of a batch, the direction toward the light and the
// intensity arriving there, as Maya's lightDataArray holds them.
// Thread safety: Light is plain data; illuminate() is pure.
#pragma once

#include "core/shade/shading_batch.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <string>

namespace pushpin::shade {

enum class LightType : unsigned char { Ambient, Directional, Point, Spot };

struct Light {
    LightType type = LightType::Directional;
    std::string name;            // DAG path of the light instance, for messages
    uint32_t shape = ~0u;        // scene::NodeId of the light shape (~0u for the default light)
    glm::vec3 color{1.0f};       // color × intensity
    // Where the light is and where it points (its local −Z), in the space the batch uses.
    glm::dvec3 position{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};  // unit
    int decayRate = 0;           // 0 none, 1 linear, 2 quadratic, 3 cubic
    float coneAngle = 0.698132f; // radians, full spread (40°)
    float penumbraAngle = 0.0f;  // radians, added on each side (negative: inside the cone)
    float dropoff = 0.0f;
    float ambientShade = 0.45f;
    bool emitDiffuse = true;
    bool emitSpecular = true;
};

// Light data at each sample of a batch for one light.
struct LightSamples {
    float lx[kBatchSize], ly[kBatchSize], lz[kBatchSize];  // unit direction from the point toward the light
    float ir[kBatchSize], ig[kBatchSize], ib[kBatchSize];  // intensity arriving (colour, decay, cone, shade)
    bool ambient = false;   // contributes to the ambient term (ambientLight)
    bool diffuse = false;   // emitDiffuse
    bool specular = false;  // emitSpecular
};

// Fills `out` for the batch's `count` samples. Falloff formulas (reference/nodes.md §3):
// - decay: intensity / max(d, 1)^decayRate, d the distance to the light (point, spot);
// - spot: cos(angle)^dropoff, times the penumbra ramp falling linearly to 0 between the half-angles
//   coneAngle/2 and coneAngle/2 + penumbraAngle (or coneAngle/2 + penumbraAngle and coneAngle/2
//   when the penumbra is negative); 0 outside;
// - ambient: I · ((1 − ambientShade) + ambientShade · max(0, N·L)), L toward the light's position.
void illuminate(const Light& light, const ShadingBatch& batch, LightSamples& out);

// The same light with its position and direction carried by `m` (e.g. cameraFromWorld).
Light transformed(const Light& light, const glm::dmat4& m);

// Maya's default light, used when a scene has no light and enableDefaultLight is on: a directional
// light of intensity 1 shining along the camera's view direction (`viewDirection` in the space
// the batch uses, unit).
Light defaultLight(const glm::dvec3& viewDirection);

}  // namespace pushpin::shade
